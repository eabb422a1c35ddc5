#!/usr/bin/env python3
"""Widths of dalembert and CAPD's C0Pped2Set over 30 starts near the benchmark start.

The width of a long flow moves by up to 40% (both tools) when the start moves by an ulp: the
wrapping of the set depends on the last bits. One start says little; this script compares
the geometric means over 30 starts near q = (0, 0, 0), u = (0.8, 0.8): the 15 doubles within
2 ulps of u1 and 1 ulp of u2, and 15 starts moved by multiples of about 1e-12.

    DALEMBERT=target/release/dalembert CAPD_FLOW=../shared/peers/capd/capd_flow \\
        python3 examples/python/capd_starts.py knife-eps 600

prints per tool the geometric mean, the two halves' means, the extremes, and the ratio of
the means (dalembert / CAPD). Without CAPD_FLOW only dalembert runs.
"""

import json
import math
import os
import struct
import subprocess
import sys


def ulps(x, k):
    """The double k ulps above x (x > 0)."""
    bits = struct.unpack("<q", struct.pack("<d", x))[0] + k
    return struct.unpack("<d", struct.pack("<q", bits))[0]


def starts():
    near = [(ulps(0.8, a), ulps(0.8, b)) for a in range(-2, 3) for b in range(-1, 2)]
    far = [(0.8 + (k - 7) * 1.3e-12, 0.8 + ((k * 5) % 7 - 3) * 0.7e-12) for k in range(15)]
    return near + far


def dalembert(binary, scene, t, u):
    cmd = [binary, "flow", "--scene", scene, "--q", "0,0,0"]
    cmd += ["--u", "%r,%r" % u, "--t", t, "--json"]
    if scene == "knife-eps":
        cmd += ["--param", "eps=0.1"]
    d = json.loads(subprocess.run(cmd, capture_output=True, text=True, check=True).stdout)
    return max(b - a for a, b in d["q"] + d["u"])


def capd(binary, scene, t, u):
    cmd = [binary, scene, t, "pped2", "0,0,0", "%r,%r" % u]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    return json.loads(out)["max_width"]


def geo(ws):
    return math.exp(sum(math.log(w) for w in ws) / len(ws))


def report(name, ws):
    print("%-9s geo %.4g  (near %.4g, far %.4g)  min %.4g  max %.4g"
          % (name, geo(ws), geo(ws[:15]), geo(ws[15:]), min(ws), max(ws)))


def main():
    scene, t = sys.argv[1], sys.argv[2]
    ours = [dalembert(os.environ.get("DALEMBERT", "dalembert"), scene, t, u) for u in starts()]
    report("dalembert", ours)
    if os.environ.get("CAPD_FLOW"):
        theirs = [capd(os.environ["CAPD_FLOW"], scene, t, u) for u in starts()]
        report("CAPD", theirs)
        print("ratio of the means: %.3f" % (geo(ours) / geo(theirs)))


if __name__ == "__main__":
    main()
