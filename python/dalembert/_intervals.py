"""Intervals as the oracle prints them, and the few certified operations done in Python.

Every bound the binary prints reaches the caller unchanged: JSON numbers are read by
Python's `json` (correctly rounded, so each endpoint is the f64 the binary printed) and kept
as they are in `Interval(lo, hi)`; the decimal strings of an answer computed with more than
53 bits (contract E18) are kept as the exact `Exact` (a `decimal.Decimal` subclass that
mixes exactly with floats) each writes. So an end is a `float` at 53 bits and an `Exact`
above: both exact, compared exactly with ints, floats, Fractions and Decimals, and both
take float operands (`iv.lo - 1.2`). Nothing here
rounds, re-computes or re-centres them. The bounds this module computes itself
(`distance`, `quotient`, `observed_order`, `Interval.width_up`, `to_array` of decimal ends)
round outwards; their docstrings say how. `Interval.mid` is a point, not a bound.
"""

from __future__ import annotations

import math
from decimal import (
    MAX_EMAX, MIN_EMIN, Context, Decimal, DivisionByZero, Inexact, InvalidOperation, Overflow,
    Rounded, localcontext,
)
from fractions import Fraction
from typing import Any, Iterable, Iterator, List, Sequence, Tuple, Union

__all__ = [
    "Interval", "IntervalLike", "Exact", "down", "up", "distance", "quotient", "observed_order",
    "to_array",
]


def _exponent(d: Decimal) -> int:
    """The exponent of a finite Decimal's last digit."""
    e = d.as_tuple().exponent
    assert isinstance(e, int)
    return e


_EXACT_TRAPS = [InvalidOperation, DivisionByZero, Overflow, Inexact, Rounded]


def _operand(x: Any) -> Any:
    """`x` as a Decimal operand: a float or an int exactly (Decimal(float) is the float's
    exact binary value), a Decimal as it is; NotImplemented for anything else."""
    if isinstance(x, Decimal):
        return x
    if isinstance(x, (float, int)) and not isinstance(x, bool):
        if isinstance(x, float) and not math.isfinite(x):
            return NotImplemented
        return Decimal(x)
    return NotImplemented


def _exact_context(a: Decimal, b: Decimal, product: bool) -> Context:
    """A context whose precision holds the exact sum (or product) of finite a and b."""
    da, db = len(a.as_tuple().digits), len(b.as_tuple().digits)
    if product:
        prec = da + db
    else:
        prec = max(a.adjusted(), b.adjusted()) - min(_exponent(a), _exponent(b)) + 2
    return Context(prec=max(prec, 1), Emax=MAX_EMAX, Emin=MIN_EMIN, traps=_EXACT_TRAPS)


class Exact(Decimal):
    """An interval end of an answer computed with more than 53 bits (contract E18, E20):
    the exact decimal number the binary printed, a `decimal.Decimal` that also mixes with
    floats. Comparisons with ints, floats, Fractions and Decimals are exact (as Decimal's);
    `+`, `-` and `*` with an int, a float (taken as its exact binary value) or a Decimal
    are exact and give an `Exact` (`iv.lo - 1.2` is the exact difference from the float
    1.2); `/` rounds to the current decimal context (a point, not a bound); with a
    Fraction the result is the exact `Fraction`. `float(x)` is the float nearest x."""

    __slots__ = ()

    def _exact(self, other: Any, op: str, swap: bool = False) -> Any:
        if isinstance(other, Fraction):
            fa, fb = Fraction(self), other
            if swap:
                fa, fb = fb, fa
            return {"+": fa + fb, "-": fa - fb, "*": fa * fb}[op]
        o = _operand(other)
        if o is NotImplemented:
            return NotImplemented
        a, b = (o, self) if swap else (self, o)
        c = _exact_context(a, b, op == "*")
        r = c.add(a, b) if op == "+" else c.subtract(a, b) if op == "-" else c.multiply(a, b)
        return Exact(r)

    def __add__(self, other: Any) -> Any:
        return self._exact(other, "+")

    def __radd__(self, other: Any) -> Any:
        return self._exact(other, "+", True)

    def __sub__(self, other: Any) -> Any:
        return self._exact(other, "-")

    def __rsub__(self, other: Any) -> Any:
        return self._exact(other, "-", True)

    def __mul__(self, other: Any) -> Any:
        return self._exact(other, "*")

    def __rmul__(self, other: Any) -> Any:
        return self._exact(other, "*", True)

    def __truediv__(self, other: Any) -> Any:
        if isinstance(other, Fraction):
            return Fraction(self) / other
        o = _operand(other)
        return NotImplemented if o is NotImplemented else Exact(Decimal.__truediv__(self, o))

    def __rtruediv__(self, other: Any) -> Any:
        if isinstance(other, Fraction):
            return other / Fraction(self)
        o = _operand(other)
        return NotImplemented if o is NotImplemented else Exact(Decimal.__truediv__(o, self))

    def __neg__(self, context: Any = None) -> "Exact":
        return Exact(self.copy_negate())

    def __pos__(self, context: Any = None) -> "Exact":
        return self

    def __abs__(self, round: bool = True, context: Any = None) -> "Exact":
        return Exact(self.copy_abs())

    def __repr__(self) -> str:
        return f"Exact('{self}')"


class Interval(tuple):  # type: ignore[type-arg]
    """A closed interval [lo, hi] as the oracle printed it: `lo` and `hi` are the JSON
    numbers, unchanged (never rounded, never recomputed), or for an answer computed with
    more than 53 bits the `Exact` numbers (exact Decimals that mix with floats) of its
    decimal strings. The exact value lies in
    it. (A tuple `(lo, hi)` underneath, so that the client builds many of them fast;
    `x in iv` is the interval's membership, not the tuple's, and compares exactly.)"""

    __slots__ = ()

    def __new__(cls, lo: float, hi: float) -> "Interval":
        if not lo <= hi:
            raise ValueError(f"not an interval: [{lo!r}, {hi!r}]")
        return tuple.__new__(cls, (lo, hi))

    @property
    def lo(self) -> float:
        return tuple.__getitem__(self, 0)  # type: ignore[no-any-return]

    @property
    def hi(self) -> float:
        return tuple.__getitem__(self, 1)  # type: ignore[no-any-return]

    def __contains__(self, x: Any) -> bool:
        """Exact comparison: x may be an int, float, Fraction or Decimal."""
        return bool(self[0] <= x <= self[1])

    def contains(self, x: Any) -> bool:
        return x in self

    def excludes_zero(self) -> bool:
        return self.lo > 0 or self.hi < 0

    def width_up(self) -> float:
        """An upper bound on hi - lo: the float difference rounded up by one ulp (decimal
        ends: the exact difference rounded up to a float)."""
        lo, hi = self
        if type(lo) is float and type(hi) is float:
            return up(hi - lo)
        return _float_up(Fraction(hi) - Fraction(lo))

    def mag(self) -> float:
        """max(|lo|, |hi|): exact (abs and max of floats round nothing)."""
        return max(abs(self.lo), abs(self.hi))

    @property
    def mid(self) -> Any:
        """A point inside the interval (a point, not a bound): a float (round to nearest);
        for decimal ends the float nearest the exact midpoint, or, when no float lies in
        the interval, the exact midpoint as a `Decimal`."""
        lo, hi = self
        if type(lo) is float and type(hi) is float:
            m = lo / 2 + hi / 2
            return min(max(m, lo), hi)
        f = float((Fraction(lo) + Fraction(hi)) / 2)  # correctly rounded
        if lo <= f <= hi:  # (if a float lies in [lo, hi], the one nearest the midpoint does)
            return f
        a, b = Decimal(lo), Decimal(hi)
        with localcontext() as c:  # digits enough for the exact sum, then exact halving
            c.traps[Inexact] = True
            low = min(_exponent(a), _exponent(b))
            c.prec = max(a.adjusted(), b.adjusted()) - low + 3
            return Exact((a + b) / 2)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Interval) and tuple.__eq__(self, other)

    def __ne__(self, other: object) -> bool:
        return not self == other

    def __hash__(self) -> int:
        return tuple.__hash__(self)

    def __repr__(self) -> str:
        return f"Interval({self[0]!r}, {self[1]!r})"


def _unchecked(pairs: Any) -> List[Interval]:
    """Intervals from [lo, hi] pairs already known to be intervals (the client's fast path;
    `intervals` checks)."""
    new = tuple.__new__
    return [new(Interval, p) for p in pairs]


def intervals(pairs: Any) -> List[Interval]:
    """Intervals from a list of [lo, hi] pairs of numbers with lo <= hi; ValueError
    otherwise."""
    for p in pairs:
        if not (isinstance(p, list) and len(p) == 2 and p[0] <= p[1]):
            raise ValueError(f"not an interval [lo, hi]: {p!r}")
    return _unchecked(pairs)


IntervalLike = Union[Interval, Sequence[float], Tuple[float, float]]


def _outward(x: Any) -> Any:
    """`x` with every interval's ends made floats outward: float ends as they are, other
    ends (decimals) rounded down (lo) and up (hi) to floats exactly."""
    if isinstance(x, Interval):
        lo, hi = x
        if type(lo) is float and type(hi) is float:
            return x
        return (_float_down(Fraction(lo)), _float_up(Fraction(hi)))
    if isinstance(x, (list, tuple)):
        return [_outward(v) for v in x]
    return x


def to_array(intervals: Any) -> Any:
    """The intervals as a float64 numpy array whose last axis is [lo, hi]: `(n, 2)` for a
    vector of intervals, `(n, n, 2)` for a matrix, `(2,)` for one interval. Float ends are
    the oracle's floats, copied exactly (float64 holds every f64); decimal ends (answers
    computed with more than 53 bits) are rounded outward to the floats around them, so
    that the array still encloses. Needs numpy."""
    import numpy as np

    return np.array(_outward(intervals), dtype=np.float64)


# Python floats round to nearest: the result r of one +, -, *, / or abs of floats is the
# exact result rounded to the nearest f64, so the exact result lies between the floats next
# to r. `down(r)` and `up(r)` step one ulp outwards (math.nextafter), which turns each
# operation's rounded result into a certified bound.


def down(x: float) -> float:
    """The float below x (a lower bound on the exact result of the operation that gave x)."""
    return math.nextafter(x, -math.inf)


def up(x: float) -> float:
    """The float above x (an upper bound on the exact result of the operation that gave x)."""
    return math.nextafter(x, math.inf)


def _box(b: IntervalLike) -> Interval:
    return b if isinstance(b, Interval) else Interval(b[0], b[1])


def _zip_same(a: Iterable[Any], b: Iterable[Any]) -> Iterator[Tuple[Any, Any]]:
    la, lb = list(a), list(b)
    if len(la) != len(lb):
        raise ValueError(f"dimensions differ: {len(la)} and {len(lb)}")
    return zip(la, lb)


def distance(x: Sequence[float], box: Sequence[IntervalLike]) -> Interval:
    """Certified enclosure of |x - b|_inf for every b in the box (spec chapter 8,
    `distance`): an `Interval` with lo <= min over the box and hi >= max over the box.
    `x` is a sequence of floats, `box` a sequence of `Interval`s (or [lo, hi] pairs, e.g. the
    rows of an `(n, 2)` array). Each subtraction is done in float and its result moved one
    ulp outwards with math.nextafter (`down`/`up`), since Python rounds to nearest; abs and
    max are exact. A box with decimal ends (an answer computed with more than 53 bits) is
    measured in exact rationals, each bound then rounded outward to a float."""
    lo = hi = 0.0
    for xi, b in _zip_same(x, box):
        ib = _box(b)
        xi = float(xi)
        if type(ib.lo) is not float or type(ib.hi) is not float:  # decimal ends: exact
            fx, flo, fhi = Fraction(xi), Fraction(ib.lo), Fraction(ib.hi)
            near_q = max(flo - fx, fx - fhi, Fraction(0))
            lo = max(lo, _float_down(near_q))
            hi = max(hi, _float_up(max(fx - flo, fhi - fx)))
            continue
        far = max(up(xi - ib.lo), up(ib.hi - xi))
        if xi < ib.lo:
            near = down(ib.lo - xi)
        elif xi > ib.hi:
            near = down(xi - ib.hi)
        else:
            near = 0.0
        lo, hi = max(lo, near, 0.0), max(hi, far)
    return Interval(lo, hi)


def quotient(a: IntervalLike, b: IntervalLike) -> Interval:
    """Certified a / b for intervals of positive numbers (b.lo > 0, a.lo >= 0): each
    endpoint divided in float and moved one ulp outwards (math.nextafter); with a decimal
    end, divided exactly in rationals and rounded outward to floats."""
    ia, ib = _box(a), _box(b)
    if not (ia.lo >= 0 and ib.lo > 0):
        raise ValueError(f"quotient needs a >= 0 and b > 0: {ia}, {ib}")
    if any(type(e) is not float for e in (*ia, *ib)):  # decimal ends: exact, then outward
        return Interval(_float_down(Fraction(ia.lo) / Fraction(ib.hi)),
                        _float_up(Fraction(ia.hi) / Fraction(ib.lo)))
    return Interval(max(0.0, down(ia.lo / ib.hi)), up(ia.hi / ib.lo))


# Observed order: a logarithm is not one rounded operation (math.log's error is not
# specified), so it is bounded here in exact rational arithmetic (fractions.Fraction) and
# the final bounds are rounded outwards to floats exactly.


def _atanh_series(m: Fraction) -> Tuple[Fraction, Fraction]:
    """ln m = 2 atanh(t), t = (m - 1) / (m + 1), |t| <= 1/3: partial sum and tail bound."""
    t = (m - 1) / (m + 1)
    t2, term, s = t * t, t, Fraction(0)
    for j in range(40):  # |t|^(2j+1) <= 3^-81 at the end
        s += term / (2 * j + 1)
        term *= t2
    tail = 2 * abs(term) / (81 * (1 - t2))  # sum of the remaining terms, bounded
    return 2 * s - tail, 2 * s + tail


_LN2 = _atanh_series(Fraction(2))


def _ln_bounds(x: Fraction) -> Tuple[Fraction, Fraction]:
    """Rationals lo <= ln(x) <= hi for a rational x > 0 (error below 2^-100)."""
    x = Fraction(x)
    if x <= 0:
        raise ValueError("ln of a non-positive number")
    k = x.numerator.bit_length() - x.denominator.bit_length()
    m = x / Fraction(2) ** k  # m in (1/2, 2)
    lo_m, hi_m = _atanh_series(m)
    lo_2, hi_2 = _LN2
    if k >= 0:
        return lo_m + k * lo_2, hi_m + k * hi_2
    return lo_m + k * hi_2, hi_m + k * lo_2


def _float_down(r: Fraction) -> float:
    f = float(r)  # Fraction -> float is correctly rounded
    return down(f) if Fraction(f) > r else f


def _float_up(r: Fraction) -> float:
    f = float(r)
    return up(f) if Fraction(f) < r else f


def observed_order(e_a: IntervalLike, e_b: IntervalLike, h_a: float, h_b: float) -> Interval:
    """Certified enclosure of log(e_a / e_b) / log(h_a / h_b) for the errors e_a at step
    h_a and e_b at h_b (intervals of positive numbers, h floats taken as exact): every
    order p with e_a / e_b = (h_a / h_b)^p for some e_a, e_b in the intervals lies in it.
    Logarithms are bounded in exact rational arithmetic, the result rounded outwards."""
    ia, ib = _box(e_a), _box(e_b)
    if not (ia.lo > 0 and ib.lo > 0):
        raise ValueError(f"no order: an error interval reaches 0 ({ia}, {ib})")
    if h_a == h_b or h_a <= 0 or h_b <= 0:
        raise ValueError("observed_order needs two different positive steps")
    num_lo = _ln_bounds(Fraction(ia.lo) / Fraction(ib.hi))[0]
    num_hi = _ln_bounds(Fraction(ia.hi) / Fraction(ib.lo))[1]
    den_lo, den_hi = _ln_bounds(Fraction(h_a) / Fraction(h_b))
    if den_lo <= 0 <= den_hi:
        raise ValueError("observed_order: log(h_a / h_b) not proved non-zero")
    qs = [n / d for n in (num_lo, num_hi) for d in (den_lo, den_hi)]
    return Interval(_float_down(min(qs)), _float_up(max(qs)))
