#!/usr/bin/env python3
"""Throughput of the Python API against `dalembert batch` alone, on the same 3,000 particle
`step` queries (issue 38: the API adds at most 20 % to batch's time, whether the queries are
sent as one list or one at a time).

    python3 benches/python_throughput.py [--n 3000] [--reps 15] [--pin] [--sync] [--binary PATH]

Variants, run in turn (batch, list, submit, batch, list, submit, ...) so that a change of
load on the machine falls on all of them alike; every run includes the process start:
  batch      `dalembert batch < file > /dev/null` (the queries' JSON made beforehand)
  list       Oracle().run(queries): one list, pipelined
  submit     one query at a time with Oracle.submit(), answers collected with .result()
  sync       (--sync) one query at a time with Oracle.step(), a round trip per query
Every Python variant reads every answer's q2 (so the answers are parsed and their intervals
built). --pin runs everything (this script and the batch process) on one CPU: then a run's
wall time is the batch process's CPU time plus this script's, and the API's share is
"Python CPU / batch CPU": this script's CPU seconds in the run over the CPU seconds of
`batch` alone. CPU times are getrusage's (user + system); min and median over the reps.
"""

import argparse
import json
import os
import random
import resource
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
from dalembert import Oracle, find_binary  # noqa: E402


def pairs(n, seed=1):
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        h = rng.uniform(0.05, 0.5)
        q0 = [rng.uniform(-1, 1) for _ in range(3)]
        v = [rng.uniform(-1, 1), rng.choice([-1, 1]) * rng.uniform(0.2, 1), 0.0]
        v[2] = q0[1] * v[0]
        out.append((q0, [a + h * b for a, b in zip(q0, v)], h))
    return out


def cpu(who):
    r = resource.getrusage(who)
    return r.ru_utime + r.ru_stime


def measure(f):
    """(wall seconds, CPU seconds of this process, CPU seconds of the batch process)"""
    t0, s0, c0 = time.perf_counter(), cpu(resource.RUSAGE_SELF), cpu(resource.RUSAGE_CHILDREN)
    f()
    t1, s1, c1 = time.perf_counter(), cpu(resource.RUSAGE_SELF), cpu(resource.RUSAGE_CHILDREN)
    return t1 - t0, s1 - s0, c1 - c0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=3000)
    ap.add_argument("--reps", type=int, default=15)
    ap.add_argument("--pin", action="store_true")
    ap.add_argument("--sync", action="store_true", help="also the round-trip variant")
    ap.add_argument("--binary")
    a = ap.parse_args()
    if a.pin:
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    exe = find_binary(a.binary)
    ps = pairs(a.n)
    queries = [{"cmd": "step", "scene": "particle", "q0": q0, "q1": q1, "h": h}
               for q0, q1, h in ps]
    text = "".join(json.dumps({"id": i + 1, **q}) + "\n" for i, q in enumerate(queries)).encode()

    def batch():
        subprocess.run([exe, "batch"], input=text, stdout=subprocess.DEVNULL, check=True)

    def as_list():
        with Oracle(exe) as o:
            for r in o.run(queries):
                r.q2[0].lo

    def submit():
        with Oracle(exe) as o:
            pend = [o.submit(q) for q in queries]
            for p in pend:
                p.result().q2[0].lo

    def sync():
        with Oracle(exe) as o:
            for q0, q1, h in ps:
                o.step(q0, q1, h, scene="particle").q2[0].lo

    variants = [("batch", batch), ("list", as_list), ("submit", submit)]
    if a.sync:
        variants.append(("sync", sync))
    as_list()  # warm up: imports, caches, the binary's pages
    runs = {name: [] for name, _ in variants}
    for _ in range(a.reps):
        for name, f in variants:
            runs[name].append(measure(f))

    def stats(name, i):
        xs = [r[i] for r in runs[name]]
        return min(xs), statistics.median(xs)

    print(f"binary {exe}; {a.n} particle step queries; {a.reps} reps of each variant, "
          f"alternating{'; pinned to one CPU' if a.pin else ''}")
    print(f"{'':7} {'wall min':>9} {'median':>7} {'CPU: batch min':>15} {'median':>7}"
          f" {'Python min':>11} {'median':>7}  {'Python/batch CPU min':>20} {'median':>7}"
          f"  {'wall/batch median':>17}")
    bw = stats("batch", 0)[1]
    bc_min, bc_med = stats("batch", 2)
    for name, _ in variants:
        (w0, w1), (p0, p1), (c0, c1) = stats(name, 0), stats(name, 1), stats(name, 2)
        if name == "batch":
            print(f"{name:7} {w0:7.3f} s {w1:7.3f} {c0:13.3f} s {c1:7.3f}")
            continue
        print(f"{name:7} {w0:7.3f} s {w1:7.3f} {c0:13.3f} s {c1:7.3f} {p0:9.3f} s {p1:7.3f}"
              f"  {100 * p0 / bc_min:19.1f}% {100 * p1 / bc_med:6.1f}%"
              f"  {100 * (w1 / bw - 1):+16.1f}%")


if __name__ == "__main__":
    main()
