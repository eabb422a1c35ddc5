#!/usr/bin/env python3
"""Validate a scheme written in Python on the contact oscillator, with the `dalembert` package.

The scene `contact-oscillator` (spec (3.8)): q = (x, y, z),
L = |qd|^2 / 2 - V,  V = (x^2 + y^2 + z^2 + eps x^2 z^2) / 2,  constraint xd + y zd = 0,
mu = (1, 0, y). The scheme (written below, ~10 lines) is a Stormer-Verlet step with DLA's
midpoint discrete constraint:
    q2 = 2 q1 - q0 - h^2 grad V(q1) + c mu(q1),   mu((q1 + q2) / 2) . (q2 - q1) = 0,
explicit here because mu depends on y only and y2 does not depend on c. Its one-step error
against the exact discrete flow is O(h^3) (the midpoint constraint is centred at 3h/2, not
at q1; spec (7.9)), so the observed local order tends to 3 and the global order to 2.

What the oracle certifies: (1) per step, for a trajectory of 200 steps (one `check` query):
the distance of each q_k to the exact discrete flow from (q_0, q_1), each pair's defect
(its distance from M_h^{e,nh}) and the energy error; (2) the one-step error on a ladder of h
(`step` queries) and the observed order between successive rungs, as certified intervals.
The script asserts them and prints `ok`.

Usage: validate_scheme.py [path/to/dalembert]   (default: $DALEMBERT, or `dalembert` on PATH)
"""
import sys

from dalembert import Oracle, distance, observed_order

EPS = 0.3  # the scene's default parameter


def scheme(q0, q1, h):
    x, y, z = q1
    grad = [x + EPS * x * z * z, y, z + EPS * x * x * z]
    w = [b - a - h * h * g for a, b, g in zip(q0, q1, grad)]  # q2 - q1 with c = 0
    ym = y + w[1] / 2                                        # (y1 + y2) / 2
    c = -(w[0] + ym * w[2]) / (1 + ym * y)                   # mu(ym) . (w + c mu(y)) = 0
    return [x + w[0] + c, y + w[1], z + w[2] + c * y]


def main():
    q0, u, tol = [0.1, 0.2, 0.3], [0.5, 0.5], 1e-3
    with Oracle(sys.argv[1] if len(sys.argv) > 1 else None, scene="contact-oscillator") as o:
        # (1) per-step certified verdicts on 200 steps of h = 0.05
        h = 0.05
        q = [q0, [iv.mid for iv in o.flow(q0, u, h).q]]  # q1: a float point of the exact motion
        while len(q) < 201:
            q.append(scheme(q[-2], q[-1], h))
        c = o.check(q, h, tol=tol)
        for k in range(0, 200, 40):
            print(f"k={k:3}  |q_k - exact| in {c.distance[k]}  defect {c.defect[k][0]}")
        assert c.passed and c.max_distance.hi <= tol                 # proved within tol
        assert all(d[0].excludes_zero() for d in c.defect[1:])       # proved off M_h^{e,nh}
        assert all(-1e-4 < e.lo and e.hi < 1e-4 for e in c.energy_error)
        # (2) one-step error against the exact discrete flow, and the observed order
        hs = [2.0 ** -k for k in range(2, 10)]
        errs = []
        for h in hs:
            q1 = [iv.mid for iv in o.flow(q0, u, h).q]
            errs.append(distance(scheme(q0, q1, h), o.step(q0, q1, h).q2))
        orders = [observed_order(*errs[i:i + 2], *hs[i:i + 2]) for i in range(len(hs) - 1)]
        for h, e, p in zip(hs[1:], errs[1:], orders):
            print(f"h={h:<10} error in {e}  observed order in {p}")
        assert 2.9 < orders[-1].lo and orders[-1].hi < 3.1, orders[-1]
    print("ok")


if __name__ == "__main__":
    main()
