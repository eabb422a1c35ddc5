"""The client keeps a flat answer as its line until a key is read, and then parses that key
alone: what every key then gives must be exactly what parsing the whole line with
`json.loads` gives (same types, bit-identical floats, the same intervals and errors), for
real answers of every command and for random floats at the edges of f64."""

import json
import math
import random
import struct
import subprocess
from collections.abc import Mapping

from dalembert import Interval, find_binary
from dalembert._oracle import Answer, Oracle, OracleError, Pending, ProtocolError, _answer

P = {"scene": "particle"}
STEP = dict(P, q0=[0.1, 0.2, 0.3], q1=[0.5, 0.6, 0.55], h=0.3)
LINE = [[k / 8, 0.5, k / 16] for k in range(5)]
QUERIES = [
    dict(STEP, cmd="step"),
    dict(STEP, cmd="retract"),
    dict(STEP, cmd="lagrangian"),
    dict(P, cmd="flow", q=[0, 0.5, 0], u=[0.8, 0.8], t=0.5, jacobian=True),
    dict(P, cmd="flow", q=[0, 0.5, 0], u=[0.8, 0.8], times=[0.25, 0.5, 1]),
    dict(P, cmd="check", q=LINE, h=0.125, tol=1e-12),
    dict(P, cmd="check", q=LINE, t=[0, 0.125, 0.375, 0.5, 0.625], defect_tol=1e-6),
    dict(P, cmd="integrate", q0=[0.1, 0.2, 0.3], q1=[0.15, 0.25, 0.35], h=0.05, steps=4,
         scheme="dla"),
    dict(P, cmd="order", scheme="dla", q=[0, 0, 0], u=[0.8, 0.8], rungs=3),
    dict(STEP, cmd="step", q0=[0, 0]),  # an input error
    dict(P, cmd="flow", q=[0, 0, 0], u=[0.8, 0.8], t=1e4, deadline=1e-3),  # past the budget
    dict(STEP, cmd="step", h=-0.0),
    dict(STEP, cmd="step", q0=[5e-324, -0.0, 1e-310]),
]


def eager(line, cmd):
    """The answer as the whole line parsed by json.loads gives it."""
    obj = json.loads(line)
    return _answer(cmd, obj["ok"]) if "ok" in obj else obj["error"]


def identical(a, b):
    """Same types all the way down, floats bit for bit (-0.0 is not 0.0)."""
    if type(a) is not type(b):
        return False
    if isinstance(a, float):
        return struct.pack("<d", a) == struct.pack("<d", b)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(identical(x, y) for x, y in zip(a, b))
    if isinstance(a, Mapping):
        return list(a) == list(b) and all(identical(a[k], b[k]) for k in a)
    return a == b


def answer_lines(queries):
    text = "".join(json.dumps({"id": i + 1, **q}) + "\n" for i, q in enumerate(queries))
    out = subprocess.run([find_binary(), "batch"], input=text.encode(), capture_output=True,
                         check=True).stdout
    return out.split(b"\n")[:-1]


def test_every_key_of_every_command_is_what_json_loads_gives():
    lines = answer_lines(QUERIES)
    assert len(lines) == len(QUERIES)
    seen = set()
    for i, (line, q) in enumerate(zip(lines, QUERIES)):
        got = Oracle._result(line, Pending(None, i + 1, q["cmd"]))
        want = eager(line, q["cmd"])
        if isinstance(got, OracleError):
            assert identical(got.message, want["message"]) and got.code == want["code"]
            assert identical(got.reached, want.get("reached")), (got.reached, line)
            seen.add("error")
            continue
        assert isinstance(got, Answer), (got, line)
        assert list(got) == list(want)
        for key in want:  # each key alone, in an order of its own: nothing shared
            fresh = Oracle._result(line, Pending(None, i + 1, q["cmd"]))
            assert identical(fresh[key], want[key]), (q["cmd"], key)
        assert identical(got, want)
        seen.add(q["cmd"])
    assert seen == {q["cmd"] for q in QUERIES} | {"error"}, seen


def random_float(rng):
    kind = rng.randrange(6)
    if kind == 0:
        return rng.choice([0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1e308,
                           -1.7976931348623157e308, 1.7976931348623157e308, 0.1, 1 / 3])
    if kind == 1:  # any bit pattern that is finite: subnormals included
        while True:
            x = struct.unpack("<d", rng.getrandbits(64).to_bytes(8, "little"))[0]
            if math.isfinite(x):
                return x
    if kind == 2:
        return rng.uniform(-1, 1) * 10.0 ** rng.randint(-320, 308)
    return rng.uniform(-2, 2)


def test_random_floats_are_read_bit_for_bit():
    rng = random.Random(20261128)
    for n in range(300):
        pairs = [sorted([random_float(rng), random_float(rng)])
                 for _ in range(rng.randint(1, 6))]
        lo, hi = pairs[0]
        other = [random_float(rng) for _ in range(3)]
        obj = {"id": n, "ok": {"q2": pairs, "l": [lo, hi], "stats": other, "member": True}}
        # the binary's compact form (kept as text, each key parsed alone) and a spaced one
        # (parsed whole)
        for line, kept in ((json.dumps(obj, separators=(",", ":")), True),
                           (json.dumps(obj).encode(), False)):
            a = Oracle._result(line, Pending(None, n, "lagrangian"))
            assert (a._text is not None) == kept
            assert identical(a.l, Interval(lo, hi))
            assert identical(a.stats, other) and a.member is True
            a = Oracle._result(line, Pending(None, n, "step"))
            assert identical(a.q2, [Interval(x, y) for x, y in pairs])
            assert identical(dict(a), json.loads(line)["ok"] | {"q2": a.q2})


def test_what_is_not_an_answer_is_still_refused():
    def result(text, id=1, cmd="step"):
        return Oracle._result(text.encode(), Pending(None, id, cmd))

    assert "not JSON" in str(result('{"id":1,"ok":'))
    assert "not JSON" in str(result('{"id":1,"ok":{}} x'))
    not_utf8 = Oracle._result(b'{"id":1,"ok":{"q2":"\xff"}}', Pending(None, 1, "step"))
    assert "not JSON" in str(not_utf8)
    assert "not the answer to id 1" in str(result('{"id":2,"ok":{}}'))
    assert isinstance(result('{"id":1.5,"ok":{}}', id=1.5), Answer)
    assert "without ok or error" in str(result('{"id":1,"okay":{"x":1.5}}'))
    for bad in ('[[1.5, 0.5]]', '[[1.5]]', '[["b", 0.5]]', '[1.5]', '1.5'):
        with_bad = result('{"id":1,"ok":{"q2":%s}}' % bad)
        try:
            with_bad.q2
        except ProtocolError as e:
            assert "expected intervals" in str(e)
        else:
            raise AssertionError(f"{bad} read as intervals")
    e = result('{"id":1,"error":{"code":3,"message":"m","reason":"budget","reached":0.25}}')
    assert isinstance(e, OracleError) and type(e.reached) is float and e.reached == 0.25
