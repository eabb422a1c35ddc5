"""The refusal's one cause (`OracleError.cause`, contract E23), the step limit as a budget
the user sets (`max_steps`, E24), the stops certified before a refusal (`Uncertified.at`,
E25), inline scenes inspected (`Oracle.scenes`, E27) and `check` at a precision (E28),
through the Python client; and `grade` keeping the certified times of a run refused
part-way."""

import math

import pytest

from dalembert import CAUSES, Oracle, Uncertified

np = pytest.importorskip("numpy")


# the unicycle with free x, theta: its derived basis e1 = (1, tan theta, 0) is singular at
# theta = pi/2, which the motion from theta = 1.3 at w = 0.5 reaches at t = 0.5416
UNICYCLE = {"coordinates": ["x", "y", "theta"], "parameters": {"m": 2.0, "J": 0.75},
            "mass": [["m", 0, 0], [0, "m", 0], [0, 0, "J"]],
            "constraints": [["-sin(theta)", "cos(theta)", 0]], "free": ["x", "theta"]}
Q0, U0 = [0.0, 0.0, 1.3], [0.1, 0.5]


def closed(t):
    th0, w = Q0[2], U0[1]
    s = U0[0] / math.cos(th0)
    th = th0 + w * t
    return [s / w * (math.sin(th) - math.sin(th0)), -s / w * (math.cos(th) - math.cos(th0)), th]


def test_a_singular_basis_is_the_cause_basis(oracle):
    with pytest.raises(Uncertified) as e:
        oracle.flow(Q0, U0, 1.0, scene=UNICYCLE)
    assert e.value.cause == "basis" and e.value.reason == "undefined"
    assert 0.5 < e.value.reached < (math.pi / 2 - 1.3) / 0.5 and e.value.at == []
    assert CAUSES >= {"mass", "basis", "domain", "width", "steps", "work", "deadline",
                      "proof", "unbounded", "internal"}


def test_the_step_limit_is_a_budget_the_user_sets(oracle):
    with pytest.raises(Uncertified) as e:
        oracle.flow([0, 0, 0], [1, 0.5], 20.0, scene="knife", max_steps=5)
    assert (e.value.cause, e.value.reason) == ("steps", "budget") and e.value.past_budget
    assert oracle.flow([0, 0, 0], [1, 0.5], 20.0, scene="knife", max_steps=100000).q
    with Oracle(scene="knife", max_steps=5) as o:
        with pytest.raises(Uncertified) as e:
            o.flow([0, 0, 0], [1, 0.5], 20.0)
        assert e.value.cause == "steps"
        assert o.flow([0, 0, 0], [1, 0.5], 20.0, max_steps=100000).q  # the query's own wins
    with pytest.raises(ValueError, match=r"^max_steps: expected an integer >= 1, got 0$"):
        Oracle(max_steps=0)


def test_the_stops_before_a_refusal_come_with_it(oracle):
    with pytest.raises(Uncertified) as e:
        oracle.flow(Q0, U0, times=[0.2, 0.4, 1.0, 1.5], scene=UNICYCLE)
    at = e.value.at
    assert [s.t for s in at] == [0.2, 0.4] and e.value.cause == "basis"
    for stop in at:
        for iv, ref in zip(stop.q, closed(stop.t)):
            assert iv.lo - 1e-12 <= ref <= iv.hi + 1e-12  # (a float closed form)
    # at 106 bits the stops' ends are Exact numbers
    with pytest.raises(Uncertified) as e:
        oracle.flow(Q0, U0, times=[0.2, 0.4, 1.0], scene=UNICYCLE, precision=106)
    assert len(e.value.at) == 2 and abs(e.value.at[1].q[2].lo - 1.5) < 1e-15


def test_an_inline_scene_is_inspected_as_compiled(oracle):
    entry = oracle.scenes(UNICYCLE)["scenes"][0]
    assert entry["n"] == 3 and entry["k"] == 1
    assert any("tan" in b or "sin" in b for b in entry["basis"]), entry["basis"]
    with_m = oracle.scenes(UNICYCLE, params={"m": 3.0})["scenes"][0]
    assert "3" in str(with_m["parameters"])
    assert oracle.scenes("knife")["scenes"][0]["name"] == "knife"
    assert len(oracle.scenes()["scenes"]) >= 7


def test_check_takes_a_precision(oracle):
    rows = [[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.2, 0.0, 0.0]]
    a = oracle.check(rows, 0.1, scene="particle", precision=106)
    assert a["precision"] == 106 and len(a.distance) == 3


def test_grade_keeps_the_certified_times_of_a_run_refused_part_way(oracle):
    from dalembert import Scene, grade

    t = np.array([0.0, 0.2, 0.4, 1.0, 1.5])
    s = U0[0] / math.cos(Q0[2])
    y = np.array([[closed(tk)[i] for tk in t] for i in range(3)]
                 + [[s * math.cos(closed(tk)[2]) for tk in t], [U0[1]] * 5])
    y[3, 0] = U0[0]  # the start exactly
    g = grade(t=t, y=y, scene=Scene(UNICYCLE), tol=1e-6, oracle=oracle)
    assert g.refused == [(1.0, "basis"), (1.5, "basis")] and g.verdict == "refused"
    assert np.isfinite(g.error[:3]).all() and np.isinf(g.error[3:]).all()
    assert g.max_error < 1e-6 and g.passed is False
