#!/usr/bin/env python3
"""Widths of the exact discrete objects, two builds side by side, on random pairs.

    python3 benches/exact_widths.py BIN_A BIN_B [N [SEED [PRECISION [COMMAND]]]]

draws N pairs (default 150; SEED 3; PRECISION 106; COMMAND step, or retract, lagrangian) on
six built-in scenes (particle, knife, knife-eps, sleigh, rolling-disk, contact-oscillator),
`h` from 0.01 to 1, and runs `COMMAND --precision PRECISION --json` with both binaries. With
`ON=1` each `q1` is the midpoint of the 53-bit flow of BIN_A from `q0` with a random `u` over
`h` (a pair on M_h^{e,nh} up to f64's rounding); otherwise `q1 = q0 + h w`, `w` random in
[-1, 1] (a pair off it). For each component answered by both, the ratio of B's width to A's
(the decimals read exactly); prints their count, geometric mean, largest and smallest, how many
are wider or narrower by more than 1%, the widest few, and any pair the two answer differently.
"""
import json
import math
import os
import random
import subprocess
import sys
from fractions import Fraction

SCENES = [("particle", 3), ("knife", 3), ("knife-eps", 3), ("sleigh", 3),
          ("rolling-disk", 4), ("contact-oscillator", 3)]


def widths(out):
    """Each `[lo, hi]` of the answer's arrays, by key and index: (width, magnitude)."""
    d = json.loads(out)
    res = {}
    for k in sorted(d):
        if not isinstance(d[k], list):
            continue
        for i, c in enumerate(d[k]):
            if isinstance(c, list) and len(c) == 2:
                lo, hi = Fraction(str(c[0])), Fraction(str(c[1]))
                res[f"{k}{i}"] = (hi - lo, max(abs(lo), abs(hi)))
    return res


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    a, b = sys.argv[1], sys.argv[2]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 150
    rnd = random.Random(int(sys.argv[4]) if len(sys.argv) > 4 else 3)
    prec = sys.argv[5] if len(sys.argv) > 5 else "106"
    cmd = sys.argv[6] if len(sys.argv) > 6 else "step"
    on = os.environ.get("ON") == "1"
    ratios, wider, differ, both = [], [], [], 0
    for _ in range(n):
        name, dim = rnd.choice(SCENES)
        h = float(f"{rnd.choice([0.01, 0.05, 0.1, 0.25, 0.5]) * (1 + rnd.random()):.6g}")
        q0 = [round(rnd.uniform(-1, 1), 6) for _ in range(dim)]
        if name == "contact-oscillator":
            q0[0] = round(rnd.uniform(0.5, 1.5), 6)
        q1 = [repr(round(x + h * rnd.uniform(-1, 1), 6)) for x in q0]
        if on:
            u = [repr(round(rnd.uniform(-1, 1), 6)) for _ in range(2)]
            fl = subprocess.run([a, "flow", "--scene", name, "--q", ",".join(map(repr, q0)),
                                 "--u", ",".join(u), "--t", repr(h), "--json"],
                                capture_output=True, text=True, check=False)
            if fl.returncode != 0:
                continue
            q1 = [repr((lo + hi) / 2) for lo, hi in json.loads(fl.stdout)["q"][:dim]]
        args = [cmd, "--scene", name, "--q0", ",".join(map(repr, q0)), "--q1", ",".join(q1),
                "--h", repr(h), "--precision", prec, "--json"]
        ra = subprocess.run([a, *args], capture_output=True, text=True, check=False)
        rb = subprocess.run([b, *args], capture_output=True, text=True, check=False)
        if ra.returncode != rb.returncode:
            differ.append((" ".join(args), ra.returncode, rb.returncode))
            continue
        if ra.returncode != 0:
            continue
        both += 1
        wa, wb = widths(ra.stdout), widths(rb.stdout)
        for k, (x, mag) in wa.items():
            if x > 0:
                r = float(wb[k][0] / x)
                ratios.append(r)
                if r > 1.01:
                    wider.append((r, k, float(x / mag) if mag else 0.0, " ".join(args)))
    logs = [math.log(r) for r in ratios if r > 0]
    print(f"{cmd} at {prec} bits, {'on' if on else 'off'} M_h: {n} pairs, {both} answered by "
          f"both, {len(ratios)} components; width B / A: geometric mean "
          f"{math.exp(sum(logs) / len(logs)) if logs else float('nan'):.3f}, largest "
          f"{max(ratios, default=float('nan')):.3g}, smallest {min(ratios, default=float('nan')):.3g}; "
          f"wider by >1%: {len(wider)}, narrower by >1%: {sum(r < 0.99 for r in ratios)}")
    for r, k, rel, line in sorted(wider, reverse=True)[:5]:
        print(f"  {r:.2f}x wider: {k} (A {rel:.1e} relative) of {line}")
    for line, ca, cb in differ[:10]:
        print(f"  answered differently (exit {ca} against {cb}): {line}")


if __name__ == "__main__":
    main()
