"""Kept for old scripts only: the client is the `dalembert` Python package (python/dalembert;
`pip install .` installs it with the binary; docs/python.md). This module is its re-export;
new code imports `dalembert`."""
from dalembert import *  # noqa: F401,F403
