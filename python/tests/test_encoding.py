"""The client writes each query as one JSON line of its own making (a template per form of
query, floats with 17 significant digits): read back, the line must be the query with its
id, the keys in the query's order, every float the same f64 bit for bit (a float with an
integer value may be written without a fraction, `4` or `-0`, which the binary reads as
the same f64, as Python's float() does), ints, bools, strings and nested values as
`json` writes them; NaN and infinity are refused as `json` refuses them."""

import json
import math
import random
import struct

import pytest

from dalembert import InputError
from dalembert._oracle import _line

from test_decoding import identical, random_float


class IntText(str):
    """A JSON number without fraction or exponent, as written."""


def back(query, id):
    line = _line(query, id)
    assert isinstance(line, bytes) and b"\n" not in line
    return json.loads(line, parse_int=IntText)


def same(got, want):
    """`got` (read back, integers as IntText) is `want` (what json writes, read back)."""
    if isinstance(got, IntText):
        if type(want) is float:  # the f64 the binary reads from the integer text
            return struct.pack("<d", float(got)) == struct.pack("<d", want)
        return type(want) is int and int(got) == want
    if isinstance(want, dict):
        return (type(got) is dict and list(got) == list(want)
                and all(same(got[k], want[k]) for k in want))
    if isinstance(want, list):
        return (type(got) is list and len(got) == len(want)
                and all(same(a, b) for a, b in zip(got, want)))
    return identical(got, want)


def test_random_queries_read_back_bit_for_bit():
    rng = random.Random(20261129)
    for n in range(2000):
        q = {"cmd": rng.choice(["step", "flow", "w%d", "in%sfo"]), "scene": "particle"}
        for k in range(rng.randint(0, 5)):
            kind = rng.randrange(7)
            key = rng.choice(["q0", "q1", "h", "t", "%s", "k\"%", "steps", "order", f"x{k}"])
            if kind == 0:
                v = random_float(rng)
            elif kind == 1:
                v = [random_float(rng) for _ in range(rng.randint(0, 4))]
            elif kind == 2:
                v = tuple(random_float(rng) for _ in range(3))
            elif kind == 3:
                v = [0, 0.5, rng.randint(-10**20, 10**20)]
            elif kind == 4:
                v = rng.choice([True, False, None, 4, "dla", {"eps": random_float(rng)}])
            elif kind == 5:
                v = [[random_float(rng), random_float(rng)], [1.0]]
            else:
                v = rng.choice([4.0, -0.0, 1e17, 2.0 ** 60])
            q[key] = v
        want = json.loads(json.dumps({"id": n, **q}))
        got = back(q, n)
        assert same(got, want), (q, got)


def test_an_id_in_the_query_is_replaced():
    got = back({"cmd": "step", "id": "mine", "h": 0.5}, 7)
    assert same(got, {"id": 7, "cmd": "step", "h": 0.5})


def test_floats_of_integer_keys_stay_floats():
    # `steps` 4.0 is refused by the binary as it was (a float where an integer is due)
    got = back({"cmd": "integrate", "steps": 4.0, "h": 4.0}, 1)
    assert type(got["steps"]) is float and same(got["h"], 4.0)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_numbers_are_refused(bad):
    for q in ({"cmd": "step", "h": bad}, {"cmd": "step", "q0": [0.5, bad, 0.5]},
              {"cmd": "step", "params": {"eps": bad}}):
        with pytest.raises(InputError, match="non-finite"):
            _line(q, 1)


def test_floats_bit_for_bit_at_the_edges():
    rng = random.Random(5)
    xs = [random_float(rng) for _ in range(5000)] + [5e-324, -0.0, 1.7976931348623157e308]
    got = back({"q": xs}, 1)["q"]
    assert len(got) == len(xs) and all(same(a, b) for a, b in zip(got, xs))
