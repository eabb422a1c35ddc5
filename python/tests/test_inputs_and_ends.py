"""numpy arrays wherever a vector is (issue 49), with one clear error for a wrong shape;
campaigns of dict queries answered as `Answer`s (issue 47); interval ends that mix with
floats exactly at every precision (`Exact` above 53 bits, issue 49)."""

from decimal import Decimal
from fractions import Fraction

import pytest

from dalembert import Answer, Exact, InputError, Interval
from dalembert.campaign import run_local

np = pytest.importorskip("numpy")

Q, U = [0.1, -0.2, 0.3], [0.8, 0.5]


def test_numpy_vectors_and_scalars_are_the_lists(oracle):
    want = oracle.flow(Q, U, 0.5, scene="knife")
    got = oracle.flow(np.array(Q), np.array(U),
                      np.float64(0.5), scene="knife")
    assert got.q == want.q and got.u == want.u
    dense = oracle.flow(np.array(Q), np.array(U), times=np.array([0.25, 0.5]), scene="knife")
    assert dense.at[1].q == oracle.flow(Q, U, times=[0.25, 0.5], scene="knife").at[1].q
    rows = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.2, 0.0, 0.0]])
    a = oracle.check(rows, 0.1, scene="particle", pairs=False)
    b = oracle.check(rows.tolist(), 0.1, scene="particle", pairs=False)
    assert a.distance == b.distance
    # a list of numpy rows, numpy scalars inside a list
    c = oracle.check([r for r in rows], 0.1, scene="particle", pairs=False)
    assert c.distance == b.distance


@pytest.mark.parametrize("key,value,shape", [
    ("q", np.zeros((3, 1)), "(3, 1)"), ("u", np.zeros((1, 2)), "(1, 2)"),
    ("times", np.zeros((2, 2)), "(2, 2)")])
def test_an_array_of_the_wrong_shape_is_one_clear_error(oracle, key, value, shape):
    args = dict(q=Q, u=U, t=0.5)
    if key == "times":
        args["t"] = None
    args[key] = value
    with pytest.raises(ValueError) as e:
        oracle.flow(args["q"], args["u"], args["t"], scene="knife",
                    **({"times": value} if key == "times" else {}))
    assert str(e.value) == f"{key}: expected a vector (a 1-D array), got an array of shape " \
                           f"{shape}"
    with pytest.raises(ValueError, match=r"^q: expected rows \(a 2-D array\), got an array "
                                         r"of shape \(3,\)$"):
        oracle.check(np.zeros(3), 0.1, scene="particle")


def test_run_local_takes_dicts_and_gives_answers(oracle):
    queries = [oracle.query("flow", scene="knife", q=np.array(Q), u=U, t=k / 4)
               for k in range(1, 4)]
    queries.append({"cmd": "flow", "scene": "knife", "q": [0, 0], "u": U, "t": 1.0})
    got = run_local(queries)
    assert all(type(a) is Answer for a in got[:3])
    assert [a.q for a in got[:3]] == [oracle.flow(Q, U, k / 4, scene="knife").q
                                      for k in range(1, 4)]
    assert isinstance(got[3], InputError) and got[3].code == 2 and got[3].id == 4
    lines = run_local(['{"id":7,"cmd":"flow","scene":"knife","q":[0,0,0],"u":[1,0],"t":1}'])
    assert isinstance(lines[0], str) and lines[0].startswith('{"id":7,"ok":')
    with pytest.raises(ValueError, match="not a mix"):
        run_local(["{}", {"cmd": "flow"}])


def test_ends_mix_with_floats_exactly_at_every_precision(oracle):
    f53 = oracle.flow(Q, U, 0.5, scene="knife")
    f106 = oracle.flow(Q, U, 0.5, scene="knife", precision=106)
    for iv in f53.q:
        assert type(iv.lo) is float and type(iv.lo - 1.2) is float
    for iv in f106.q:
        lo, hi = iv
        assert type(lo) is Exact and isinstance(lo, Decimal)
        d = lo - 1.2
        assert type(d) is Exact and Fraction(d) == Fraction(lo) - Fraction(1.2)
        assert Fraction(1.2 - hi) == Fraction(1.2) - Fraction(hi)
        assert Fraction(lo * 0.1) == Fraction(lo) * Fraction(0.1)
        assert Fraction(2 * lo + hi) == 2 * Fraction(lo) + Fraction(hi)
        assert lo - Fraction(1, 3) == Fraction(lo) - Fraction(1, 3)
        assert (lo <= iv.mid <= hi) and (lo < 2.0) == (Fraction(lo) < 2)
        assert -lo == Exact(0) - lo and abs(-lo) == abs(lo)
        # the 53-bit box, rounded outward, contains the 106-bit one's ends compared exactly
    for a, b in zip(f53.q, f106.q):
        assert a.lo <= b.lo and b.hi <= a.hi
    assert repr(Exact("1.5")) == "Exact('1.5')"
    assert Interval(Exact("1"), Exact("2")).width_up() == 1.0
