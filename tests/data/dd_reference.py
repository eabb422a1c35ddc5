#!/usr/bin/env python3
"""Independent references for the double-double intervals (src/precision/dd*.rs).

Writes tests/data/dd_reference.txt, read by tests/it/precision_dd.rs. Every value is computed
with mpmath at 3000 bits (far beyond the 106 bits tested) and written as two exact expansions
of four doubles, L = l1 + l2 + l3 + l4 <= exact <= U = u1 + u2 + u3 + u4, where l4 (u4) is the
remainder rounded down (up) to a double, checked exactly; so the Rust test can compare its
interval ends with L and U exactly (no rounding), and U - L is about 2^-200 relative.

Line format (all numbers are the hex bits of doubles):
  op  a_hi a_lo  b_hi b_lo  |  l1 l2 l3 l4  |  u1 u2 u3 u4  |  tol
where op is a binary operation (add sub mul div: x = a, y = b), a unary function of the point
a (b = 0), a unary function over the interval [a, b] (op ends in _iv), or a constant (const_*).
tol is the allowed width in units of 2^-104 relative to |value| (see the Rust test).

Run: python3 -m venv /tmp/mpv && /tmp/mpv/bin/pip install mpmath
     /tmp/mpv/bin/python tests/data/dd_reference.py > tests/data/dd_reference.txt
"""
import math
import random
import struct

from mpmath import mp, mpf

mp.prec = 3000
random.seed(20261128)


def bits(x):
    return "%016x" % struct.unpack("<Q", struct.pack("<d", x))[0]


def rd(x):
    """The largest double <= x (exact, by comparison)."""
    d = float(x)
    while mpf(d) > x:
        d = math.nextafter(d, -math.inf)
    while mpf(math.nextafter(d, math.inf)) <= x:
        d = math.nextafter(d, math.inf)
    return d


def ru(x):
    return -rd(-x)


def expansion(v, down):
    parts = []
    r = v
    for _ in range(3):
        p = float(r)
        parts.append(p)
        r = r - mpf(p)
    parts.append(rd(r) if down else ru(r))
    return parts


def two_sum(a, b):
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def dd(hi, lo=0.0):
    return two_sum(hi, lo)


def ddval(p):
    return mpf(p[0]) + mpf(p[1])


def rand_dd(lo_exp, hi_exp):
    """A random normalised double-double with leading exponent in [lo_exp, hi_exp]."""
    h = random.choice([-1, 1]) * random.uniform(1, 2) * 2.0 ** random.randint(lo_exp, hi_exp)
    l = h * 2.0 ** -53 * random.uniform(-0.5, 0.5)
    return dd(h, l)


def nearest_dd(c):
    h = float(c)
    return dd(h, float(c - mpf(h)))


lines = []


def emit(op, a, b, lo, hi, tol):
    L = expansion(lo, True)
    U = expansion(hi, False)
    assert sum(mpf(x) for x in L) <= lo and sum(mpf(x) for x in U) >= hi
    lines.append(" ".join([op, bits(a[0]), bits(a[1]), bits(b[0]), bits(b[1]), "|"] + [bits(x) for x in L] + ["|"] + [bits(x) for x in U] + ["|", str(tol)]))


ZERO = (0.0, 0.0)

# Constants.
for name, c in [("const_pi", mp.pi), ("const_frac_pi_2", mp.pi / 2), ("const_ln2", mp.log(2))]:
    emit(name, ZERO, ZERO, c, c, 2)

# Arithmetic on points.
binary = {
    "add": lambda x, y: x + y,
    "sub": lambda x, y: x - y,
    "mul": lambda x, y: x * y,
    "div": lambda x, y: x / y,
}
for op, f in binary.items():
    cases = [(rand_dd(-20, 20), rand_dd(-20, 20)) for _ in range(25)]
    cases += [(rand_dd(-300, 300), rand_dd(-300, 300)) for _ in range(5)]
    a = rand_dd(0, 0)
    cases.append((a, dd(-a[0], -a[1] * 0.75)))  # cancellation
    cases.append((dd(1.0, 2.0 ** -60), dd(1.0, 2.0 ** -61)))
    cases.append((dd(3.0), dd(7.0)))
    cases.append((dd(1e-300, 1e-317), dd(1e-20)))
    cases.append((dd(1e300), dd(1e-7)))
    for a, b in cases:
        v = f(ddval(a), ddval(b))
        emit(op, a, b, v, v, 4)

unary_points = {
    "sqrt": (mp.sqrt, [dd(2.0), dd(1e-310), dd(1e300), dd(0.25)] + [(abs(x[0]), abs(x[0]) * 0 + x[1] * (1 if x[0] > 0 else -1)) for x in [rand_dd(-30, 30) for _ in range(12)]], 4),
    "exp": (mp.exp, [dd(1.0), dd(-1.0), dd(1e-300), dd(2.0 ** -30), dd(709.7), dd(-708.0), dd(-745.0), dd(-740.0), dd(0.5), nearest_dd(mp.log(2))] + [rand_dd(-10, 9) for _ in range(14)], 16),
    "ln": (mp.log, [dd(2.0), dd(10.0), dd(1e-310), dd(1.7e308), dd(1.0, 2.0 ** -70), dd(1.0 - 2.0 ** -50), dd(0.5), nearest_dd(mp.e)] + [(abs(x[0]), x[1] if x[0] > 0 else -x[1]) for x in [rand_dd(-300, 300) for _ in range(12)]], 16),
    "atan": (mp.atan, [dd(1.0), dd(1e300), dd(1e-300), dd(-0.5), dd(2.0 ** 60), dd(0.1)] + [rand_dd(-10, 10) for _ in range(12)], 16),
    "sinh": (mp.sinh, [dd(1.0), dd(1e-300), dd(1e-5), dd(0.5), dd(-0.75), dd(710.0), dd(-709.0), dd(20.0)] + [rand_dd(-10, 5) for _ in range(10)], 16),
    "cosh": (mp.cosh, [dd(1.0), dd(1e-300), dd(1e-5), dd(0.5), dd(-0.75), dd(710.0), dd(-709.0), dd(20.0)] + [rand_dd(-10, 5) for _ in range(10)], 16),
    "tanh": (mp.tanh, [dd(1.0), dd(1e-300), dd(1e-5), dd(0.5), dd(-0.75), dd(20.0), dd(-100.0), dd(0.3)] + [rand_dd(-10, 4) for _ in range(10)], 16),
    "asinh": (mp.asinh, [dd(1.0), dd(1e-300), dd(1e-10), dd(0.3), dd(0.36), dd(-5.0), dd(1e10), dd(1e100), dd(2.0 ** 61)] + [rand_dd(-10, 30) for _ in range(10)], 16),
}
trig_args = [dd(1.0), dd(-1.0), dd(1e-300), dd(5e-324), dd(float(mp.pi)), nearest_dd(mp.pi), dd(float(mp.pi / 2)), nearest_dd(mp.pi / 2),
             dd(1e22), dd(2.0 ** 60), dd(1e300), dd(-1e300), dd(0.785), dd(0.786), nearest_dd(3 * mp.pi / 2), nearest_dd(mp.pi * 1000),
             dd(float(mp.pi) * 2 ** 40)] + [rand_dd(-5, 5) for _ in range(10)]
unary_points["sin"] = (mp.sin, trig_args, 16)
unary_points["cos"] = (mp.cos, trig_args, 16)
unary_points["tan"] = (mp.tan, trig_args, 24)
for op, (f, args, tol) in unary_points.items():
    for a in args:
        v = f(ddval(a))
        emit(op, a, ZERO, v, v, tol)


# Intervals: [a, b] with a <= b; the exact range computed from the critical points.
def trig_range(f, a, b, maxat, minat):
    """Range of f (sin or cos) on [a, b]; maxat/minat: residues of j mod 4 with f(j pi/2) = +-1."""
    lo = min(f(a), f(b))
    hi = max(f(a), f(b))
    j0 = int(mp.ceil(a / (mp.pi / 2)))
    j1 = int(mp.floor(b / (mp.pi / 2)))
    for j in range(j0, j1 + 1):
        if j % 4 == maxat:
            hi = mpf(1)
        if j % 4 == minat:
            lo = mpf(-1)
    return lo, hi


iv_cases = [(1.0, 2.0), (-1.0, 2.0), (3.0, 4.0), (-0.5, 0.25), (2.0 ** 60, 2.0 ** 60 + 2048), (4.0, 6.5), (1e22, 1e22 + 2 ** 21),
            (1.0, 5.0), (-3.0, 2.5), (-1.5, 1.6), (2.0, 8.0)]
for a, b in iv_cases:
    A, B = mpf(a), mpf(b)
    lo, hi = trig_range(mp.sin, A, B, 1, 3)
    emit("sin_iv", dd(a), dd(b), lo, hi, 16)
    lo, hi = trig_range(mp.cos, A, B, 0, 2)
    emit("cos_iv", dd(a), dd(b), lo, hi, 16)
for a, b in [(-1.0, 1.0), (0.5, 2.0), (-700.0, 1.0)]:
    emit("exp_iv", dd(a), dd(b), mp.exp(a), mp.exp(b), 16)
for a, b in [(0.5, 2.0), (1e-300, 1e300)]:
    emit("ln_iv", dd(a), dd(b), mp.log(a), mp.log(b), 16)
for a, b in [(1.0, 1.5), (-1.0, 1.0), (3.0, 4.0)]:
    emit("tan_iv", dd(a), dd(b), mp.tan(a), mp.tan(b), 24)
for a, b in [(-2.0, 3.0), (0.5, 1.0)]:
    emit("atan_iv", dd(a), dd(b), mp.atan(a), mp.atan(b), 16)
    emit("sinh_iv", dd(a), dd(b), mp.sinh(a), mp.sinh(b), 16)
    emit("tanh_iv", dd(a), dd(b), mp.tanh(a), mp.tanh(b), 16)
    emit("asinh_iv", dd(a), dd(b), mp.asinh(a), mp.asinh(b), 16)
emit("cosh_iv", dd(-2.0), dd(3.0), mpf(1), mp.cosh(3), 16)
emit("cosh_iv", dd(0.5), dd(1.0), mp.cosh(0.5), mp.cosh(1), 16)
emit("sqrt_iv", dd(-1.0), dd(4.0), mpf(0), mpf(2), 4)
emit("sqrt_iv", dd(2.0), dd(3.0), mp.sqrt(2), mp.sqrt(3), 6)

print("# Generated by tests/data/dd_reference.py (mpmath %s, 3000 bits); do not edit." % __import__("mpmath").__version__)
print("\n".join(lines))
