"""Grading a float solver's run against the exact flow: `grade` and `work_precision`.

The run is any `t, y` (scipy's `OdeResult` has `.t`, shape (times,), and `.y`, shape
(states, times)). The exact flow starts from the scene's `(q, u)` of `y[:, 0]` at `t[0]`
(`Scene.state`) and is asked once, for every time, in one batch query (`flow` with
`times`, contract E11); each stop's certified box minus the run's `(q, u)` at that time is
the error, an interval computed in exact rationals and rounded outward to floats, so it
contains the exact value minus the float one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, List, Mapping, NamedTuple, Optional, Sequence, Tuple, Union

from ._intervals import _float_down, _float_up
from ._oracle import Oracle, SceneLike, Uncertified
from ._scene import Scene, _vector

__all__ = ["Grade", "grade", "work_precision", "WorkPrecisionRow", "WorkPrecision"]


@dataclass
class Grade:
    """A run graded against the exact flow.

    - `t`: the run's times (numpy, (times,)).
    - `error`: numpy, (times, n + m, 2): per time and component of (q, u) (n coordinates,
      m = n - k quasi-velocities), an interval [lo, hi] containing the exact value minus
      the run's float value; [-inf, inf] at a refused time.
    - `max_error`: a float proved to bound |error| at every certified time.
    - `passed`: None without `tol`; else True when `max_error <= tol` is proved, False
      otherwise (see `verdict`).
    - `verdict`: None without `tol`; else "passed", "failed" (an error proved beyond tol),
      "straddle" (neither proved: an error's interval contains tol; a higher precision may
      decide) or "refused" (some time was not certified, and no error is proved beyond tol).
    - `refused`: the times not certified, each `(t, cause)` (`OracleError.cause`, or its
      `reason` from a binary that does not name a cause).
    - `precision`: the bits the exact flow was computed with."""

    t: Any
    error: Any
    max_error: float
    passed: Optional[bool]
    verdict: Optional[str]
    refused: List[Tuple[float, Optional[str]]] = field(default_factory=list)
    precision: int = 53
    tol: Optional[float] = None

    def __repr__(self) -> str:
        return (f"Grade({len(self.t)} times, max_error={self.max_error:.3e}, "
                f"passed={self.passed}, verdict={self.verdict!r}, "
                f"refused={len(self.refused)}, precision={self.precision})")


def _times_and_states(sol: Any, t: Any, y: Any) -> Tuple[Any, Any]:
    import numpy as np

    if sol is not None:
        if t is not None or y is not None:
            raise ValueError("grade: give sol, or t and y, not both")
        t, y = getattr(sol, "t", None), getattr(sol, "y", None)
        if t is None or y is None:
            raise ValueError("grade: sol has no .t and .y (a scipy OdeResult has both)")
    if t is None or y is None:
        raise ValueError("grade: give sol (with .t and .y), or both t and y")
    tt = np.asarray(t, dtype=np.float64)
    yy = np.asarray(y, dtype=np.float64)
    if tt.ndim != 1 or len(tt) == 0:
        raise ValueError(f"t: expected a non-empty vector of times (a 1-D array), got shape "
                         f"{tt.shape}")
    if yy.ndim != 2 or yy.shape[1] != len(tt):
        hint = " (y is (states, times) as scipy gives it: pass y.T)" \
            if yy.ndim == 2 and yy.shape[0] == len(tt) else ""
        raise ValueError(f"y: expected shape (states, {len(tt)}) for {len(tt)} times, got "
                         f"{yy.shape}{hint}")
    if not (np.all(np.isfinite(tt)) and np.all(np.isfinite(yy))):
        raise ValueError("t, y: a value is not finite")
    if len(tt) > 1 and not np.all(np.diff(tt) > 0):
        raise ValueError("t: times must be strictly increasing")
    return tt, yy


def _sub(lo: Any, hi: Any, x: float) -> Tuple[float, float]:
    """Floats enclosing [lo, hi] - x, exact then rounded outward."""
    if type(lo) is float and type(hi) is float:
        a, b = lo - x, hi - x
        # a float difference is exact when it reads back (checked exactly, in rationals)
        if Fraction(a) != Fraction(lo) - Fraction(x):
            a = _float_down(Fraction(lo) - Fraction(x))
        if Fraction(b) != Fraction(hi) - Fraction(x):
            b = _float_up(Fraction(hi) - Fraction(x))
        return a, b
    return _float_down(Fraction(lo) - Fraction(x)), _float_up(Fraction(hi) - Fraction(x))


def _dimensions(scene: Any, oracle: Oracle, params: Any) -> Tuple[int, int]:
    if isinstance(scene, Scene):
        return scene.n, scene.m
    entry = oracle.scenes(scene, params=params)["scenes"][0]
    return int(entry["n"]), int(entry["n"]) - int(entry["k"])


def _state(scene: Any, y: Any, n: int, m: int, params: Any, check: bool
           ) -> Tuple[List[float], List[float]]:
    if isinstance(scene, Scene):
        if check:
            return scene.state(y, params)
        ys = _vector(y, "y")
        if len(ys) == n + m:
            return ys[:n], ys[n:]
        return _unchecked(scene, ys, params)
    ys = _vector(y, "y")
    if len(ys) != n + m:
        raise ValueError(f"y: {len(ys)} states; the built-in scene `{scene}` is graded from "
                         f"[q, u] ({n + m} entries): for [q, qdot] pose it as a "
                         f"dalembert.Scene")
    return ys[:n], ys[n:]


def _unchecked(scene: Scene, ys: List[float], params: Any) -> Tuple[List[float], List[float]]:
    """(q, u) of a later time of the run: u from qdot as `Scene.state` takes it, without the
    check that qdot is in D (its drift from D is part of the run's error)."""
    import numpy as np

    n = scene.n
    if len(ys) != 2 * n:
        return scene.state(ys, params)  # the error message for a wrong length
    q, qd = ys[:n], np.array(ys[n:])
    if scene.get("basis") is None:
        coords = list(scene["coordinates"])
        return q, [float(qd[coords.index(f)]) for f in scene["free"]]
    E = scene.basis_at(q, params)
    return q, [float(x) for x in np.linalg.lstsq(E.T, qd, rcond=None)[0]]


def grade(sol: Any = None, *, t: Any = None, y: Any = None,
          scene: Union[Scene, SceneLike], tol: Optional[float] = None, precision: int = 53,
          params: Optional[Mapping[str, float]] = None, oracle: Optional[Oracle] = None,
          max_steps: Optional[int] = None) -> Grade:
    """Grade a run (`sol` with `.t` and `.y`, or `t` and `y` arrays, y of shape (states,
    times)) against the exact flow of `scene` from `scene.state(y[:, 0])` at `t[0]`: one
    batch query (`flow` with `times`), at `precision` bits (53, or up to 1024: the same
    call). `scene`: a `Scene` (y as [q, qdot] or [q, u]), or a built-in name or dict (y as
    [q, u]). `oracle`: the session to ask (default: a new one, closed after). Returns a
    `Grade`. A time not certified is in `refused` with its cause; the times before it are
    graded."""
    import numpy as np

    tt, yy = _times_and_states(sol, t, y)
    if tol is not None and not (isinstance(tol, (int, float)) and tol >= 0
                                and math.isfinite(tol)):
        raise ValueError(f"tol: expected a finite number >= 0, got {tol!r}")
    if isinstance(scene, Mapping) and not isinstance(scene, Scene):
        scene = Scene(scene)
    own = oracle is None
    o = Oracle() if oracle is None else oracle
    try:
        n, m = _dimensions(scene, o, params)
        states = [_state(scene, yy[:, j], n, m, params, j == 0) for j in range(len(tt))]
        q0, u0 = states[0]
        times = []
        for tj in tt:
            d = float(tj) - float(tt[0])
            if Fraction(d) != Fraction(float(tj)) - Fraction(float(tt[0])):
                raise ValueError(f"t: {float(tj)!r} - t[0] = {float(tt[0])!r} is not a float "
                                 "exactly, so the "
                                 "exact flow cannot be asked at it: start the run at t = 0")
            times.append(d)
        query = o.query("flow", scene=scene, params=params, q=q0, u=u0, times=times,
                        precision=precision if precision != 53 else None,
                        max_steps=max_steps)
        refused: List[Tuple[float, Optional[str]]] = []
        try:
            stops = list(o.ask(query)["at"])
        except Uncertified as e:
            stops = list(e.at)
            cause = e.cause or e.reason
            refused = [(float(tj), cause) for tj in tt[len(stops):]]
    finally:
        if own:
            o.close()
    error = np.full((len(tt), n + m, 2), [-np.inf, np.inf])
    max_error = 0.0
    proved_beyond = False
    for j, stop in enumerate(stops):
        q, u = states[j]
        for c, (iv, x) in enumerate(zip(list(stop["q"]) + list(stop["u"]), q + u)):
            lo, hi = _sub(iv[0], iv[1], x)
            error[j, c] = (lo, hi)
            max_error = max(max_error, abs(lo), abs(hi))
            if tol is not None and (lo > tol or hi < -tol):
                proved_beyond = True
    passed: Optional[bool] = None
    verdict: Optional[str] = None
    if tol is not None:
        if proved_beyond:
            verdict = "failed"
        elif refused:
            verdict = "refused"
        elif max_error <= tol:
            verdict = "passed"
        else:
            verdict = "straddle"
        passed = verdict == "passed"
    return Grade(t=tt, error=error, max_error=max_error, passed=passed, verdict=verdict,
                 refused=refused, precision=precision, tol=tol)


class WorkPrecisionRow(NamedTuple):
    """One run of `work_precision`: its label, the rtol or cost given with it (or the
    run's `nfev` when none was given), the proved max error and the whole `Grade`."""

    label: str
    given: Any
    max_error: float
    grade: Grade


class WorkPrecision(List[WorkPrecisionRow]):
    """The rows of `work_precision`; `figure` the matplotlib Figure (None without
    matplotlib); `table()` the rows as text."""

    figure: Any = None

    def table(self) -> str:
        lines = [f"{'run':<24} {'given':>12} {'proved max error':>18}  refused"]
        for r in self:
            given = f"{r.given:.3g}" if isinstance(r.given, (int, float)) else str(r.given)
            lines.append(f"{r.label:<24} {given:>12} {r.max_error:>18.3e}  "
                         f"{len(r.grade.refused)}")
        return "\n".join(lines)


def work_precision(solver_runs: Sequence[Any], *, scene: Union[Scene, SceneLike],
                   precision: int = 106, params: Optional[Mapping[str, float]] = None,
                   oracle: Optional[Oracle] = None, plot: Optional[bool] = None
                   ) -> WorkPrecision:
    """Grade each run of `solver_runs`, items `(label, sol)` or `(label, sol, given)`
    (`given` the rtol or cost to plot against; default the run's `nfev`), at `precision`
    bits, in one session. Returns a `WorkPrecision` of rows (label, given, max_error,
    grade); with matplotlib installed (or `plot=True`) its `figure` plots the proved max
    error against `given`, log-log (`plot=False`: no figure)."""
    own = oracle is None
    o = Oracle() if oracle is None else oracle
    rows = WorkPrecision()
    try:
        for i, run in enumerate(solver_runs):
            if not isinstance(run, (tuple, list)) or len(run) not in (2, 3):
                raise ValueError(f"solver_runs[{i}]: expected (label, sol) or (label, sol, "
                                 f"given), got {type(run).__name__}")
            label, sol = str(run[0]), run[1]
            given = run[2] if len(run) == 3 else getattr(sol, "nfev", None)
            g = grade(sol, scene=scene, precision=precision, params=params, oracle=o)
            rows.append(WorkPrecisionRow(label, given, g.max_error, g))
    finally:
        if own:
            o.close()
    if plot is not False:
        try:
            from matplotlib.figure import Figure
        except ImportError:
            if plot:
                raise
            return rows
        fig = Figure(figsize=(5, 4))
        ax = fig.add_subplot()
        for r in rows:
            if isinstance(r.given, (int, float)) and r.max_error > 0:
                ax.loglog([r.given], [r.max_error], "o", label=r.label)
        ax.set_xlabel("rtol or cost given")
        ax.set_ylabel(f"proved max error ({precision} bits)")
        ax.legend(fontsize="small")
        rows.figure = fig
    return rows
