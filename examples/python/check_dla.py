#!/usr/bin/env python3
"""A Python DLA step for the nonholonomic particle, checked against the dalembert oracle.

The oracle is used through `dalembert batch` (JSON lines in, JSON lines out), so nothing
here links Rust. For each step size h the script takes one DLA step (q0, q1) -> q2 and asks
the oracle for the exact discrete flow from the same pair: `step` returns certified
enclosures of q(2h) on the exact trajectory through (q0, q1 moved onto M_h^{e,nh}).
The certified distance |q2_dla - q(2h)| must be small and shrink like h^3 (local error of a
second-order scheme). Exit status 0 when every check passes.

Usage: check_dla.py [path/to/dalembert]     (default: `dalembert` on PATH, or $DALEMBERT)
"""
import json
import os
import subprocess
import sys


def dla_particle_step(q0, q1, h):
    """DLA (midpoint L_d, M_h^d) for the particle, solved by hand.

    D*-projected equations at q1 with e1 = (1, 0, y1), e2 = (0, 1, 0), L = |v|^2/2:
      y2 = 2 y1 - y0,
      (x1 - x0) + y1 (z1 - z0) = (x2 - x1) (1 + y1 (y1 + y2) / 2),
      z2 = z1 + (y1 + y2) / 2 (x2 - x1)              (the discrete constraint M_h^d).
    """
    (x0, y0, z0), (x1, y1, z1) = q0, q1
    y2 = 2 * y1 - y0
    x2 = x1 + ((x1 - x0) + y1 * (z1 - z0)) / (1 + y1 * (y1 + y2) / 2)
    z2 = z1 + (y1 + y2) / 2 * (x2 - x1)
    return [x2, y2, z2]


class Oracle:
    def __init__(self, exe):
        self.p = subprocess.Popen([exe, "batch"], stdin=subprocess.PIPE,
                                  stdout=subprocess.PIPE, text=True)
        self.n = 0

    def ask(self, query):
        self.n += 1
        query = dict(query, id=self.n)
        self.p.stdin.write(json.dumps(query) + "\n")
        self.p.stdin.flush()
        answer = json.loads(self.p.stdout.readline())
        assert answer["id"] == self.n, answer
        if "error" in answer:
            raise RuntimeError(answer["error"]["message"])
        return answer["ok"]

    def close(self):
        self.p.stdin.close()
        return self.p.wait()


def distance_upper(x, box):
    """Upper bound of max_i |x_i - b_i| over the box (plain floats: an estimate of the
    certified bound, off by at most a few ulps; fine for a test tolerance)."""
    return max(max(abs(xi - lo), abs(xi - hi)) for xi, (lo, hi) in zip(x, box))


def main():
    exe = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("DALEMBERT", "dalembert")
    oracle = Oracle(exe)
    q0 = [0.0, 0.0, 0.0]
    u = [0.8, 0.8]                     # quasi-velocities: xd = 0.8, yd = 0.8, zd = y xd
    errors = []
    for h in [0.2, 0.1, 0.05, 0.025]:
        # q1 on the exact trajectory (so the pair is on M_h^{e,nh} up to rounding)
        f = oracle.ask({"cmd": "flow", "scene": "particle", "q": q0, "u": u, "t": h})
        q1 = [(lo + hi) / 2 for lo, hi in f["q"]]
        q2 = dla_particle_step(q0, q1, h)
        s = oracle.ask({"cmd": "step", "scene": "particle", "q0": q0, "q1": q1, "h": h})
        err = distance_upper(q2, s["q2"])
        width = max(hi - lo for lo, hi in s["q2"])
        errors.append(err)
        print(f"h = {h:<6} |q2_dla - q(2h)| <= {err:.3e}   (oracle width {width:.1e})")
    # a malformed query gets an error answer and the stream goes on
    try:
        oracle.ask({"cmd": "step", "scene": "particle", "q0": [0, 0], "q1": q1, "h": 0.1})
        raise SystemExit("a wrong dimension was accepted")
    except RuntimeError as e:
        print(f"bad query answered with an error: {e}")
    assert oracle.close() == 0
    ratios = [a / b for a, b in zip(errors, errors[1:])]
    print("ratios as h halves:", ", ".join(f"{r:.2f}" for r in ratios))
    assert errors[0] < 1e-2, errors
    # local error of a second-order scheme is O(h^3): ratio 8; accept anything above 5
    assert all(r > 5.0 for r in ratios), ratios
    print("ok")


if __name__ == "__main__":
    main()
