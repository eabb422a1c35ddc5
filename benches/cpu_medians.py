#!/usr/bin/env python3
"""CPU time of whole `dalembert` processes, several builds side by side.

    python3 benches/cpu_medians.py N BIN_A BIN_B ...

runs each case below N times with every binary in turn (interleaved, so that a change in
the machine's load falls on all of them alike) and prints, per case, the median CPU time
(user + system, from getrusage) of each binary in ms and its ratio to the first one. The
cases are the flows of docs/peers.md and docs/benchmarks.md, with and without --jacobian.
`CASES=word1;word2` keeps the cases whose command line contains one of the words.
`SET=precision` runs instead the knife (T = 50) and the trailer (T = 2) of docs/precision.md at
106, 160, 256 and 512 bits, and the knife at 1024; `SET=exact` the exact step, retraction and
discrete Lagrangian at 106 bits of docs/precision.md's sixth round.
"""
import os
import resource
import statistics
import subprocess
import sys

CASES = [
    "flow --scene rolling-disk --q 0,0,0,0 --u 1.2,0.7 --t 50",
    "flow --scene sleigh --q 0,0,0 --u 0.3,1 --t 50",
    "flow --scene rolling-disk --q 0,0,0,0 --u 1.2,0.7 --t 0.5",
    "flow --scene sleigh --q 0,0,0 --u 0.3,1 --t 0.5",
    "flow --scene particle --q 0,0,0 --u 0.8,0.8 --t 0.5",
    "flow --scene knife --q 0,0,0 --u 0.8,0.8 --t 0.5",
    "flow --scene knife --q 0,0,0 --u 0.8,0.8 --t 50",
    "flow --scene particle --q 0,0,0 --u 0.8,0.8 --t 50",
    "flow --scene contact-oscillator --q 1,0.5,0.2 --u 0.3,0.4 --t 0.5",
    "flow --scene contact-oscillator --q 1,0.5,0.2 --u 0.3,0.4 --t 50",
    "flow --scene contact-oscillator-nr --q 1,0.5,0.2 --u 0.3,0.4 --t 0.5",
    "flow --scene particle --q 0,0,0 --u 0.8,0.8 --t 10 --jacobian",
    "flow --scene particle --q 0,0,0 --u 0.8,0.8 --t 50 --jacobian",
    "flow --scene particle --q 0,0,0 --u 0.8,0.8 --t 600 --jacobian",
    "flow --scene knife --q 0,0,0 --u 0.8,0.8 --t 50 --jacobian",
    "flow --scene knife --q 0,0,0 --u 0.8,0.8 --t 600 --jacobian",
    "flow --scene knife-eps --q 0,0,0 --u 0.8,0.8 --t 600 --jacobian",
    "flow --scene particle --q 0,0,0 --u 0.8,0.8 --t 600",
    "flow --scene knife --q 0,0,0 --u 0.8,0.8 --t 600",
    "flow --scene knife-eps --q 0,0,0 --u 0.8,0.8 --t 600",
    "flow --scene contact-oscillator --param eps=2 --q 0.5,-0.5,1 --u 1,-1 --t 20",
    "flow --scene sleigh --q 0,0,0 --u 0.8,0.8 --t 20",
]

PRECISION_CASES = [
    f"flow --scene knife --q 0,0,0 --u 0.8,0.8 --t 50 --precision {bits}"
    for bits in [106, 160, 256, 512, 1024]
] + [
    f"flow --scene-file examples/scenes/trailer.toml --q 0,0,0,0 --u 1,0.3 --t 2 --precision {bits}"
    for bits in [106, 160, 256, 512]
]

EXACT_CASES = [
    "step --scene knife --q0 0,0,0 --q1 0.1,0.05,0.01 --h 0.1 --precision 106",
    "retract --scene knife --q0 0,0,0 --q1 0.3,0.1,0.1 --h 0.5 --precision 106",
    "step --scene sleigh --q0 0,0,0 --q1 0.05,0.1,0.02 --h 0.1 --precision 106",
    "step --scene rolling-disk --q0 0,0,0,0 --q1 0.1,0.05,0.1,0.05 --h 0.1 --precision 106",
    "step --scene contact-oscillator --q0 1,0.5,0.2 --q1 1.03,0.54,0.2 --h 0.1 --precision 106",
    "lagrangian --scene knife --q0 0,0,0 --q1 0.1,0.05,0.01 --h 0.1 --precision 106",
]


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    n, bins = int(sys.argv[1]), sys.argv[2:]
    cases = {"precision": PRECISION_CASES, "exact": EXACT_CASES}.get(os.environ.get("SET"), CASES)
    if os.environ.get("CASES"):
        words = os.environ["CASES"].split(";")
        cases = [c for c in cases if any(w in c for w in words)]
    times = {(c, b): [] for c in cases for b in bins}
    for _ in range(n):
        for c in cases:
            for b in bins:
                before = resource.getrusage(resource.RUSAGE_CHILDREN)
                subprocess.run([b, *c.split(), "--json"], stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL, check=False)
                after = resource.getrusage(resource.RUSAGE_CHILDREN)
                times[(c, b)].append(after.ru_utime - before.ru_utime
                                     + after.ru_stime - before.ru_stime)
    for c in cases:
        med = [statistics.median(times[(c, b)]) for b in bins]
        ratios = " ".join(f"{m / med[0]:.3f}" for m in med[1:])
        print(f"{c.removeprefix('flow '):72s} " + " ".join(f"{m * 1e3:8.2f}" for m in med)
              + (f"  ratios {ratios}" if ratios else ""))


if __name__ == "__main__":
    main()
