#!/usr/bin/env python3
"""Reference states and exact discrete objects for the tests of answers computed with more than
106 bits (tests/it/precision_wide.rs): the knife's and the particle's closed-form flows
(flow_reference.py) and the particle's retraction, exact step and exact discrete Lagrangian
(exact_reference.py), evaluated by mpmath at 300 decimal digits from the exact f64 inputs.

    python3 tests/data/wide_reference.py > tests/data/wide_reference.txt   (needs mpmath)

Each line: `flow` scene q u t, `decimal knife` q u t (the decimals read exactly, for
`--exact-decimals`), or `exact` q0 q1 h (exact f64 values, Python's repr), then each
quantity (the flow's q, u, v; the exact objects' u0, s, q2, l as in exact_reference.py) as two
decimals `lo hi`: the value minus and plus 1e-250 max(1, |value|), each printed with 280
significant digits (so the printing moves it by far less than 1e-250 |value|). Under the
assumption that mpmath's elementary functions are accurate to 260 digits at 300, each pair
brackets the exact quantity, and it is about 2^-830 wide relative: far below the 512-bit answers
it is compared with. A quantity that is itself a short binary number (phi = phi0 + w t, w: sums
and products of a few doubles, exact in mpmath's 997 bits) is given as its exact decimal, twice.
"""
import decimal
import os
import sys

import mpmath as mp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import exact_reference  # noqa: E402
import flow_reference  # noqa: E402

DPS = 300

FLOWS = [
    ("knife", (0.0, 0.0, 0.0), (0.8, 0.8), 0.5),
    ("knife", (0.0, 0.0, 0.0), (0.8, 0.8), 5.0),
    ("knife", (0.0, 0.0, 0.0), (0.8, 0.8), -5.0),
    ("knife", (0.3, -1.2, 2.5), (-0.7, 1.9), 7.0),
    ("knife", (0.0, 0.0, 0.0), (0.8, 0.8), 50.0),
    ("particle", (0.0, 0.0, 0.0), (0.8, 0.8), 0.5),
    ("particle", (0.2, -0.5, 1.0), (-1.1, 0.3), 20.0),
]


DECIMAL_FLOWS = [
    ("0.1,0.2,0.3", "0.7,0.9", "5"),
]


def exact_decimal(v):
    """The exact decimal of a binary number of mpmath (sign, man, exp, bc)."""
    sign, man, exp, _ = v._mpf_
    with decimal.localcontext() as c:
        c.prec = 2000
        d = decimal.Decimal(man) * decimal.Decimal(2) ** exp
    return ("-" if sign else "") + format(d, "e")


def brackets(vals):
    out = []
    for v in vals:
        # A sum or product of a few doubles (phi = phi0 + w t, w, yd0) is exact in mpmath's
        # 997 bits (at most a few hundred significant bits): it is given as that point.
        if v._mpf_[3] <= 300:
            out += [exact_decimal(v)] * 2
            continue
        r = mp.mpf(10) ** -250 * max(1, abs(v))
        out += [mp.nstr(v - r, 280, min_fixed=1, max_fixed=0),
                mp.nstr(v + r, 280, min_fixed=1, max_fixed=0)]
    return out


def main():
    mp.mp.dps = DPS
    nums = lambda xs: ",".join(repr(float(x)) for x in xs)
    for scene, q, u, t in FLOWS:
        vals = (flow_reference.knife if scene == "knife" else flow_reference.particle)(q, u, t)
        print("flow", scene, nums(q), nums(u), repr(float(t)), *brackets(vals))
    # decimal inputs read as exact decimals (flow --exact-decimals): the same closed form from
    # the decimals themselves (mpmath reads a string at its 300 digits)
    for q, u, t in DECIMAL_FLOWS:
        vals = flow_reference.knife(q.split(","), u.split(","), t)
        print("decimal knife", q, u, t, *brackets(vals))
    for q0, q1, h in exact_reference.CASES:
        print("exact", nums(q0), nums(q1), repr(float(h)),
              *brackets(exact_reference.retraction(q0, q1, h)))


if __name__ == "__main__":
    main()
