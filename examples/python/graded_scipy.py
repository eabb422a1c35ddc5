#!/usr/bin/env python3
"""From a sympy model to graded scipy runs, with the `dalembert` package.

1. The model, in sympy.physics.mechanics: a blade (unicycle) on a plane, held by a spring
   to the origin, with a q-dependent inertia and a magnetic-like one-form,
       L = m/2 (xd^2 + yd^2) + (J + a cos^2 theta)/2 thetad^2 + a x thetad - k/2 (x^2 + y^2),
       -sin(theta) xd + cos(theta) yd = 0,
   as a `LagrangesMethod` with `nonhol_coneqs`. `dalembert.sympy.from_lagranges` makes the
   oracle's scene of it; the same method gives scipy its right-hand side (the Lagrange
   multiplier form, state [q, qdot]).
2. scipy's `solve_ivp` runs (RK45, DOP853, LSODA at several rtol), each graded by
   `dalembert.work_precision` against the exact flow: the table of the proved max error,
   at 53 and at 106 bits. At 53 bits the exact flow's own boxes (about 1e-13 wide here)
   bound what can be graded; at 106 bits the tight runs are graded too.
3. A Hypothesis property over `dalembert.strategies.states` (starts whose flow the oracle
   certifies to the horizon): DOP853 at rtol 1e-9 stays within 1e-6 of the exact flow.

Exit status 0 when every check passes; prints `ok` last.

Usage: graded_scipy.py [path/to/dalembert]   (default: the package's binary, $DALEMBERT,
or `dalembert` on PATH)
"""
import sys

import numpy as np
import sympy as sp
from hypothesis import given, settings
from scipy.integrate import solve_ivp
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

import dalembert
from dalembert.strategies import states
from dalembert.sympy import from_lagranges

# -- 1. the model ----------------------------------------------------------------------
t = dynamicsymbols._t
x, y, th = dynamicsymbols("x y theta")
xd, yd, thd = (c.diff(t) for c in (x, y, th))
m, J, a, k = sp.symbols("m J a k", positive=True)
L = m / 2 * (xd**2 + yd**2) + (J + a * sp.cos(th) ** 2) / 2 * thd**2 + a * x * thd \
    - k / 2 * (x**2 + y**2)
lm = LagrangesMethod(L, [x, y, th], nonhol_coneqs=[-sp.sin(th) * xd + sp.cos(th) * yd])
PARAMS = {m: 2.0, J: 0.75, a: 0.25, k: 1.5}
scene = from_lagranges(lm, PARAMS, name="spring_unicycle")

lm.form_lagranges_equations()
plain = sp.symbols("s0:7")  # x, y, theta, xd, yd, thetad, the multiplier
sub = {**dict(zip([xd, yd, thd], plain[3:6])), **dict(zip([x, y, th], plain[:3])),
       lm.lam_vec[0]: plain[6]}
mass_full = sp.lambdify(plain, lm.mass_matrix_full.subs(PARAMS).subs(sub), "numpy")
forcing_full = sp.lambdify(plain, lm.forcing_full.subs(PARAMS).subs(sub), "numpy")


def rhs(_t, s):
    """d/dt [q, qdot] (the multiplier solved for at each call)."""
    full = (*s, 0.0)
    sol = np.linalg.solve(np.array(mass_full(*full), dtype=float),
                          np.array(forcing_full(*full), dtype=float).ravel())
    return sol[:6]


def start(q, u):
    """[q, qdot] for the scene's (q, u): qdot = u1 e1 + u2 e2 of the derived basis (free x
    and theta: e1 = (1, tan theta, 0), e2 = (0, 0, 1))."""
    return [*q, u[0], np.tan(q[2]) * u[0], u[1]]


def main(binary=None):
    T = np.linspace(0.0, 1.5, 16)
    q0, u0 = [0.5, -0.25, 0.2], [0.3, 0.7]
    assert scene.state(start(q0, u0)) == (q0, u0)
    with dalembert.Oracle(binary=binary) as oracle:
        # -- 2. scipy runs, graded at 53 and 106 bits ------------------------------------
        runs = [(f"{method} rtol={rtol:.0e}",
                 solve_ivp(rhs, (0.0, 1.5), start(q0, u0), method=method, rtol=rtol,
                           atol=rtol * 1e-3, t_eval=T), rtol)
                for method, rtols in (("RK45", (1e-4, 1e-7)),
                                      ("DOP853", (1e-6, 1e-9, 1e-12, 1e-14)),
                                      ("LSODA", (1e-6,)))
                for rtol in rtols]
        tables = {}
        for bits in (53, 106):
            rows = dalembert.work_precision(runs, scene=scene, precision=bits, oracle=oracle,
                                            plot=False)
            print(f"-- the proved max error over {len(T)} times, exact flow at {bits} bits")
            print(rows.table())
            tables[bits] = rows
            for r in rows:
                assert not r.grade.refused, r
        # a tighter rtol of the same method is graded with a smaller proved error
        by = {r.label: r.max_error for r in tables[106]}
        assert by["DOP853 rtol=1e-12"] < by["DOP853 rtol=1e-09"] < by["DOP853 rtol=1e-06"]
        assert by["RK45 rtol=1e-07"] < by["RK45 rtol=1e-04"]
        # 53-bit boxes (about 1e-15 wide here) are most of what is proved at rtol 1e-14;
        # at 106 bits the proved error is the run's own
        tightest = [r for r in zip(tables[53], tables[106]) if r[0].label.endswith("1e-14")]
        print(f"DOP853 rtol=1e-14: proved {tightest[0][0].max_error:.2e} at 53 bits, "
              f"{tightest[0][1].max_error:.2e} at 106")
        # 106 bits grades at least as tightly as 53 (both are proved bounds of one error)
        for r53, r106 in zip(tables[53], tables[106]):
            assert r106.max_error <= r53.max_error * (1 + 1e-6) + 1e-12
        # a tolerance check of one run: proved within 1e-8 at 106 bits
        tight = dict((r[0], r[1]) for r in runs)["DOP853 rtol=1e-12"]
        g = dalembert.grade(tight, scene=scene, tol=1e-11, precision=106, oracle=oracle)
        print(f"DOP853 rtol=1e-12 against tol 1e-11: max error {g.max_error:.3e}, "
              f"verdict {g.verdict}")
        assert g.passed

        # -- 3. a Hypothesis property over certified starts -----------------------------
        checked = []

        @settings(max_examples=6, deadline=None, derandomize=True, database=None)
        @given(states(oracle, scene, 0.5, 0.5, t=1.0))
        def dop853_follows_the_exact_flow(s):
            sol = solve_ivp(rhs, (0.0, 1.0), start(s.q, s.u), method="DOP853", rtol=1e-9,
                            atol=1e-12, t_eval=[0.0, 0.5, 1.0])
            g = dalembert.grade(sol, scene=scene, tol=1e-6, oracle=oracle)
            assert g.passed, (s, g.max_error, g.verdict, g.refused)
            checked.append(g.max_error)

        dop853_follows_the_exact_flow()
        print(f"Hypothesis: {len(checked)} certified starts, DOP853 rtol=1e-9 within "
              f"{max(checked):.2e} of the exact flow")
    print("ok")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
