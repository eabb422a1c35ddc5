#!/usr/bin/env python3
"""Throughput of the Python API against `dalembert batch` alone, on the same 3,000 particle
`step` queries (issue: the API adds at most 20 % to batch's time).

    python3 benches/python_throughput.py [--n 3000] [--reps 5] [--pin] [--binary PATH]

Times (best of --reps, each including the process start):
  batch      `dalembert batch < file > /dev/null` (--jobs 1)
  list       Oracle().run(queries): one list, pipelined
  submit     one query at a time with Oracle.submit(), answers collected with .result()
  sync       one query at a time with Oracle.step() (waits for each answer: a round trip
             per query, for comparison)
Every Python variant reads every answer's q2 (so the answers are parsed and their
intervals built). --pin runs everything (this script and the batch process) on one CPU.
Beside the wall times, the CPU seconds of the batch process and of this script: on one
core the API adds at most its own CPU time to batch's, and that ratio is far less sensitive
to other load on the machine than wall times are. "waits" is how many times this script
waited for the pipes (its voluntary context switches): one per answer when the answers come
one write each, a few dozen when they come in large writes.
"""

import argparse
import json
import os
import random
import resource
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


def best(f, reps):
    """Best of `reps`: (wall seconds, CPU seconds of this process, CPU seconds of the batch
    process, voluntary context switches of this process), the run with the least wall
    time."""
    runs = []
    for _ in range(reps):
        t0, c0 = time.perf_counter(), os.times()
        w0 = resource.getrusage(resource.RUSAGE_SELF).ru_nvcsw
        f()
        t1, c1 = time.perf_counter(), os.times()
        w1 = resource.getrusage(resource.RUSAGE_SELF).ru_nvcsw
        runs.append((t1 - t0, (c1.user + c1.system) - (c0.user + c0.system),
                     (c1.children_user + c1.children_system)
                     - (c0.children_user + c0.children_system), w1 - w0))
    return min(runs)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=3000)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--pin", action="store_true")
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

    base, _, base_cpu, _ = best(batch, a.reps)
    print(f"binary {exe}; {a.n} particle step queries; best of {a.reps}"
          f"{'; pinned to one CPU' if a.pin else ''}")
    print(f"{'':8} {'wall':>9} {'queries/s':>10} {'vs batch':>9} {'CPU: batch':>11} {'Python':>7}"
          f" {'Python/batch CPU':>17} {'waits':>6}")
    print(f"{'batch':8} {base:7.3f} s {a.n / base:10.0f} {'':9} {base_cpu:9.3f} s")
    for name, f in (("list", as_list), ("submit", submit), ("sync", sync)):
        t, cpu, child, waits = best(f, a.reps)
        print(f"{name:8} {t:7.3f} s {a.n / t:10.0f} {100 * (t / base - 1):+8.1f}% "
              f"{child:9.3f} s {cpu:5.3f} s {100 * cpu / base_cpu:+16.1f}% {waits:6d}")


if __name__ == "__main__":
    main()
