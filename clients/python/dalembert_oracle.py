"""Kept for scripts that load this file by path (examples/python/*.py): the client is now
the `dalembert` Python package (python/dalembert; `pip install .` installs it with the
binary; docs/python.md). This module re-exports it: the installed package when there is
one, else the package's source in this repository (then the binary comes from $DALEMBERT,
PATH, or the `binary` argument)."""

import os
import sys

try:
    import dalembert as _pkg
    _pkg.Oracle  # noqa: B018 (the package, not a directory of that name on the path)
except (ImportError, AttributeError):
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                    "python"))
    sys.modules.pop("dalembert", None)
    import dalembert as _pkg

from dalembert import (  # noqa: E402,F401
    Answer, InputError, Interval, Oracle, OracleError, Pending, ProtocolError, Uncertified,
    distance, down, find_binary, observed_order, quotient, to_array, up,
)

__all__ = [
    "Oracle", "Interval", "Answer", "Pending", "OracleError", "InputError", "Uncertified",
    "ProtocolError", "distance", "quotient", "observed_order", "down", "up", "find_binary",
    "to_array",
]
