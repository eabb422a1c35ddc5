"""`dalembert.grade` and `work_precision` on scipy runs: the proved error intervals contain
the closed form's value minus the run's (mpmath at 40 digits, independent of the binary), at
53 and 106 bits; the verdicts; a refusal part-way keeps the certified times; bad input gets
one clear error."""

import math

import pytest

sp = pytest.importorskip("sympy")
mp = pytest.importorskip("mpmath")
np = pytest.importorskip("numpy")
integrate = pytest.importorskip("scipy.integrate")
from sympy.physics.mechanics import dynamicsymbols  # noqa: E402

from dalembert import Grade, grade, work_precision  # noqa: E402
from dalembert.sympy import scene_from_lagrangian  # noqa: E402

T = dynamicsymbols._t
X, Y, TH = dynamicsymbols("x y theta")
XD, YD, THD = (c.diff(T) for c in (X, Y, TH))
m, J = sp.symbols("m J", positive=True)
SCENE = scene_from_lagrangian(m / 2 * (XD**2 + YD**2) + J / 2 * THD**2, [X, Y, TH],
                              [-sp.sin(TH) * XD + sp.cos(TH) * YD], {m: 2.0, J: 0.75})
Q0, U0 = [0.1, -0.2, 0.3], [0.8, 0.5]
TIMES = np.linspace(0.0, 2.0, 9)


def rhs(_t, s):
    """The free unicycle as a [q, qdot] ODE (constraint force eliminated by hand: the speed
    along the blade is constant, so xdd = -thd * yd, ydd = thd * xd, thdd = 0)."""
    x, y, th, xd, yd, thd = s
    return [xd, yd, thd, -thd * yd, thd * xd, 0.0]


def run(method="DOP853", rtol=1e-6, t_eval=TIMES):
    y0 = Q0 + [U0[0], math.tan(Q0[2]) * U0[0], U0[1]]
    return integrate.solve_ivp(rhs, (0.0, float(t_eval[-1])), y0, method=method, rtol=rtol,
                               atol=rtol * 1e-3, t_eval=t_eval)


def closed(t):
    """(q, u) of the exact motion at t, 40 digits."""
    with mp.workdps(40):
        th0, w = mp.mpf(Q0[2]), mp.mpf(U0[1])
        s = mp.mpf(U0[0]) / mp.cos(th0)
        th = th0 + w * mp.mpf(t)
        return [Q0[0] + s / w * (mp.sin(th) - mp.sin(th0)),
                Q0[1] - s / w * (mp.cos(th) - mp.cos(th0)), th, s * mp.cos(th), w]


@pytest.mark.parametrize("bits", [53, 106])
def test_the_error_intervals_contain_the_true_errors(oracle, bits):
    sol = run()
    g = grade(sol, scene=SCENE, precision=bits, oracle=oracle)
    assert isinstance(g, Grade) and g.error.shape == (len(TIMES), 5, 2) and not g.refused
    worst = 0
    with mp.workdps(40):
        for j, t in enumerate(TIMES):
            q, u = SCENE.state(sol.y[:, j]) if j == 0 else (
                list(sol.y[:3, j]), [sol.y[3, j], sol.y[5, j]])
            for c, (ref, x) in enumerate(zip(closed(t), q + u)):
                lo, hi = g.error[j, c]
                true = ref - mp.mpf(x)
                assert lo <= true <= hi, (bits, j, c, lo, float(true), hi)
                worst = max(worst, abs(true))
                assert hi - lo <= 1e-13 * max(1, abs(float(true)))
        assert worst <= g.max_error <= worst * (1 + 1e-9) + 1e-14
    # the start is the run's own state (at 106 bits enclosed to within its rounding)
    assert np.abs(g.error[0]).max() <= (0.0 if bits == 53 else 1e-30)
    assert g.passed is None and g.verdict is None


def test_verdicts_passed_failed_straddle(oracle):
    sol = run(rtol=1e-4)
    g = grade(sol, scene=SCENE, oracle=oracle)
    assert grade(sol, scene=SCENE, tol=2 * g.max_error, oracle=oracle).verdict == "passed"
    low = grade(sol, scene=SCENE, tol=g.max_error / 2, oracle=oracle)
    assert (low.passed, low.verdict) == (False, "failed")
    j, c = np.unravel_index(np.argmax(np.abs(g.error).max(axis=2)), g.error.shape[:2])
    lo, hi = sorted(abs(g.error[j, c]))
    mid = lo / 2 + hi / 2
    assert lo < mid < hi  # (a box several ulps wide)
    s = grade(sol, scene=SCENE, tol=mid, oracle=oracle)
    assert (s.passed, s.verdict) == (False, "straddle")


def test_t_and_y_arrays_a_built_in_scene_and_work_precision(oracle):
    # the knife as a built-in scene: y is [q, u]; a constant run is graded against the flow
    t = np.array([0.0, 0.5, 1.0])
    y = np.array([[0.0] * 3, [0.0] * 3, [0.0] * 3, [0.0] * 3, [0.0] * 3])
    g = grade(t=t, y=y, scene="knife", oracle=oracle)
    assert g.error.shape == (3, 5, 2) and g.max_error > 0.1  # the knife slides down
    rows = work_precision([("DOP853 1e-4", run(rtol=1e-4), 1e-4),
                           ("DOP853 1e-8", run(rtol=1e-8), 1e-8), ("RK45", run("RK45"))],
                          scene=SCENE, precision=106, oracle=oracle, plot=False)
    assert [r.label for r in rows] == ["DOP853 1e-4", "DOP853 1e-8", "RK45"]
    assert rows[0].max_error > rows[1].max_error and rows[2].given == rows[2].grade.t.size \
        or rows[2].given == run("RK45").nfev
    assert rows.figure is None and "proved max error" in rows.table()


def test_bad_input_gets_one_clear_error(oracle):
    sol = run()
    with pytest.raises(ValueError, match=r"^y: expected shape \(states, 9\) for 9 times, got "
                                         r"\(9, 6\) \(y is \(states, times\) as scipy gives "
                                         r"it: pass y.T\)$"):
        grade(t=sol.t, y=sol.y.T, scene=SCENE, oracle=oracle)
    with pytest.raises(ValueError, match=r"y has 4 entries; the scene \(3 coordinates, 2 "
                                         r"quasi-velocities\) takes \[q, qdot\] \(6 entries\)"):
        grade(t=sol.t, y=sol.y[:4], scene=SCENE, oracle=oracle)
    with pytest.raises(ValueError, match=r"^y: 6 states; the built-in scene `knife` is graded "
                                         r"from \[q, u\] \(5 entries\)"):
        grade(sol, scene="knife", oracle=oracle)
    with pytest.raises(ValueError, match="give sol, or t and y, not both"):
        grade(sol, t=sol.t, scene=SCENE, oracle=oracle)
    with pytest.raises(ValueError, match=r"^t: 1.0 - t\[0\] = 0.001 is not a float exactly"):
        grade(t=[0.001, 1.0], y=sol.y[:, :2], scene=SCENE, oracle=oracle)


def test_work_precision_plots_with_matplotlib(oracle):
    pytest.importorskip("matplotlib")  # optional by design: the rows come without it
    rows = work_precision([("a", run(rtol=1e-4), 1e-4), ("b", run(rtol=1e-8), 1e-8)],
                          scene=SCENE, precision=53, oracle=oracle)
    ax = rows.figure.axes[0]
    assert ax.get_xscale() == "log" and len(ax.lines) == 2
    assert ax.lines[1].get_ydata()[0] == rows[1].max_error
