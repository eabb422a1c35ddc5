"""Answers computed with more than 53 bits, read through Python: every end is the exact
`Decimal` of the answer's decimal string (negative ends included, which compared as strings
would be out of order), it brackets the closed forms and exact discrete objects of
tests/data/wide_reference.txt (mpmath at 300 digits, independent of the binary), and the
module's own bounds on such intervals (`to_array`, `distance`, `width_up`, `mid`) stay
outward."""

import math
import os
from decimal import Decimal
from fractions import Fraction

import pytest

from dalembert import Exact, Interval, distance, to_array
from dalembert._oracle import Oracle, Pending, ProtocolError

REFERENCE = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "data",
                         "wide_reference.txt")


def reference_lines(kind):
    with open(REFERENCE) as f:
        return [line.split() for line in f if line.startswith(kind + " ")]


def brackets(fields):
    return [(Decimal(fields[i]), Decimal(fields[i + 1])) for i in range(0, len(fields), 2)]


def vec(text):
    return [float(x) for x in text.split(",")]


def encloses(iv, bracket):
    lo, hi = bracket
    return type(iv.lo) is Exact and type(iv.hi) is Exact and iv.lo <= lo and hi <= iv.hi


@pytest.mark.parametrize("bits", [106, 256])
def test_flows_at_precision_bracket_the_closed_forms(oracle, bits):
    seen_negative = False
    for f in reference_lines("flow"):
        scene, q, u, t = f[1], vec(f[2]), vec(f[3]), float(f[4])
        if abs(t) > 10:  # (the long flows are the Rust tests')
            continue
        refs = brackets(f[5:])
        a = oracle.flow(q, u, t, scene=scene, precision=bits)
        assert a["precision"] == bits
        got = a.q + a.u + a.v
        assert len(got) == len(refs)
        for iv, ref in zip(got, refs):
            assert encloses(iv, ref), (f[:5], iv, ref)
            assert Fraction(iv.hi) - Fraction(iv.lo) <= Fraction(2) ** (24 - bits) * max(
                1, abs(Fraction(t))) * max(1, abs(Fraction(ref[1])))
            seen_negative |= iv.hi < 0
    assert seen_negative


def test_exact_step_and_lagrangian_at_256_bits_bracket_the_references(oracle):
    for f in reference_lines("exact"):
        q0, q1, h = vec(f[1]), vec(f[2]), float(f[3])
        refs = brackets(f[4:])  # u0 (2), s, q2 (3), l
        s = oracle.step(q0, q1, h, scene="particle", precision=256)
        for iv, ref in zip(s.q2, refs[3:6]):
            assert encloses(iv, ref), (f[:4], iv, ref)
        lag = oracle.lagrangian(q0, q1, h, scene="particle", precision=256)
        assert encloses(lag.l, refs[6])


def test_the_module_bounds_stay_outward_on_decimal_ends(oracle):
    f = reference_lines("flow")[1]  # the knife to t = 5: x, y and theta, x < 0
    a = oracle.flow(vec(f[2]), vec(f[3]), float(f[4]), scene="knife", precision=256)
    refs = brackets(f[5:11])
    for iv, (rlo, rhi) in zip(a.q, refs):
        w = iv.width_up()
        assert type(w) is float and Fraction(iv.hi) - Fraction(iv.lo) <= Fraction(w)
        m = iv.mid
        assert iv.lo <= m <= iv.hi
        assert isinstance(m, Decimal) or type(m) is float
    # a float point near the flow: the distance encloses |x - r| for every r in the brackets
    x = [float(rlo) for rlo, _ in refs]
    d = distance(x, a.q)  # the max-norm distance: over the components, the nearest and
    gaps = [[abs(Fraction(xi) - Fraction(r)) for r in b] for xi, b in zip(x, refs)]
    assert Fraction(d.lo) <= max(min(g) for g in gaps)  # the farthest of the brackets
    assert max(max(g) for g in gaps) <= Fraction(d.hi)
    assert d.hi < 1e-15
    np = pytest.importorskip("numpy")
    arr = to_array(a.q)
    assert arr.shape == (3, 2) and arr.dtype == np.float64
    for (lo, hi), iv in zip(arr.tolist(), a.q):
        # the floats around the decimal ends: outward, and no float between
        assert lo <= iv.lo and iv.hi <= hi
        assert math.nextafter(lo, math.inf) > iv.lo and math.nextafter(hi, -math.inf) < iv.hi


def test_decimal_ends_are_read_exactly_or_refused():
    def answer(body, cmd="step"):
        return Oracle._result('{"id":1,"ok":%s}' % body, Pending(None, 1, cmd))

    a = answer('{"q2":[["-4.06e-2","-4.05e-2"],["0","1.5e-300"]],"precision":106}')
    assert a.q2 == [Interval(Decimal("-0.0406"), Decimal("-0.0405")),
                    Interval(Decimal(0), Decimal("1.5e-300"))]
    assert Fraction(-406, 10000) in a.q2[0] and Fraction(-405, 10000) in a.q2[0]
    # membership is the exact comparison (the float -0.0406 is not the decimal -0.0406)
    assert (-0.0406 in a.q2[0]) == (Fraction(-0.0406) >= Fraction(-406, 10000))
    assert (-0.0405 in a.q2[0]) == (Fraction(-0.0405) <= Fraction(-405, 10000))
    assert a.precision == 106
    for bad in ('[["1.5","0.5"]]', '[["1.5x","2"]]', '[["NaN","1"]]', '[[" 1","2"]]',
                '[[true,1.5]]', '[["1_0","20"]]'):
        with pytest.raises(ProtocolError, match="expected intervals"):
            answer('{"q2":%s}' % bad).q2


def test_a_damaged_answer_is_reported_when_read():
    def answer(text):
        return Oracle._result(text, Pending(None, 1, "step"))

    a = answer('{"id":1,"ok":{"q1":[[0.5,1.0]],"q2":[[0.5,}}')
    assert a.q1 == [Interval(0.5, 1.0)]  # an undamaged key reads
    with pytest.raises(ProtocolError, match="not JSON"):
        a.q2
    with pytest.raises(ProtocolError, match="not JSON"):
        list(answer('{"id":1,"ok":{"q1":[[0.5,1.0]],"q2":[[0.5,}}'))
    # a key is only ever one of the flat object's own keys
    b = answer('{"id":1,"ok":{"q1":[[0.5,1.0]],"q2":[[2.0,3.0]]}}')
    with pytest.raises(KeyError):
        b['q1":[[0.5,1.0]],"q2']
    assert "q3" not in b and b.get("q2") == [Interval(2.0, 3.0)] and len(b) == 2
