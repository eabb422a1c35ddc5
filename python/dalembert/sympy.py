"""A `dalembert.Scene` from a model written with sympy (optional dependency `sympy`).

    import sympy as sp
    from sympy.physics.mechanics import dynamicsymbols  # type: ignore[import-untyped]
    from dalembert.sympy import scene_from_lagrangian

    x, y, th = dynamicsymbols("x y theta")
    t = dynamicsymbols._t
    m, J = sp.symbols("m J")
    xd, yd, thd = (c.diff(t) for c in (x, y, th))
    L = m / 2 * (xd**2 + yd**2) + J / 2 * thd**2
    scene = scene_from_lagrangian(L, [x, y, th], [-sp.sin(th) * xd + sp.cos(th) * yd],
                                  {m: 2.0, J: 0.75})

`L` must be quadratic-plus-linear in the velocities, `L = 1/2 qd^T M(q) qd + A(q) qd -
V(q)` (spec eq. (3.1)): M, A and V are read off its polynomial in the velocities, and a term
of another degree, or one in which a velocity is not a polynomial variable, is refused
naming it. Each constraint is linear in the velocities, `mu^a(q) qd = 0` (a term without a
velocity, or of degree 2, is refused naming it). Every expression is printed in the scene
language (spec (10.4)): `+ - * /`, integer powers, `sqrt`, real powers (`b^e`, defined for
b > 0), `sin cos tan exp log atan sinh cosh tanh`, `pi`, numbers (integers and rationals
exact, `(1/3)` is the real one third; a sympy Float is its nearest f64); `cot sec csc coth
sech csch` as quotients. Anything else (Abs, asin, atan2, Piecewise, an undefined function,
explicit time, a symbol without a value) is refused naming the expression and where it is.
"""

from __future__ import annotations

import itertools
import math
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

import sympy as sp  # type: ignore[import-untyped]
from sympy.core.function import AppliedUndef  # type: ignore[import-untyped]

from ._scene import FUNCTIONS, IDENTIFIER, NOT_ANALYTIC, RESERVED, Scene

__all__ = ["scene_from_lagrangian", "from_lagranges", "to_scene_expr", "SceneError"]


class SceneError(ValueError):
    """A sympy model the scene language cannot take: the message names the expression and
    where it is (the key, row and column of the scene)."""


# precedences of the printed forms: a sum, a product or quotient, a negation, a power, an atom
_ADD, _MUL, _NEG, _POW, _ATOM = 1, 2, 3, 4, 5
_SAME_NAME = {sp.sin: "sin", sp.cos: "cos", sp.tan: "tan", sp.exp: "exp", sp.log: "log",
              sp.atan: "atan", sp.sinh: "sinh", sp.cosh: "cosh", sp.tanh: "tanh"}
_QUOTIENTS = {sp.cot: ("cos", "sin"), sp.sec: ("1", "cos"), sp.csc: ("1", "sin"),
              sp.coth: ("cosh", "sinh"), sp.sech: ("1", "cosh"), sp.csch: ("1", "sinh")}
_F64_INTEGER = 2 ** 53


class _Printer:
    """Prints sympy expressions in the scene language; `names` maps the sympy symbols that
    may appear (coordinates, parameters) to their scene names."""

    def __init__(self, names: Mapping[sp.Symbol, str], where: str, shown: Any) -> None:
        self.names, self.where, self.shown = names, where, shown

    def refuse(self, e: Any, why: str) -> SceneError:
        return SceneError(f"{self.where}: the scene language cannot read `{self.shown(e)}`: "
                          f"{why}")

    def wrap(self, e: Any, prec: int) -> str:
        text, p = self.p(e)
        return text if p > prec else f"({text})"

    def p(self, e: Any) -> Tuple[str, int]:
        if e.is_Integer:
            n = int(e)
            if abs(n) > _F64_INTEGER:
                raise self.refuse(e, "an integer beyond 2^53 is not exactly an f64 (write it "
                                  "as a product or power)")
            return (str(n), _ATOM) if n >= 0 else (str(n), _NEG)
        if e.is_Rational:
            text = f"{abs(e.p)}/{e.q}"
            return (text, _MUL) if e.p > 0 else ("-" + text, _NEG)
        if e.is_Float:
            f = float(e)
            if not math.isfinite(f):
                raise self.refuse(e, "not a finite number")
            return (repr(f), _ATOM) if f >= 0 else (repr(f), _NEG)
        if e is sp.pi:
            return "pi", _ATOM
        if e is sp.E:
            return "exp(1)", _ATOM
        if e.is_Symbol:
            if e in self.names:
                return self.names[e], _ATOM
            raise self.refuse(e, "a symbol without a value (give it in `parameters`, or it "
                              "is not a coordinate)")
        if e.is_Add:
            terms = e.as_ordered_terms()
            out = self.wrap(terms[0], _ADD - 1)
            for term in terms[1:]:
                if term.could_extract_minus_sign():
                    out += " - " + self.wrap(-term, _ADD)
                else:
                    out += " + " + self.wrap(term, _ADD)
            return out, _ADD
        if e.is_Mul:
            if e.could_extract_minus_sign():
                return "-" + self.wrap(-e, _NEG - 1), _NEG
            num, den = [], []
            for f in e.as_ordered_factors():
                if f.is_Pow and f.exp.is_Rational and f.exp.is_negative:
                    den.append(f.base ** (-f.exp))
                elif f.is_Rational and not f.is_Integer:
                    if f.p != 1:
                        num.append(sp.Integer(f.p))
                    den.append(sp.Integer(f.q))
                else:
                    num.append(f)
            text = "*".join(self.wrap(f, _MUL) for f in num) if num else "1"
            for d in den:
                text += "/" + self.wrap(d, _MUL)
            return text, _MUL
        if e.is_Pow:
            b, x = e.base, e.exp
            if x.is_Integer:
                n = int(x)
                if abs(n) > 1024:
                    raise self.refuse(e, "an integer exponent beyond 1024")
                if n < 0:
                    return f"1/{self.wrap(b ** -n, _MUL)}", _MUL
                return f"{self.wrap(b, _POW)}^{n}", _POW
            if x.is_Rational and x.q == 2:
                root = f"sqrt({self.p(b)[0]})"
                k = int(x.p)
                if k == 1:
                    return root, _ATOM
                if k == -1:
                    return f"1/{root}", _MUL
                if k > 0:
                    return f"{root}^{k}", _POW
                return f"1/{root}^{-k}", _MUL
            if b is sp.E:
                return f"exp({self.p(x)[0]})", _ATOM
            # the real-exponent path of (10.6): exp(x log b), defined for b > 0
            return f"{self.wrap(b, _POW)}^({self.p(x)[0]})", _POW
        if isinstance(e, sp.Function) and len(e.args) == 1:
            fn = type(e)
            arg = self.p(e.args[0])[0]
            if fn in _SAME_NAME:
                return f"{_SAME_NAME[fn]}({arg})", _ATOM
            if fn in _QUOTIENTS:
                num_f, den_f = _QUOTIENTS[fn]
                top = "1" if num_f == "1" else f"{num_f}({arg})"
                return f"{top}/{den_f}({arg})", _MUL
        name = type(e).__name__
        if isinstance(e, AppliedUndef):
            why = "an undefined function (a dynamic symbol that is not a coordinate, or " \
                  "explicit time)"
        elif name.lower() in NOT_ANALYTIC or isinstance(e, (sp.Abs, sp.sign, sp.Piecewise,
                                                             sp.floor, sp.ceiling)):
            why = "not analytic (the validated flow needs analytic data)"
        elif isinstance(e, sp.Derivative):
            why = "a derivative (only coordinates' first derivatives, the velocities, " \
                  "belong in L and the constraints)"
        else:
            why = f"{name} is not in it (its functions: {', '.join(FUNCTIONS)}; powers, " \
                  "+ - * /, pi and numbers)"
        raise self.refuse(e, why)


def _name(c: Any, i: int, t: Any) -> str:
    if not (isinstance(c, AppliedUndef) and c.args == (t,)):
        raise SceneError(f"q[{i + 1}]: expected a coordinate as dynamicsymbols makes it (a "
                         f"function of {t}), got `{c}`")
    name: str = c.func.__name__
    if not IDENTIFIER.match(name) or name in RESERVED:
        raise SceneError(f"q[{i + 1}]: the name `{name}` is not a name of the scene language "
                         f"(an identifier [A-Za-z_][A-Za-z0-9_]*, not one of its functions "
                         f"or pi): rename the dynamic symbol")
    return name


def _parameters(parameters: Mapping[Any, Any], coords: Sequence[str]
                ) -> Dict[str, float]:
    out: Dict[str, float] = {}
    for k, v in parameters.items():
        name = k if isinstance(k, str) else getattr(k, "name", None)
        if not isinstance(name, str):
            raise SceneError(f"parameters: a key is a symbol or a name, not `{k}`")
        if not IDENTIFIER.match(name) or name in RESERVED or name in coords:
            raise SceneError(f"parameters: `{name}` cannot be a parameter's name (an "
                             f"identifier, not a function of the scene language, pi, or a "
                             f"coordinate)")
        try:
            value = float(v)
        except (TypeError, ValueError):
            raise SceneError(f"parameters: `{name}` = {v!r} is not a number") from None
        if not math.isfinite(value):
            raise SceneError(f"parameters: `{name}` = {v!r} is not finite")
        out[name] = value
    return out


def scene_from_lagrangian(L: Any, q: Sequence[Any], constraints: Sequence[Any],
                          parameters: Mapping[Any, Any], *, free: Optional[Sequence[Any]] = None,
                          basis: Optional[Sequence[Sequence[Any]]] = None, t: Any = None,
                          name: str = "sympy") -> Scene:
    """The `Scene` of the Lagrangian `L` (a sympy expression in the coordinates `q`,
    functions of time as `dynamicsymbols` makes them, and their first derivatives) with the
    nonholonomic constraints `constraints` (expressions linear in the velocities, each
    `= 0`; a sympy `Eq` is taken as lhs - rhs) and the parameter values `parameters` (a
    dict from symbols or names to numbers; every other symbol is refused).

    `free`: the free coordinates of the derived basis (spec (10.10)); by default the first
    choice (in the order of `q`, the dependent coordinates taken from the end) whose pivot
    block of the constraints has a determinant free of q and nonzero, else the first whose
    determinant is nonzero at q = 0. `basis`: rows e_a(q) of D instead (sympy expressions
    in q). `t`: the time symbol (default `dynamicsymbols._t`). SceneError (a ValueError)
    names what cannot be read."""
    from sympy.physics.mechanics import dynamicsymbols  # type: ignore[import-untyped]

    t = dynamicsymbols._t if t is None else t
    q = list(q)
    if not q:
        raise SceneError("q: no coordinates")
    names = [_name(c, i, t) for i, c in enumerate(q)]
    if len(set(names)) != len(names):
        raise SceneError(f"q: coordinates named alike: {names}")
    params = _parameters(parameters, names)
    Q = [sp.Symbol(f"_dalembert_q{i}", real=True) for i in range(len(q))]
    QD = [sp.Symbol(f"_dalembert_qd{i}", real=True) for i in range(len(q))]
    to_plain = {c.diff(t): v for c, v in zip(q, QD)}
    to_plain_q = dict(zip(q, Q))
    back = {**{v: sp.Symbol(n) for v, n in zip(Q, names)},
            **{v: sp.Symbol(n + "d") for v, n in zip(QD, names)}}

    def shown(e: Any) -> str:
        return str(e.xreplace(back)) if isinstance(e, sp.Basic) else str(e)

    symbols: Dict[Any, str] = dict(zip(Q, names))
    by_name = {n: n for n in params}

    def plain(e: Any, where: str) -> Any:
        e = sp.sympify(e)
        if isinstance(e, sp.Eq):
            e = e.lhs - e.rhs
        e = e.subs(to_plain).subs(to_plain_q)
        for s in e.free_symbols:
            if s in symbols:
                continue
            if s == t:
                term = next((a for a in sp.Add.make_args(sp.expand(e)) if a.has(t)), e)
                raise SceneError(f"{where}: explicit time `{t}` in `{shown(term)}`: a scene "
                                 "is autonomous")
            if s.name in by_name and s not in QD:
                symbols[s] = s.name
        return e

    def printer(where: str) -> _Printer:
        return _Printer(symbols, where, shown)

    def velocity_poly(e: Any, where: str) -> Any:
        # a term in which a velocity is not a polynomial variable is named
        if not e.is_polynomial(*QD):
            for term in sp.Add.make_args(sp.expand(e)):
                if not term.is_polynomial(*QD):
                    raise SceneError(f"{where}: the term `{shown(term)}` is not a polynomial "
                                     "in the velocities")
            raise SceneError(f"{where}: `{shown(e)}` is not a polynomial in the velocities")
        return sp.Poly(e, *QD)

    # -- the Lagrangian: M, A, V read off its polynomial in the velocities --------------
    Lp = plain(L, "L")
    n = len(q)
    M = [[sp.Integer(0)] * n for _ in range(n)]
    A = [sp.Integer(0)] * n
    V = sp.Integer(0)
    for monom, coeff in velocity_poly(Lp, "L").terms():
        deg = sum(monom)
        idx = [i for i, d in enumerate(monom) if d]
        if deg > 2:
            term = coeff * sp.Mul(*[v ** d for v, d in zip(QD, monom)])
            raise SceneError(f"L: the term `{shown(term)}` is of degree {deg} in the velocities "
                             "(L must be quadratic-plus-linear: 1/2 qd^T M(q) qd + A(q) qd - V(q))")
        if deg == 2 and len(idx) == 1:
            M[idx[0]][idx[0]] += 2 * coeff
        elif deg == 2:
            i, j = idx
            M[i][j] += coeff
            M[j][i] += coeff
        elif deg == 1:
            A[idx[0]] += coeff
        else:
            V -= coeff
    # -- the constraints: rows mu^a(q), linear in the velocities ------------------------
    mu: List[List[Any]] = []
    for a, c in enumerate(constraints):
        where = f"constraints[{a + 1}]"
        cp = plain(c, where)
        row = [sp.Integer(0)] * n
        for monom, coeff in velocity_poly(cp, where).terms():
            deg = sum(monom)
            term = coeff * sp.Mul(*[v ** d for v, d in zip(QD, monom)])
            if deg != 1:
                raise SceneError(f"{where}: the term `{shown(term)}` is of degree {deg} in the "
                                 "velocities (a constraint is mu(q) qd = 0: linear, without "
                                 "a term free of the velocities)")
            row[monom.index(1)] += coeff
        if all(x == 0 for x in row):
            raise SceneError(f"{where}: `{shown(cp)}` has no velocity in it")
        mu.append(row)
    k = len(mu)
    if not 1 <= k <= n - 1:
        raise SceneError(f"constraints: {k} for {n} coordinates (1 to n - 1 = {n - 1} "
                         "allowed)")
    scene: Dict[str, Any] = {"name": name, "coordinates": names, "parameters": params}

    # printed with the scene's names as the symbols (so that sympy orders the factors by
    # them), every other symbol refused first
    named = {s: sp.Symbol(nm) for s, nm in symbols.items() if s in Q}
    printed_names = {sp.Symbol(nm): nm for nm in names}

    def text(e: Any, where: str) -> Any:
        e = sp.sympify(e)
        if any(e.has(v) for v in QD):
            raise SceneError(f"{where}: `{shown(e)}` depends on a velocity")
        for s in sorted(e.free_symbols, key=str):
            if s not in symbols:
                raise printer(where).refuse(s, "a symbol without a value (give it in "
                                            "`parameters`, or it is not a coordinate)")
        e = _tidy(e.xreplace(named))
        if e.is_Integer and abs(int(e)) <= _F64_INTEGER:
            return int(e)
        known = {**printed_names, **{s: nm for s, nm in symbols.items() if s not in Q}}
        return _Printer(known, where, shown).p(e)[0]

    scene["mass"] = [[text(M[i][j] if j >= i else M[j][i], f"mass[{i + 1}][{j + 1}]")
                      for j in range(n)] for i in range(n)]
    if V != 0:
        scene["potential"] = text(V, "potential")
    if any(x != 0 for x in A):
        scene["one_form"] = [text(x, f"one_form[{i + 1}]") for i, x in enumerate(A)]
    scene["constraints"] = [[text(x, f"constraints[{a + 1}][{i + 1}]")
                             for i, x in enumerate(row)] for a, row in enumerate(mu)]
    if basis is not None and free is not None:
        raise SceneError("basis and free: give one of them (either decides the basis)")
    if basis is not None:
        rows = [list(r) for r in basis]
        if len(rows) != n - k or any(len(r) != n for r in rows):
            raise SceneError(f"basis: expected {n - k} rows of {n} expressions")
        scene["basis"] = [[text(plain(x, f"basis[{a + 1}][{i + 1}]"), f"basis[{a + 1}][{i + 1}]")
                           for i, x in enumerate(r)] for a, r in enumerate(rows)]
    else:
        scene["free"] = _free(free, q, names, mu, Q, params, symbols)
    return Scene(scene)


def _tidy(e: Any) -> Any:
    """A lighter form of an entry read off L (terms collected; no general simplify, which
    can take long)."""
    try:
        return sp.factor_terms(sp.expand(e))
    except (sp.PolynomialError, TypeError):  # pragma: no cover (expand never refuses here)
        return e


def _free(free: Optional[Sequence[Any]], q: Sequence[Any], names: List[str],
          mu: List[List[Any]], Q: List[Any], params: Dict[str, float],
          symbols: Dict[Any, str]) -> List[str]:
    n, k = len(names), len(mu)
    if free is not None:
        out = []
        for f in free:
            nm = f if isinstance(f, str) else (names[list(q).index(f)] if f in list(q)
                                               else None)
            if nm not in names:
                raise SceneError(f"free: `{f}` is not a coordinate ({', '.join(names)})")
            out.append(nm)
        if len(out) != n - k or len(set(out)) != len(out):
            raise SceneError(f"free: expected {n - k} distinct coordinates, got {out}")
        return out
    at_zero = {s: (0 if s in Q else params[name]) for s, name in symbols.items()}
    combos = list(itertools.combinations(range(n), k))[::-1]  # dependent ones from the end
    fallback = None
    for dep in combos:
        det = sp.Matrix([[row[i] for i in dep] for row in mu]).det()
        if det == 0:
            continue
        if not any(det.has(s) for s in Q):
            return [names[i] for i in range(n) if i not in dep]
        if fallback is None:
            try:
                value = complex(det.subs(at_zero).evalf())
            except (TypeError, ValueError):
                continue
            if value != 0 and math.isfinite(abs(value)):
                fallback = dep
    if fallback is None:
        raise SceneError("free: no choice of free coordinates has a pivot block proved "
                         "nonsingular at q = 0: give free= or basis=")
    return [names[i] for i in range(n) if i not in fallback]


def from_lagranges(lm: Any, parameters: Mapping[Any, Any], **kw: Any) -> Scene:
    """`scene_from_lagrangian` of a `sympy.physics.mechanics.LagrangesMethod`: its
    Lagrangian, coordinates and constraints (`nonhol_coneqs`, and the time derivatives of
    `hol_coneqs`, which are linear in the velocities too). A method with a `forcelist`
    (forces not from a potential) is refused: a scene's forces come from L."""
    if getattr(lm, "_forcelist", None):
        raise SceneError("from_lagranges: the LagrangesMethod has a forcelist; a scene's "
                         "forces come from L (put conservative forces in the potential)")
    L = lm._L[0] if isinstance(lm._L, sp.MatrixBase) else lm._L
    return scene_from_lagrangian(L, list(lm.q), list(lm.coneqs), parameters, **kw)


def to_scene_expr(e: Any, names: Mapping[Any, str], where: str = "expression") -> str:
    """One sympy expression printed in the scene language, `names` mapping its symbols to
    scene names (SceneError naming what cannot be read)."""
    text: str = _Printer(dict(names), where, str).p(sp.sympify(e))[0]
    return text
