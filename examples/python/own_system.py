#!/usr/bin/env python3
"""Pose your own nonholonomic system from Python, inline, and use the oracle on it.

The system is not built into dalembert: a unicycle (a blade on a horizontal plane) with
mass m and moment of inertia J,

    L = m/2 (xd^2 + yd^2) + J/2 thetad^2,   constraint  -sin(theta) xd + cos(theta) yd = 0,

sent as a JSON object in the `scene` field of each `dalembert batch` query (the same keys
as a scene file; see the README, "Your own system"), here by the module
the `dalembert` Python package (`Oracle(scene=UNICYCLE)`). With free = ["x", "theta"] the basis of
D is derived: e1 = (1, tan theta, 0), e2 = (0, 0, 1), so u = (xd, thetad).

The script checks the certified answers against the closed form (speed along the blade
s = u1 / cos(theta0) and turning rate w = u2 are constant), then checks a Python
implementation of a first-order step against the exact discrete flow. Exit status 0 when
every check passes.

Usage: own_system.py [path/to/dalembert]     (default: $DALEMBERT, or `dalembert` on PATH)
"""
import math
import sys

from dalembert import Oracle, distance

UNICYCLE = {
    "name": "unicycle",
    "coordinates": ["x", "y", "theta"],
    "parameters": {"m": 2.0, "J": 0.75},
    "mass": [["m", 0, 0], [0, "m", 0], [0, 0, "J"]],
    "constraints": [["-sin(theta)", "cos(theta)", 0]],
    "free": ["x", "theta"],
}


def closed_form(q0, u, t):
    """The exact motion from q0 with quasi-velocities u (float evaluation)."""
    x0, y0, th0 = q0
    s, w = u[0] / math.cos(th0), u[1]
    th = th0 + w * t
    return [x0 + s / w * (math.sin(th) - math.sin(th0)),
            y0 - s / w * (math.cos(th) - math.cos(th0)), th]


def inside(x, iv, slack=0.0):
    return iv.lo - slack <= x <= iv.hi + slack


def main():
    oracle = Oracle(sys.argv[1] if len(sys.argv) > 1 else None, scene=UNICYCLE)

    # 1. The certified flow contains the closed form (up to the float error of evaluating
    #    the closed form here, a few 1e-16).
    q0, u, t = [0.2, -0.1, 0.3], [0.6, 0.9], 1.0  # theta stays below pi/2
    flow = oracle.flow(q0, u, t)
    ref = closed_form(q0, u, t)
    for i in range(3):
        assert inside(ref[i], flow["q"][i], 1e-14), (i, ref[i], flow["q"][i])
    print(f"flow to t = {t}: widths", [f"{b - a:.1e}" for a, b in flow["q"]])

    # 2. A pair taken from the exact motion lies on M_h^{e,nh} (defect ~ 0) ...
    h = 0.25
    q1 = closed_form(q0, u, h)
    r = oracle.retract(q0, q1, h)
    assert r["member"] == "possible", r
    assert all(abs(a) < 1e-14 and abs(b) < 1e-14 for a, b in r["defect"]), r["defect"]

    # ... and a user's first-order step q2 = 2 q1 - q0 (here in Python) is O(h^2) away
    # from the exact discrete flow; the oracle certifies by how much, for every h.
    errors = []
    for h in [0.2, 0.1, 0.05]:
        q1 = closed_form(q0, u, h)
        q2_user = [2 * b - a for a, b in zip(q0, q1)]
        exact = oracle.step(q0, q1, h).q2
        # |q2_user - q2_exact|_inf, certified lower bound (rounded downwards)
        lower = distance(q2_user, exact).lo
        errors.append(lower)
        print(f"h = {h}: certified |q2_user - q2_exact| >= {lower:.3e}")
    ratios = [errors[i] / errors[i + 1] for i in range(len(errors) - 1)]
    # the step is the central difference q'' = 0: its error is h^2 |q''| (ratio 4)
    assert all(3.5 < x < 4.5 for x in ratios), ratios
    print("ratios", [f"{x:.2f}" for x in ratios])
    assert oracle.close() == 0
    print("ok")


if __name__ == "__main__":
    main()
