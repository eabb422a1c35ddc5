#!/usr/bin/env python3
"""References for the arbitrary precision intervals (tests/it/precision_mp.rs), from mpmath.

Writes tests/data/mp_reference.txt: one case per line,
    FUNC PREC IN_LO IN_HI REF_LO REF_HI
IN_LO, IN_HI: the argument's ends, exact decimal expansions of dyadic numbers (doubles, or
PREC-bit numbers near multiples of pi/2), so the test reads them exactly.
REF_LO, REF_HI: a rigorous enclosure of the exact range of FUNC over [IN_LO, IN_HI]
(a point when IN_LO = IN_HI), as decimals of about 2 PREC bits rounded outward: mpmath's value
at 3 PREC + 64 bits, checked against a second evaluation at 3 PREC + 192 bits, widened by a
relative 2^-(2 PREC + 16) and then rounded outward to DIGITS decimal digits. An exact end (the
extrema +-1 of sin and cos, and the bounds on the reals that cut the widened values:
|sin|, |cos|, |tanh| <= 1, cosh >= 1, exp >= 1 or <= 1 by the sign of x, ln >= 0 or <= 0 by
x against 1, atan, sinh, tanh, asinh of the sign of x) is written exactly.
Run: python3 -m venv /tmp/mpv && /tmp/mpv/bin/pip install mpmath
     /tmp/mpv/bin/python tests/data/mp_reference.py > tests/data/mp_reference.txt
"""
import math
import sys
from fractions import Fraction

import mpmath
from mpmath import mp, mpf

FUNCS = {
    "exp": mpmath.exp, "ln": mpmath.log, "sin": mpmath.sin, "cos": mpmath.cos,
    "tan": mpmath.tan, "atan": mpmath.atan, "sinh": mpmath.sinh, "cosh": mpmath.cosh,
    "tanh": mpmath.tanh, "asinh": mpmath.asinh, "sqrt": mpmath.sqrt,
}


def exact_decimal(q):
    """The exact decimal expansion of a dyadic rational q (terminates)."""
    q = Fraction(q)
    if q == 0:
        return "0"
    sign = "-" if q < 0 else ""
    q = abs(q)
    k = 0
    while q.denominator != 1:
        q *= 10
        k += 1
    s = str(q.numerator)
    return f"{sign}{s}e-{k}" if k else f"{sign}{s}"


def dyadic(x):
    """Exact rational value of an mpf or float."""
    if isinstance(x, float):
        return Fraction(x)
    sign, man, exp, _ = x._mpf_
    v = Fraction(int(man)) * (Fraction(2) ** int(exp))
    return -v if sign else v


def outward(v, digits, up):
    """v (a Fraction) rounded to `digits` significant decimals, down or up: a decimal string."""
    if v == 0:
        return "0"
    neg = v < 0
    a = -v if neg else v
    e = math.floor(math.log10(a.numerator) - math.log10(a.denominator))
    f = e - digits + 1
    while True:
        q = a / (Fraction(10) ** f)
        if q >= 10 ** digits:
            f += 1
            continue
        if q < 10 ** (digits - 1):
            f -= 1
            continue
        break
    n = q.numerator // q.denominator
    exact = Fraction(n) == q
    away = up != neg
    if not exact and away:
        n += 1
    return f"{'-' if neg else ''}{n}e{f}"


def value(fname, x, prec):
    with mpmath.workprec(prec):
        return FUNCS[fname](mpf(x))


def rigorous(fname, x, prec):
    """Fraction bounds (lo, hi) of f(x), x a Fraction (exact dyadic)."""
    if fname == "ln" and x == 1:
        return Fraction(0), Fraction(0)
    if fname == "sqrt":
        r = Fraction(math.isqrt(x.numerator), math.isqrt(x.denominator))
        if r * r == x:
            return r, r
    xs = mpf(x.numerator) / x.denominator if x.denominator != 1 else mpf(x.numerator)
    with mpmath.workprec(3 * prec + 1000):
        xs = mpf(x.numerator) / mpf(x.denominator)
    v1 = value(fname, xs, 3 * prec + 64)
    v2 = value(fname, xs, 3 * prec + 192)
    d1, d2 = dyadic(v1), dyadic(v2)
    margin = abs(d2) * Fraction(1, 2 ** (2 * prec + 16))
    assert abs(d1 - d2) < margin / 1024, (fname, x, prec)
    lo, hi = d2 - margin, d2 + margin
    # cut to the function's range on the reals (the widening may leave it)
    if fname in ("sin", "cos", "tanh"):
        lo, hi = max(lo, Fraction(-1)), min(hi, Fraction(1))
    if fname == "cosh":
        lo = max(lo, Fraction(1))
    if fname == "exp":
        lo = max(lo, Fraction(1) if x >= 0 else Fraction(0))
        if x <= 0:
            hi = min(hi, Fraction(1))
    if fname == "ln":
        if x >= 1:
            lo = max(lo, Fraction(0))
        if x <= 1:
            hi = min(hi, Fraction(0))
    if fname in ("atan", "sinh", "tanh", "asinh"):
        if x >= 0:
            lo = max(lo, Fraction(0))
        if x <= 0:
            hi = min(hi, Fraction(0))
    return lo, hi


def point_cases(prec):
    doubles = [0.5, 1.0, 2.5, 10.0, 100.0, -3.7, 0.1, -0.1, 1e-8, 1e-300, 5e-324, -2.2e-310,
               1e22, 1e300, 2.0 ** 60, -(2.0 ** 60) + 3 * 2 ** 8, 6381956970095103 * 2.0 ** 797,
               math.pi, math.pi / 2, 3 * math.pi / 2, 355.0, 709.78, 710.5, -745.2, 1000.0,
               -0.75, 0.625, 3.0, 1e5]
    pts = [Fraction(d) for d in doubles]
    # the PREC-bit numbers nearest to pi, pi/2, 3 pi/2 and 100 pi, and a double-double pi
    for k in [Fraction(1), Fraction(1, 2), Fraction(3, 2), Fraction(100)]:
        with mpmath.workprec(prec):
            v = mpf(k.numerator) * mpmath.pi / k.denominator
        pts.append(dyadic(v))
    with mpmath.workprec(300):
        hi = float(mpmath.pi)
        lo = float(mpmath.pi - hi)
    pts.append(Fraction(hi) + Fraction(lo))
    for f in FUNCS:
        for x in pts:
            if f in ("ln", "sqrt") and x <= 0:
                continue
            if f in ("exp", "sinh", "cosh") and abs(x) > 2000:
                continue
            lo, hi = rigorous(f, x, prec)
            yield f, x, x, lo, hi


def range_of(f, a, b, prec):
    """Rigorous bounds of the range of f over [a, b] (Fractions)."""
    la, ha = rigorous(f, a, prec)
    lb, hb = rigorous(f, b, prec)
    lo, hi = min(la, lb), max(ha, hb)
    if f == "cosh" and a < 0 < b:
        lo = Fraction(1)
    if f in ("sin", "cos"):
        with mpmath.workprec(3 * prec + 200):
            half_pi = mpmath.pi / 2
            j0 = int(mpmath.ceil(mpf(a.numerator) / a.denominator / half_pi))
            j1 = int(mpmath.floor(mpf(b.numerator) / b.denominator / half_pi))
        for j in range(j0, j1 + 1):
            r = j % 4
            if (f == "sin" and r == 1) or (f == "cos" and r == 0):
                hi = Fraction(1)
            if (f == "sin" and r == 3) or (f == "cos" and r == 2):
                lo = Fraction(-1)
    return lo, hi


def interval_cases(prec):
    ivs = [(0.5, 0.75), (-1.0, 2.0), (1.0, 2.0), (3.0, 3.5), (-0.3, 0.1), (10.0, 10.5),
           (1e-10, 1e-9), (4.0, 5.0), (100.0, 100.25), (-7.0, -6.0)]
    for f in FUNCS:
        for a, b in ivs:
            a, b = Fraction(a), Fraction(b)
            if f in ("ln", "sqrt") and a <= 0:
                continue
            if f == "tan":
                # no pole inside: skip intervals holding an odd multiple of pi/2
                with mpmath.workprec(200):
                    j0 = int(mpmath.ceil(mpf(float(a)) / (mpmath.pi / 2)))
                    j1 = int(mpmath.floor(mpf(float(b)) / (mpmath.pi / 2)))
                if any(j % 2 for j in range(j0, j1 + 1)):
                    continue
            lo, hi = range_of(f, a, b, prec)
            yield f, a, b, lo, hi


def main():
    out = sys.stdout
    for prec in (160, 256):
        digits = math.ceil(2 * prec * math.log10(2)) + 3
        for f, a, b, lo, hi in list(point_cases(prec)) + list(interval_cases(prec)):
            def end(v, up):
                if v in (Fraction(1), Fraction(-1)) or lo == hi:
                    return exact_decimal(v)
                return outward(v, digits, up)
            out.write(f"{f} {prec} {exact_decimal(a)} {exact_decimal(b)} "
                      f"{end(lo, False)} {end(hi, True)}\n")


if __name__ == "__main__":
    main()
