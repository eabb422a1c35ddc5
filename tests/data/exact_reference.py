#!/usr/bin/env python3
"""Reference retractions, exact steps and exact discrete Lagrangians of the particle from its closed
form, evaluated by mpmath at 100 digits from the exact f64 inputs, for the tests of the exact
discrete objects computed with more than 53 bits (tests/it/precision_flow.rs).

    python3 tests/data/exact_reference.py > tests/data/exact_reference.txt   (needs mpmath)

The particle (q = (x, y, z), u = (xd, yd), constraint zd = y xd, N(q) = (-y, 0, 1)) flows as
y = y0 + yd0 t, x = x0 + k (asinh y - asinh y0), z = z0 + k (sqrt(1 + y^2) - sqrt(1 + y0^2)),
k = xd0 sqrt(1 + y0^2) / yd0 (tests/it/closed_forms.rs). The retraction solves
q(h) = Q1 + N(Q1) s: yd0 = (y1 - y0) / h, and with A = asinh y1 - asinh y0,
B = sqrt(1 + y1^2) - sqrt(1 + y0^2): k (A + y1 B) = x1 - x0 + y1 (z1 - z0), s = k B - (z1 - z0),
xd0 = k yd0 / sqrt(1 + y0^2). The step's q2 is the flow at 2h. The Lagrangian
L = (xd^2 + yd^2 + zd^2) / 2 = (xd0^2 (1 + y0^2) + yd0^2) / 2 is constant along the flow
(xd sqrt(1 + y^2) is), so l = h L.

Each line: q0, q1, h (exact f64 values), then u0 (2), s (1), q2 (3), l (1): 7 quantities, each as
four doubles `lo_hi lo_lo up_hi up_lo` in Python's hex form bracketing it exactly (as in
flow_reference.py: the value -+ 1e-80 max(1, |value|), or the value itself when it is a
double-double number).
"""
import os
import sys

import mpmath as mp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from flow_reference import bounds  # noqa: E402  (the same exact double-double bounds)

mp.mp.dps = 100


def retraction(q0, q1, h):
    x0, y0, z0 = (mp.mpf(v) for v in q0)
    x1, y1, z1 = (mp.mpf(v) for v in q1)
    h = mp.mpf(h)
    yd0 = (y1 - y0) / h
    r0, r1 = mp.sqrt(1 + y0 ** 2), mp.sqrt(1 + y1 ** 2)
    a, b = mp.asinh(y1) - mp.asinh(y0), r1 - r0
    k = (x1 - x0 + y1 * (z1 - z0)) / (a + y1 * b)
    s = k * b - (z1 - z0)
    xd0 = k * yd0 / r0
    y2 = y0 + 2 * h * yd0
    r2 = mp.sqrt(1 + y2 ** 2)
    q2 = [x0 + k * (mp.asinh(y2) - mp.asinh(y0)), y2, z0 + k * (r2 - r0)]
    lag = h * (xd0 ** 2 * r0 ** 2 + yd0 ** 2) / 2
    return [xd0, yd0, s] + q2 + [lag]


CASES = [
    ((0.0, 0.0, 0.0), (0.4, 0.4, 0.0), 0.5),
    ((0.1, -0.3, 0.2), (0.35, -0.1, 0.18), 0.25),
    ((1.0, 2.0, -1.0), (1.01, 2.02, -0.98), 0.01),
    ((0.0, 0.5, 0.0), (0.3, 0.9, 0.2), 0.4),
]


def main():
    nums = lambda xs: ",".join(repr(float(x)) for x in xs)
    for q0, q1, h in CASES:
        print(nums(q0), nums(q1), repr(float(h)), *bounds(retraction(q0, q1, h)))


if __name__ == "__main__":
    main()
