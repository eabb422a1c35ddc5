#!/usr/bin/env python3
"""Reference states of the knife and the particle from their closed forms (tests/it/closed_forms.rs
derives them), evaluated with mpmath at 100 decimal digits from the exact f64 inputs, for the
tests of flows computed with more than 53 bits (tests/it/precision_flow.rs).

    python3 tests/data/flow_reference.py > tests/data/flow_reference.txt   (needs mpmath)

Each line: scene, q, u, t (as the exact f64 values, Python's repr), then the 8 components q, u, v
of the exact state, each as two double-double numbers `lo_hi lo_lo up_hi up_lo` (four doubles in
Python's exact hex form) with lo_hi + lo_lo <= value <= up_hi + up_lo exactly: the 100-digit value
minus and plus 1e-80 max(1, |value|) (mpmath's rounding error at this precision is far below
that), rounded outward to double-double sums and checked exactly in mpmath. So each pair is a
rigorous enclosure under the assumption that mpmath's elementary functions are accurate to 90
digits, and it is about 2^-150 wide relative: far below the 106-bit answers it is compared with.
A value that is itself a double-double number (phi = phi0 + w t, w: sums and products of a few
doubles, exact in mpmath's 332 bits) is given as that point.
"""
import math

import mpmath as mp

mp.mp.dps = 100


def knife(q, u, t):
    x0, y0, p0 = (mp.mpf(v) for v in q)
    s0, w = (mp.mpf(v) for v in u)
    t = mp.mpf(t)
    phi = p0 + w * t
    if w == 0:
        s = s0 + t * mp.cos(p0) / 2
        x = x0 + s0 * mp.cos(p0) * t + (mp.cos(p0) * t) ** 2 / 4
        y = y0 + s0 * mp.sin(p0) * t + mp.sin(p0) * mp.cos(p0) * t ** 2 / 4
    else:
        big_s = s0 - mp.sin(p0) / (2 * w)
        s = s0 + (mp.sin(phi) - mp.sin(p0)) / (2 * w)
        x = x0 + big_s * (mp.sin(phi) - mp.sin(p0)) / w \
            + (mp.sin(phi) ** 2 - mp.sin(p0) ** 2) / (4 * w ** 2)
        y = y0 + big_s * (mp.cos(p0) - mp.cos(phi)) / w + t / (4 * w) \
            - (mp.sin(2 * phi) - mp.sin(2 * p0)) / (8 * w ** 2)
    return [x, y, phi, s, w, s * mp.cos(phi), s * mp.sin(phi), w]


def particle(q, u, t):
    x0, y0, z0 = (mp.mpf(v) for v in q)
    xd0, yd0 = (mp.mpf(v) for v in u)
    t = mp.mpf(t)
    if yd0 == 0:
        return [x0 + xd0 * t, y0, z0 + y0 * xd0 * t, xd0, yd0, xd0, yd0, y0 * xd0]
    y = y0 + yd0 * t
    r0, r1 = mp.sqrt(1 + y0 ** 2), mp.sqrt(1 + y ** 2)
    k = xd0 / yd0 * r0
    xd = xd0 * r0 / r1
    return [x0 + k * (mp.asinh(y) - mp.asinh(y0)), y, z0 + k * (r1 - r0), xd, yd0, xd, yd0, y * xd]


CASES = [
    ("knife", (0.0, 0.0, 0.0), (0.8, 0.8), 0.5),
    ("knife", (0.0, 0.0, 0.0), (0.8, 0.8), 5.0),
    ("knife", (0.0, 0.0, 0.0), (0.8, 0.8), 50.0),
    ("knife", (0.0, 0.0, 0.0), (0.8, 0.8), -5.0),
    ("knife", (0.3, -1.2, 2.5), (-0.7, 1.9), 7.0),
    ("knife", (1e-3, 2.0, -0.4), (0.25, 0.0), 3.0),
    ("knife", (0.0, 0.0, 1.5707963267948966), (1.0, 1e-3), 10.0),
    ("particle", (0.0, 0.0, 0.0), (0.8, 0.8), 0.5),
    ("particle", (0.0, 0.0, 0.0), (0.8, 0.8), 50.0),
    ("particle", (0.2, -0.5, 1.0), (-1.1, 0.3), 20.0),
    ("particle", (0.5, 2.0, -1.0), (0.25, 0.0), 3.0),
]


def dd_bound(v, up):
    """Doubles (hi, lo) with hi + lo <= v (>= v when `up`), hi + lo within a few 2^-160 |v|."""
    hi = float(v)
    lo = float(v - mp.mpf(hi))
    while (mp.mpf(hi) + mp.mpf(lo) > v) if not up else (mp.mpf(hi) + mp.mpf(lo) < v):
        lo = math.nextafter(lo, math.inf if up else -math.inf)
    return hi, lo


def bounds(vals):
    """The four hex doubles `lo_hi lo_lo up_hi up_lo` of each value (see the module text)."""
    eps = mp.mpf(10) ** -80
    ends = []
    for v in vals:
        # A sum or product of a few doubles (phi = phi0 + w t, w, yd0) is exact in mpmath's
        # 332 bits; when it is a double-double number it is given as the point itself.
        hi = float(v)
        exact = mp.mpf(hi) + mp.mpf(float(v - mp.mpf(hi))) == v
        r = 0 if exact else eps * max(1, abs(v))
        for x in dd_bound(v - r, False) + dd_bound(v + r, True):
            ends.append(x.hex())
    return ends


def main():
    nums = lambda xs: ",".join(repr(float(x)) for x in xs)
    for scene, q, u, t in CASES:
        vals = (knife if scene == "knife" else particle)(q, u, t)
        print(scene, nums(q), nums(u), repr(float(t)), *bounds(vals))


if __name__ == "__main__":
    main()
