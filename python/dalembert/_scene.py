"""`Scene`: a posed system as the dict of a scene file (spec chapter 10), and the map from a
solver's state vector to the scene's (q, u).

A `Scene` is a `dict` with the keys of a scene file (`coordinates`, `parameters`, `mass`,
`potential`, `one_form`, `constraints`, `free` or `basis`, ...), so it is sent inline
wherever a scene is taken. `Scene.state(y)` evaluates the scene's constraints and basis in
floats (a point map, not a bound: the oracle then starts exactly from the floats it
returns) by reading their expressions with the grammar of spec (10.4).
"""

from __future__ import annotations

import math
import re
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple

__all__ = ["Scene", "FUNCTIONS", "RESERVED"]

#: The functions of the scene language, spec (10.4).
FUNCTIONS = ("sin", "cos", "tan", "exp", "log", "ln", "sqrt", "atan", "sinh", "cosh", "tanh")
#: Names refused as "not analytic", spec (10.7).
NOT_ANALYTIC = ("abs", "min", "max", "floor", "ceil", "sign", "sgn", "signum", "round", "mod",
                "fmod", "rem", "trunc", "fract", "frac", "heaviside", "step", "clamp")
#: Names a coordinate or parameter may not have, spec (10.2).
RESERVED = frozenset(FUNCTIONS) | frozenset(NOT_ANALYTIC) | {"pi"}
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")

# the tokens of (10.4): a number, a name, an operator or a parenthesis (white space between)
_TOKEN = re.compile(r"\s*(?:(\d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)|"
                    r"([A-Za-z_][A-Za-z0-9_]*)|(\*\*|[-+*/^()]))")
_MATH: Dict[str, Callable[[float], float]] = {
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "exp": math.exp, "log": math.log,
    "ln": math.log, "sqrt": math.sqrt, "atan": math.atan, "sinh": math.sinh,
    "cosh": math.cosh, "tanh": math.tanh,
}


def _float_fn(text: Any, names: Sequence[str], where: str) -> Callable[..., float]:
    """A float function of `names` (positional) computing the expression `text` of the
    scene language (a string or a number): its tokens are checked against (10.4) and the
    expression is evaluated by Python with `^` as `**` (the same precedence and
    associativity: `-x^2` is `-(x^2)`, `2^3^2` is `2^9`). A point evaluation: rounded, not
    a bound. ValueError naming `where` for a token the grammar does not have."""
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        value = float(text)
        return lambda *args: value
    if not isinstance(text, str):
        raise ValueError(f"{where}: expected an expression (a string or a number), "
                         f"got {text!r}")
    out: List[str] = []
    pos, end = 0, len(text.rstrip())
    known = set(names)
    while pos < end:
        m = _TOKEN.match(text, pos)
        if m is None:
            raise ValueError(f"{where}: unexpected {text[pos:].strip()[:1]!r} at character "
                             f"{pos + 1} of {text!r}")
        num, name, op = m.groups()
        if num is not None:
            out.append(repr(float(num)))
        elif name is not None:
            if name == "pi":
                out.append("_pi")
            elif name in _MATH:
                out.append(f"_f_{name}")
            elif name in known:
                out.append(f"_v_{name}")
            else:
                raise ValueError(f"{where}: unknown name `{name}` in {text!r} (known: "
                                 f"{', '.join(names)}, pi)")
        elif op == "**":
            raise ValueError(f"{where}: `**` in {text!r}: powers are written `^`")
        else:
            out.append("**" if op == "^" else op)
        pos = m.end()
    args = ", ".join(f"_v_{n}" for n in names)
    env: Dict[str, Any] = {f"_f_{k}": f for k, f in _MATH.items()}
    env["_pi"] = math.pi
    env["__builtins__"] = {}
    code = compile(f"lambda {args}: ({' '.join(out)})", f"<{where}>", "eval")
    fn: Callable[..., float] = eval(code, env)  # noqa: S307 (tokens checked above)
    return fn


class Scene(dict):  # type: ignore[type-arg]
    """A scene posed as data: a dict with the keys of a scene file (spec chapter 10), usable
    wherever a scene is (`Oracle(scene=...)`, `scene=` of any query, the strategies, the
    campaign). `dalembert.sympy.scene_from_lagrangian` makes one from a sympy model;
    `Scene({...})` wraps a dict written by hand.

    `n` is the number of coordinates, `m` the number of quasi-velocities (n - k, k the
    number of constraints); `state(y)` maps a solver's state vector to the scene's (q, u)."""

    def __reduce__(self) -> Any:
        # pickled (Dask, multiprocessing) as its dict alone, without the compiled functions
        return (Scene, (dict(self),))

    @property
    def n(self) -> int:
        return len(self["coordinates"])

    @property
    def m(self) -> int:
        return self.n - len(self["constraints"])

    def _params(self, params: Optional[Mapping[str, float]]) -> Dict[str, float]:
        p = {str(k): float(v) for k, v in (self.get("parameters") or {}).items()}
        for k, v in (params or {}).items():
            if k not in p:
                raise ValueError(f"params: `{k}` is not a parameter of the scene (its "
                                 f"parameters: {', '.join(p) or 'none'})")
            p[k] = float(v)
        return p

    def _compiled(self, params: Dict[str, float]) -> Tuple[Any, Any]:
        """The float functions of the constraint rows and of the basis rows (None for a
        derived basis) of q (positional), the parameters bound."""
        key = tuple(sorted(params.items()))
        cache = self.__dict__.setdefault("_cache", {})
        if key in cache:
            return cache[key]  # type: ignore[no-any-return]
        coords = list(self["coordinates"])
        names = coords + list(params)
        values = list(params.values())

        def bind(text: Any, where: str) -> Callable[[Sequence[float]], float]:
            f = _float_fn(text, names, where)
            return lambda q: f(*q, *values)

        mu = [[bind(e, f"constraints[{a + 1}][{i + 1}]") for i, e in enumerate(row)]
              for a, row in enumerate(self["constraints"])]
        basis = None
        if self.get("basis") is not None:
            basis = [[bind(e, f"basis[{a + 1}][{i + 1}]") for i, e in enumerate(row)]
                     for a, row in enumerate(self["basis"])]
        cache[key] = (mu, basis)
        return mu, basis

    def basis_at(self, q: Sequence[float], params: Optional[Mapping[str, float]] = None
                 ) -> Any:
        """The basis rows e_a(q) of D_q (an (m, n) float numpy array; point values): the
        scene's `basis`, or the one derived from `free` (spec (10.10): e_a has the a-th unit
        vector on the free coordinates, and -B^{-1} mu[:, f_a] on the others)."""
        import numpy as np

        q = [float(x) for x in q]
        mu_f, basis_f = self._compiled(self._params(params))
        if basis_f is not None:
            return np.array([[e(q) for e in row] for row in basis_f])
        mu = np.array([[e(q) for e in row] for row in mu_f])
        coords = list(self["coordinates"])
        free = [coords.index(f) for f in self["free"]]
        dep = [i for i in range(self.n) if i not in free]
        B = mu[:, dep]
        if not np.all(np.isfinite(mu)) or abs(np.linalg.det(B)) < 1e-300:
            raise ValueError(f"Scene.state: the derived basis is singular at q = {q} (the "
                             f"constraints' columns of {', '.join(coords[i] for i in dep)})")
        E = np.zeros((self.m, self.n))
        E[:, free] = np.eye(self.m)
        E[:, dep] = -np.linalg.solve(B, mu[:, free]).T
        return E

    def state(self, y: Any, params: Optional[Mapping[str, float]] = None
              ) -> Tuple[List[float], List[float]]:
        """The scene's (q, u), lists of floats, from a solver's state vector `y`: either
        `[q, qdot]` (2n entries: u solves qdot = sum_a u_a e_a(q), in a derived basis the
        velocities of the free coordinates; refused with the distance when qdot is not in
        D(q) to within 1e-9 relative, |qdot - sum u_a e_a|_inf <= 1e-9 |qdot|_inf) or `[q, u]`
        (n + m entries, m = n - k the quasi-velocities). ValueError for any other length or
        a y that is not a vector of finite numbers."""
        ys = _vector(y, "y")
        n, m = self.n, self.m
        if len(ys) == n + m:
            return ys[:n], ys[n:]
        if len(ys) != 2 * n:
            raise ValueError(
                f"Scene.state: y has {len(ys)} entries; the scene ({n} coordinates, {m} "
                f"quasi-velocities) takes [q, qdot] ({2 * n} entries) or [q, u] ({n + m})")
        import numpy as np

        q, qd = ys[:n], np.array(ys[n:])
        E = self.basis_at(q, params)
        if self.get("basis") is None:
            coords = list(self["coordinates"])
            u = qd[[coords.index(f) for f in self["free"]]]
        else:
            u = np.linalg.lstsq(E.T, qd, rcond=None)[0]
        dist = float(np.max(np.abs(qd - E.T @ u)))
        size = float(np.max(np.abs(qd))) if n else 0.0
        if not dist <= 1e-9 * size:
            raise ValueError(
                f"Scene.state: qdot is not in D(q): its distance to D is {dist:.3g} "
                f"(|qdot - sum u_a e_a(q)|_inf), relative {dist / size if size else math.inf:.3g}"
                f" > 1e-9, at q = {q}")
        return q, [float(x) for x in u]


def _vector(y: Any, name: str) -> List[float]:
    """A vector of finite floats from a list, tuple or 1-D array; ValueError otherwise."""
    shape = getattr(y, "shape", None)
    if shape is not None and len(shape) != 1:
        raise ValueError(f"{name}: expected a vector (a 1-D array), got an array of shape "
                         f"{tuple(shape)}")
    try:
        out = [float(x) for x in y]
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected a vector of numbers, got {y!r}") from None
    if not all(math.isfinite(x) for x in out):
        raise ValueError(f"{name}: a component is not finite: {out}")
    return out
