#!/usr/bin/env python3
"""The longest step a Taylor polynomial of order p can take on the particle, remainder aside.

The particle's trajectory (spec eq. (3.2)) has y(t) = y0 + v t and u1 sqrt(1 + y^2) constant,
so u1(t) = c / sqrt(1 + (y0 + v t)^2), whose poles at y = +-i limit its Taylor series. This
script expands u1 about t = 0 to 50 digits (mpmath, independent of dalembert) and finds, by
bisection, the longest step s for which the terms the polynomial of order p drops,
sum_{k > p} |u1_k| s^k, stay under 2^-52 (the remainder tolerance of spec (5.8) at a state
of size 1). A validated step can be no longer than that, however tight its remainder.

    python3 examples/python/particle_step_limit.py

prints the step for the two flows of the exact step at h = 0.5 (the README pair
q0 = 0, q1 = (0.4, 0.4, 0.08)): the retraction's from y = 0 and the flow on to q(2h) from
y = 0.4, at orders 22, 28 and 36.
"""

import mpmath as mp

mp.mp.dps = 50
TERMS = 60


def limit(y0, v, u10, p):
    c = u10 * mp.sqrt(1 + y0**2)
    coeffs = mp.taylor(lambda t: c / mp.sqrt(1 + (y0 + v * t) ** 2), 0, TERMS)
    tol = mp.mpf(2) ** -52
    lo, hi = mp.mpf(0), mp.mpf(2)
    for _ in range(60):
        s = (lo + hi) / 2
        dropped = sum(abs(coeffs[k]) * s**k for k in range(p + 1, TERMS + 1))
        if dropped <= tol:
            lo = s
        else:
            hi = s
    return lo


def main():
    # the README pair's trajectory: u0 = (0.8212, 0.8) at y = 0 (its retraction), and at
    # t = h = 0.5, y = 0.4 with u1 = 0.8212 / sqrt(1 + 0.4^2)
    u10 = mp.mpf("0.8212")
    flows = [
        ("retraction's flow from y = 0", mp.mpf(0), mp.mpf("0.8"), u10),
        ("flow to q(2h) from y = 0.4", mp.mpf("0.4"), mp.mpf("0.8"), u10 / mp.sqrt(mp.mpf("1.16"))),
    ]
    for name, y0, v, u10 in flows:
        steps = ", ".join(f"order {p}: {float(limit(y0, v, u10, p)):.3f}" for p in (22, 28, 36))
        print(f"{name}: longest step {steps}")


if __name__ == "__main__":
    main()
