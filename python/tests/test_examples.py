"""The example Python clients run as a user runs them, against the installed binary:
examples/python/check_dla.py (a DLA step written in Python checked through the batch
protocol), own_system.py (a system posed inline, checked against its closed form),
validate_scheme.py (a scheme validated on the contact oscillator) and graded_scipy.py (a
sympy model, scipy runs graded at 53 and 106 bits, a Hypothesis property over certified
starts). Each imports the installed `dalembert` package, asserts its own properties and
prints `ok` last."""

import os
import subprocess
import sys

import pytest

from dalembert import find_binary

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.mark.parametrize("script", ["check_dla.py", "own_system.py", "validate_scheme.py",
                                    "graded_scipy.py"])
def test_example_client_passes(script):
    if script == "graded_scipy.py":
        for module in ("sympy", "scipy", "hypothesis", "numpy"):
            pytest.importorskip(module)
    out = subprocess.run([sys.executable, os.path.join(ROOT, "examples", "python", script),
                          find_binary()], capture_output=True, text=True,
                         env={**os.environ, "PYTHONDONTWRITEBYTECODE": "1"})
    assert out.returncode == 0, out.stdout + out.stderr
    assert out.stdout.rstrip().endswith("ok"), out.stdout
