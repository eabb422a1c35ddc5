#!/usr/bin/env python3
"""Two builds of the `dalembert` binary on one query mix: are their answers byte-identical,
and how do their CPU times compare? (docs/python.md, "Install": the wheel's Cargo profile
against the release profile.)

    python3 python/bench_builds.py A B [--reps 5] [--n 40]

A and B are binaries (e.g. target/release/dalembert and target/wheel/dalembert). The mix is
`--n` queries of each kind on every built-in scene, from fixed seeds: flows (t in
(0, 3]), dense flows with times, flows at 106 and 256 bits, steps, retractions and discrete
Lagrangians (h in [0.05, 0.4]), at 53 and 106 bits, and `order`; a query a build refuses
is kept (its error line is compared too). Each build answers the whole mix in one `batch`
process, in turn (A, B, A, B, ...), so that a change of load falls on both alike; the CPU
seconds (user + system, getrusage of the children) of each run are reported, min and
median, and the ratio B / A of the medians.
"""

import argparse
import json
import random
import resource
import statistics
import subprocess
import sys

SCENES = {"particle": (3, 2), "knife": (3, 2), "knife-eps": (3, 2), "rolling-disk": (4, 2),
          "sleigh": (3, 2), "contact-oscillator": (3, 2), "contact-oscillator-nr": (3, 2)}


def mix(n, seed=47):
    rng = random.Random(seed)
    out = []

    def vec(k, r):
        return [round(rng.uniform(-r, r), 6) for _ in range(k)]

    for scene, (nq, m) in SCENES.items():
        for i in range(n):
            q, u = vec(nq, 0.5), vec(m, 0.8)
            out.append({"cmd": "flow", "scene": scene, "q": q, "u": u,
                        "t": round(rng.uniform(0.01, 3.0), 3)})
            if i % 4 == 0:
                out.append({"cmd": "flow", "scene": scene, "q": q, "u": u,
                            "times": [0.25, 0.5, 1.0]})
                out.append({"cmd": "flow", "scene": scene, "q": q, "u": u, "t": 0.5,
                            "precision": 106 if i % 8 == 0 else 256})
            h = round(rng.uniform(0.05, 0.4), 3)
            q1 = [x + h * y for x, y in zip(q, vec(nq, 0.5))]
            for cmd in ("step", "retract", "lagrangian"):
                query = {"cmd": cmd, "scene": scene, "q0": q, "q1": q1, "h": h}
                if i % 5 == 0:
                    query["precision"] = 106
                out.append(query)
        out.append({"cmd": "order", "scene": scene, "scheme": "dla", "q": [0.1] * nq,
                    "u": [0.3] * m, "rungs": 3})
    for i, q in enumerate(out):
        q["id"] = i + 1
    return "".join(json.dumps(q) + "\n" for q in out).encode()


def run(binary, data):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([binary, "batch"], input=data, capture_output=True, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return out.stdout, cpu


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--n", type=int, default=40)
    args = ap.parse_args()
    data = mix(args.n)
    queries = data.count(b"\n")
    times = {args.a: [], args.b: []}
    outs = {}
    for _ in range(args.reps):
        for b in (args.a, args.b):
            out, cpu = run(b, data)
            times[b].append(cpu)
            if outs.setdefault(b, out) != out:
                sys.exit(f"{b}: two runs of the same mix differ")
    same = outs[args.a] == outs[args.b]
    errors = sum(b'"error"' in line for line in outs[args.a].splitlines())
    print(f"{queries} queries ({errors} refused), {len(outs[args.a])} bytes of answers: "
          f"{'byte-identical' if same else 'DIFFERENT'}")
    for b in (args.a, args.b):
        print(f"{b}: CPU s min {min(times[b]):.3f} median {statistics.median(times[b]):.3f}")
    ratio = statistics.median(times[args.b]) / statistics.median(times[args.a])
    print(f"median CPU B / A = {ratio:.3f}")
    if not same:
        for i, (x, y) in enumerate(zip(outs[args.a].splitlines(), outs[args.b].splitlines())):
            if x != y:
                print(f"first difference, answer {i + 1}:\n  {x[:300]}\n  {y[:300]}")
                break
        sys.exit(1)


if __name__ == "__main__":
    main()
