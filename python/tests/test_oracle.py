"""Tests of the client (`dalembert.Oracle`) and of its outward-rounded helpers, under pytest
(.ci/run runs them in a virtual environment with the package installed).

References are derived here, independently of the binary: the nonholonomic particle
(q = (x, y, z), L = |qd|^2 / 2, constraint zd = y xd, spec/contract.md) has the closed form
    y = y0 + yd t,  x = x0 + A (asinh y - asinh y0),  z = z0 + A (sqrt(1 + y^2) - sqrt(1 + y0^2)),
    xd = A yd / sqrt(1 + y^2),  A = xd0 sqrt(1 + y0^2) / yd   (yd != 0)
(tests/closed_forms.rs). For `retract`/`step` from a pair (q0, q1) the trajectory must reach
q1 + s (-y1, 0, 1) at time h: yd = (y1 - y0) / h, and with a = asinh y1 - asinh y0,
b = sqrt(1 + y1^2) - sqrt(1 + y0^2) the two remaining equations are linear in (A, s):
    A = (x1 - x0 + y1 (z1 - z0)) / (a + y1 b),   s = A b - (z1 - z0).
Then q2 = q(2h) (y2 = 2 y1 - y0), p_minus = (A yd sqrt(1 + y0^2), yd), p_plus =
(A yd sqrt(1 + y1^2), yd), u0 = (A yd / sqrt(1 + y0^2), yd), and since xd^2 (1 + y^2) = A^2 yd^2
is constant the exact discrete Lagrangian is l = h yd^2 (A^2 + 1) / 2. These are evaluated
in 60-digit decimal arithmetic (decimal's ln and sqrt are correctly rounded), an error far
below 1e-40, and each enclosure must contain the reference up to that 1e-40.
"""

import json
import math
import os
import random
import stat
import subprocess
import sys
import tempfile
import unittest
from decimal import Decimal, localcontext
from fractions import Fraction

from unittest import mock

import dalembert._oracle
from dalembert import (
    Interval, InputError, Oracle, OracleError, ProtocolError, Uncertified, distance,
    find_binary, observed_order, quotient,
)
from dalembert._intervals import _ln_bounds
SLACK = Decimal("1e-40")  # bound on the error of the 60-digit references


def asinh(y):
    s = (abs(y) + (1 + y * y).sqrt()).ln()
    return s if y >= 0 else -s


def particle_pair(q0, q1, h):
    """The exact answers of retract/step/lagrangian for the particle, in Decimal."""
    with localcontext() as c:
        c.prec = 60
        (x0, y0, z0), (x1, y1, z1) = [[Decimal(v) for v in q] for q in (q0, q1)]
        h = Decimal(h)
        yd = (y1 - y0) / h
        r0, r1 = (1 + y0 * y0).sqrt(), (1 + y1 * y1).sqrt()
        a, b = asinh(y1) - asinh(y0), r1 - r0
        A = (x1 - x0 + y1 * (z1 - z0)) / (a + y1 * b)
        s = A * b - (z1 - z0)
        y2 = 2 * y1 - y0
        return {
            "defect": [s],
            "q1": [x1 - y1 * s, y1, z1 + s],
            "q2": [x0 + A * (asinh(y2) - asinh(y0)), y2, z0 + A * ((1 + y2 * y2).sqrt() - r0)],
            "p_minus": [A * yd * r0, yd],
            "p_plus": [A * yd * r1, yd],
            "u0": [A * yd / r0, yd],
            "l": h * yd * yd * (A * A + 1) / 2,
        }


def particle_flow(q0, u, t):
    with localcontext() as c:
        c.prec = 60
        (x0, y0, z0), (u1, u2), t = [Decimal(v) for v in q0], [Decimal(v) for v in u], Decimal(t)
        r0 = (1 + y0 * y0).sqrt()
        A = u1 * r0 / u2
        y = y0 + u2 * t
        r = (1 + y * y).sqrt()
        return {"q": [x0 + A * (asinh(y) - asinh(y0)), y, z0 + A * (r - r0)],
                "u": [u1 * r0 / r, u2]}


def random_pairs(n, seed=17):
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        h = rng.uniform(0.05, 0.5)
        q0 = [rng.uniform(-1, 1) for _ in range(3)]
        v = [rng.uniform(-1, 1), rng.choice([-1, 1]) * rng.uniform(0.2, 1), 0.0]
        v[2] = q0[1] * v[0] + rng.uniform(-0.05, 0.05)  # off the constraint: defect != 0
        out.append((q0, [a + h * b for a, b in zip(q0, v)], h))
    return out


class OracleTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.oracle = Oracle(scene="particle")

    @classmethod
    def tearDownClass(cls):
        status = cls.oracle.close()
        assert status == 0, f"batch exited with {status}"

    def encloses(self, box, ref):
        """Every Interval of box contains the reference (to SLACK) and is narrow."""
        box = box if isinstance(box, list) else [box]
        ref = ref if isinstance(ref, list) else [ref]
        self.assertEqual(len(box), len(ref))
        for iv, r in zip(box, ref):
            self.assertIsInstance(iv, Interval)
            with localcontext() as c:
                c.prec = 80  # exact: the endpoints have at most 17 significant digits
                self.assertTrue(Decimal(iv.lo) - SLACK <= r <= Decimal(iv.hi) + SLACK, (iv, r))
            self.assertLess(iv.hi - iv.lo, 1e-11 * max(1.0, abs(iv.lo)), iv)

    def test_step_retract_lagrangian_enclose_the_closed_form(self):
        pairs = random_pairs(12)
        queries = [self.oracle.query(cmd, q0=q0, q1=q1, h=h)
                   for q0, q1, h in pairs for cmd in ("step", "retract", "lagrangian")]
        answers = self.oracle.run(queries)
        for i, (q0, q1, h) in enumerate(pairs):
            ref = particle_pair(q0, q1, h)
            step, retract, lag = answers[3 * i: 3 * i + 3]
            for key in ("q1", "q2", "p_minus", "p_plus"):
                self.encloses(step[key], ref[key])
            for key in ("q1", "u0", "defect"):
                self.encloses(retract[key], ref[key])
            self.encloses(lag.l, ref["l"])
            self.encloses(lag.defect, ref["defect"])
            # the pairs are off the manifold by construction: |s| > 1e-4 h, proved
            self.assertEqual(retract.member, "no")
            self.assertTrue(retract.defect[0].excludes_zero())

    def test_flow_encloses_the_closed_form(self):
        rng = random.Random(5)
        for _ in range(8):
            q0 = [rng.uniform(-1, 1) for _ in range(3)]
            u = [rng.uniform(-1, 1), rng.uniform(0.2, 1)]
            t = rng.uniform(0.1, 3)
            f = self.oracle.flow(q0, u, t)
            ref = particle_flow(q0, u, t)
            self.encloses(f.q, ref["q"])
            self.encloses(f.u, ref["u"])

    def test_inline_scene_is_the_particle(self):
        inline = {"coordinates": ["x", "y", "z"], "constraints": [["-y", 0, 1]],
                  "free": ["x", "y"]}
        q0, q1, h = random_pairs(1, seed=3)[0]
        s = self.oracle.step(q0, q1, h, scene=inline)
        ref = particle_pair(q0, q1, h)
        for key in ("q1", "q2", "p_minus", "p_plus"):
            self.encloses(s[key], ref[key])

    def test_check_answers_intervals_and_a_verdict(self):
        # an exact straight line y = const, zd = y xd: every row is on the exact flow
        q = [[k / 8, 0.5, k / 16] for k in range(5)]  # x = t, z = y x, h = 1/8
        c = self.oracle.check(q, 0.125, tol=1e-12)
        self.assertTrue(c.passed)
        self.assertEqual(len(c.distance), 5)
        self.assertTrue(all(0 in d and d.hi < 1e-12 for d in c.distance), c.distance)
        self.assertTrue(all(0 in d[0] for d in c.defect), c.defect)
        # moved by 1e-3 at the last row: proved beyond the tolerance, passed is False
        q[-1][0] += 1e-3
        c = self.oracle.check(q, 0.125, tol=1e-6)
        self.assertFalse(c.passed)
        self.assertTrue(c.max_distance.lo <= Fraction(q[-1][0]) - Fraction(1, 2) <= c.max_distance.hi)

    def test_dense_flow_and_a_check_at_times_with_a_defect_tolerance(self):
        a = self.oracle.flow([0, 0.5, 0], [0.8, 0.8], times=[0.25, 0.5, 1])
        self.assertEqual([s.t for s in a.at], [0.25, 0.5, 1])
        self.assertTrue(all(s.q[0].lo <= s.q[0].hi for s in a.at))
        # the straight line x = t, y = 1/2, z = t/2 at uneven times: on the exact flow
        t = [0, 0.125, 0.375, 0.5]
        q = [[x, 0.5, x / 2] for x in t]
        c = self.oracle.check(q, t=t, tol=1e-12, defect_tol=1e-12)
        self.assertTrue(c.passed)
        self.assertTrue(0 in c.max_defect and c.max_defect.hi < 1e-12, c.max_defect)
        q[2][0] += 1e-3  # off the manifold: the defect is proved beyond 1e-6
        c = self.oracle.check(q, t=t, tol=1e-2, defect_tol=1e-6)
        self.assertFalse(c.passed)

    def test_endpoints_are_the_printed_numbers(self):
        # the same query sent to a separate process by hand: each endpoint is bit for bit
        # the number the binary printed (no rounding, no re-centring in the module)
        line = json.dumps({"id": 1, "cmd": "step", "scene": "particle", "q0": [0.1, 0.2, 0.3],
                           "q1": [0.5, 0.6, 0.55], "h": 0.3})
        raw = subprocess.run([find_binary(), "batch"], input=line + "\n", text=True,
                             capture_output=True, check=True).stdout
        printed = json.loads(raw, parse_float=str)["ok"]["q2"]
        got = self.oracle.step([0.1, 0.2, 0.3], [0.5, 0.6, 0.55], 0.3).q2
        for iv, (lo, hi) in zip(got, printed):
            self.assertEqual((iv.lo.hex(), iv.hi.hex()), (float(lo).hex(), float(hi).hex()))

    def test_errors_are_typed_and_the_session_goes_on(self):
        with self.assertRaises(InputError) as e:
            self.oracle.step([0, 0], [0.4, 0.4, 0.08], 0.5)
        self.assertEqual(e.exception.code, 2)
        self.assertIn("3 components", e.exception.message)
        with self.assertRaises(InputError) as e:
            self.oracle.flow([0, 0, 0], [1, 1], 1, scene="no-such-scene")
        self.assertIn("no-such-scene", e.exception.message)
        with self.assertRaises(Uncertified) as e:
            self.oracle.flow([0, 0, 0], [0.8, 0.8], 1e4, deadline=1e-3)
        self.assertEqual(e.exception.code, 3)
        self.assertTrue(e.exception.past_budget)
        self.assertTrue(e.exception.message.startswith("not certified within the budget"))
        self.assertTrue(e.exception.reached is None or 0 <= e.exception.reached < 1e4)
        self.assertIsNone(self.oracle_input_reason())
        with self.assertRaises(InputError):  # refused here: JSON cannot carry NaN
            self.oracle.flow([0, math.nan, 0], [1, 1], 1)
        self.assertIsInstance(self.oracle.flow([0, 0, 0], [1, 1], 0.5).q[0], Interval)

    def oracle_input_reason(self):
        try:
            self.oracle.step([0, 0], [0.4, 0.4, 0.08], 0.5)
        except InputError as e:
            return e.reason
        raise AssertionError("a wrong dimension was answered")

    def test_a_bad_line_is_input_error_and_the_session_goes_on(self):
        with self.assertRaises(InputError) as e:
            self.oracle.ask_line("this is not JSON")
        self.assertIsNone(e.exception.id)
        self.assertIn("not JSON", e.exception.message)
        with self.assertRaises(InputError) as e:
            self.oracle.ask_line('{"id": "k", "cmd": "step", "scene": "particle", "bogus": 1}')
        self.assertEqual(e.exception.id, "k")
        self.assertIn("bogus", e.exception.message)
        ok = self.oracle.ask_line('{"id": [7], "cmd": "flow", "scene": "particle", '
                                  '"q": [0, 0, 0], "u": [0, 1], "t": 0.25}')
        self.assertEqual(ok.q[1], Interval(0.25, 0.25))  # y = t exactly

    def test_run_keeps_order_and_returns_errors_in_place(self):
        qs = [self.oracle.query("flow", q=[0, 0, 0], u=[0, 1], t=k / 4) for k in range(40)]
        qs[7] = self.oracle.query("flow", q=[0, 0], u=[0, 1], t=1)
        out = self.oracle.run(qs)
        self.assertIsInstance(out[7], InputError)
        for k, a in enumerate(out):
            if k != 7:
                self.assertEqual(a.q[1], Interval(k / 4, k / 4))


def fake_binary(body):
    """An executable standing in for dalembert (argv[1] == "batch")."""
    f = tempfile.NamedTemporaryFile("w", suffix=".py", delete=False)
    f.write(f"#!{sys.executable}\nimport sys, json\n{body}\n")
    f.close()
    os.chmod(f.name, os.stat(f.name).st_mode | stat.S_IXUSR)
    return f.name


class ProtocolTest(unittest.TestCase):
    def run_fake(self, body):
        exe = fake_binary(body)
        try:
            o = Oracle(binary=exe)
            try:
                with self.assertRaises(ProtocolError) as e:
                    o.flow([0, 0, 0], [1, 1], 1, scene="particle")
                return str(e.exception)
            finally:
                o.close()
        finally:
            os.unlink(exe)

    def test_an_answer_to_another_id_is_refused(self):
        msg = self.run_fake('for line in sys.stdin:\n'
                            '    print(json.dumps({"id": 99, "ok": {}}), flush=True)')
        self.assertIn("99", msg)

    def test_a_process_that_ends_is_refused(self):
        self.assertIn("ended", self.run_fake("sys.exit(0)"))

    def test_output_that_is_not_json_is_refused(self):
        self.assertIn("not JSON", self.run_fake('sys.stdin.readline(); print("hello", flush=True)'))

    def test_binary_from_scripts_then_environment_then_path(self):
        here = find_binary()
        self.assertTrue(os.path.isfile(here) and os.access(here, os.X_OK), here)
        saved = dict(os.environ)
        try:
            with tempfile.TemporaryDirectory() as d:
                exe = os.path.join(d, "dalembert")
                with open(exe, "w") as f:
                    f.write("#!/bin/sh\n")
                os.chmod(exe, 0o755)
                with mock.patch.object(dalembert._oracle, "_script_dirs", lambda: [d]):
                    os.environ["DALEMBERT"] = "/x/from-env"
                    self.assertEqual(find_binary(), exe)  # installed beside the scripts
        finally:
            os.environ.clear()
            os.environ.update(saved)
        no_scripts = mock.patch.object(dalembert._oracle, "_script_dirs", lambda: [])
        try:
            no_scripts.start()
            os.environ["DALEMBERT"] = "/x/from-env"
            self.assertEqual(find_binary("/x/arg"), "/x/arg")
            self.assertEqual(find_binary(), "/x/from-env")
            del os.environ["DALEMBERT"]
            os.environ["PATH"] = ""
            with self.assertRaises(FileNotFoundError):
                find_binary()
        finally:
            no_scripts.stop()
            os.environ.clear()
            os.environ.update(saved)


TRICKY = [0.0, -0.0, 1e-300, 5e-324, 1.0, 0.1, 1 / 3, 1e16, 2.0 ** 53 + 2, -7.25, 1e300]


class OutwardTest(unittest.TestCase):
    """The module's own bounds contain the exact rational results."""

    def test_distance_contains_every_exact_distance(self):
        rng = random.Random(11)
        pool = TRICKY + [rng.uniform(-2, 2) for _ in range(30)]
        for _ in range(3000):
            x = [rng.choice(pool) for _ in range(3)]
            box = [Interval(*sorted((rng.choice(pool), rng.choice(pool)))) for _ in range(3)]
            d = distance(x, box)
            # the exact extremes over the box, in rationals
            far = max(max(abs(Fraction(xi) - Fraction(b.lo)), abs(Fraction(xi) - Fraction(b.hi)))
                      for xi, b in zip(x, box))
            near = max(max(Fraction(b.lo) - Fraction(xi), Fraction(xi) - Fraction(b.hi), 0)
                       for xi, b in zip(x, box))
            self.assertTrue(d.lo <= near and far <= d.hi, (x, box, d))

    def test_quotient_contains_the_exact_quotients(self):
        rng = random.Random(12)
        pos = [v for v in TRICKY if v > 0] + [rng.uniform(0, 3) for _ in range(30)]
        for _ in range(3000):
            a = Interval(*sorted((rng.choice(pos), rng.choice(pos))))
            b = Interval(*sorted((rng.choice(pos), rng.choice(pos))))
            r = quotient(a, b)
            for n in (a.lo, a.hi):
                for d in (b.lo, b.hi):
                    self.assertIn(Fraction(n) / Fraction(d), r, (a, b, r))

    def test_ln_bounds_against_decimal(self):
        rng = random.Random(13)
        with localcontext() as c:
            c.prec = 50
            for _ in range(300):
                x = Fraction(rng.choice(TRICKY[2:] + [rng.uniform(0, 10)])).__abs__() or Fraction(1)
                lo, hi = _ln_bounds(x)
                ref = (Decimal(x.numerator) / Decimal(x.denominator)).ln()
                self.assertTrue(Decimal(lo.numerator) / Decimal(lo.denominator) - Decimal("1e-45")
                                <= ref <= Decimal(hi.numerator) / Decimal(hi.denominator)
                                + Decimal("1e-45"))
                self.assertLess(hi - lo, Fraction(1, 2 ** 100))

    def test_observed_order_contains_the_exact_order(self):
        # e = C h^p exactly (dyadic C and h): the order is exactly p, and the interval is tight
        for p in (1, 2, 3, 4):
            for c in (0.375, 1.0, 3e-5):
                e_a, e_b = c * 0.25 ** p, c * 0.125 ** p
                r = observed_order(Interval(e_a, e_a), Interval(e_b, e_b), 0.25, 0.125)
                self.assertIn(p, r)
                self.assertLess(r.hi - r.lo, 1e-14)
        # and with widths: every exact order from the corners lies inside
        r = observed_order(Interval(0.008, 0.0081), Interval(0.001, 0.00101), 0.2, 0.1)
        with localcontext() as c:
            c.prec = 40
            for ea in (0.008, 0.0081):
                for eb in (0.001, 0.00101):
                    p = (Decimal(ea) / Decimal(eb)).ln() / (Decimal(0.2) / Decimal(0.1)).ln()
                    self.assertTrue(Decimal(r.lo) <= p <= Decimal(r.hi), (p, r))
        with self.assertRaises(ValueError):
            observed_order(Interval(0.0, 1e-3), Interval(1e-4, 2e-4), 0.2, 0.1)
