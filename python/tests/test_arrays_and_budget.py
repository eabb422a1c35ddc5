"""Intervals as numpy arrays (exact copies of the printed endpoints), the typed errors of
budgets (a small `work` is refused with reason "budget", the same on every run), the
pipelined queries (`submit`) and `order`."""

import pytest

from dalembert import Interval, Oracle, Uncertified, to_array

np = pytest.importorskip("numpy")

STEP = dict(q0=[0.1, 0.2, 0.3], q1=[0.5, 0.6, 0.55], h=0.3)


def test_arrays_are_the_printed_endpoints(oracle):
    s = oracle.step(scene="particle", **STEP)
    a = s.array("q2")
    assert a.shape == (3, 2) and a.dtype == np.float64
    assert [(iv.lo, iv.hi) for iv in s.q2] == [tuple(r) for r in a.tolist()]
    f = oracle.flow([0, 0, 0], [1, 0.5], 1.0, scene="knife", jacobian=True)
    assert f.array("jacobian").shape == (5, 5, 2)
    assert to_array(Interval(1.0, 2.0)).tolist() == [1.0, 2.0]


def test_a_small_work_budget_is_refused_every_time(oracle):
    for _ in range(3):
        with pytest.raises(Uncertified) as e:
            oracle.step(scene="particle", work=1000, **STEP)
        assert e.value.reason == "budget" and e.value.past_budget
        assert e.value.message.startswith("not certified within the budget")
    assert oracle.step(scene="particle", work=10**9, **STEP).q2 == \
        oracle.step(scene="particle", **STEP).q2


def test_a_session_work_budget_applies_to_every_query():
    with Oracle(scene="particle", work=1000) as o:
        with pytest.raises(Uncertified):
            o.step(**STEP)
        assert o.step(work=10**9, **STEP).q2[0].lo <= o.step(work=10**9, **STEP).q2[0].hi


def test_submit_pipelines_and_keeps_order(oracle):
    pend = [oracle.submit(oracle.query("flow", scene="particle", q=[0, 0, 0], u=[0, 1],
                                       t=k / 8)) for k in range(500)]
    bad = oracle.submit(oracle.query("flow", scene="particle", q=[0, 0], u=[0, 1], t=1))
    assert [p.result().q[1] for p in pend] == [Interval(k / 8, k / 8) for k in range(500)]
    assert bad.outcome().code == 2


def test_order_answers_intervals_or_none():
    # the batch `order` query (contract E16)
    with Oracle(scene="particle") as o:
        a = o.order([0, 0, 0], [0.8, 0.8], "dla", rungs=3)
        assert len(a.local.error) == 3
        assert all(isinstance(e, Interval) and e.lo > 0 for e in a.local.error)
        assert all(p is None or isinstance(p, Interval) for p in a.local.order)
