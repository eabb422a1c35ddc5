#!/usr/bin/env python3
"""Widths and time of a certified `step` as h goes from 1e-6 to 1 (particle, knife), for
pairs on M_h^{e,nh} built from the certified flow. Usage: h_sweep.py path/to/dalembert"""
import json
import subprocess
import sys
import time

exe = sys.argv[1] if len(sys.argv) > 1 else "dalembert"


def run(*args):
    return subprocess.run([exe, *args, "--json"], capture_output=True, text=True)


for scene in ["particle", "knife"]:
    for h in [1e-6, 1e-4, 1e-2, 0.1, 0.5, 1.0]:
        f = json.loads(run("flow", "--scene", scene, "--q", "0,0,0", "--u", "0.8,0.8",
                           "--t", repr(h)).stdout)
        q1 = ",".join(repr((a + b) / 2) for a, b in f["q"])
        pair = ["--scene", scene, "--q0", "0,0,0", "--q1", q1, "--h", repr(h)]
        t = time.time()
        out = run("step", *pair)
        ms = (time.time() - t) * 1e3
        if out.returncode:
            print(scene, h, "exit", out.returncode, out.stderr.strip())
            continue
        s, r = json.loads(out.stdout), json.loads(run("retract", *pair).stdout)
        wid = lambda v: max(b - a for a, b in v)
        print(f"{scene:9} h={h:<7} step {ms:6.1f} ms (process)  width u0 {wid(r['u0']):.1e}"
              f"  s {wid(r['defect']):.1e}  q2 {wid(s['q2']):.1e}")
