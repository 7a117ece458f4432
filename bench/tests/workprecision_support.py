"""Shared helpers of the benchmark checks (bench/tests: the stability atlas test_stability_*.py
and test_bench_workprecision.py): run `$KANESENS_WORKPRECISION ... --json` and pick rows.
Environment: KANESENS_WORKPRECISION = path of the kanesens-workprecision executable, KANESENS =
path of the kanesens executable (the tests skip without them; ctest sets both),
KANESENS_SOURCE_DIR = the repository (default: two levels up)."""
import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(os.environ.get("KANESENS_SOURCE_DIR") or Path(__file__).resolve().parents[2])


def _executable(variable: str, example: str) -> str:
    path = os.environ.get(variable)
    if not path:
        pytest.skip(f"{variable} is not set; ctest sets it, or run: {variable}={example} pytest bench/tests")
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        pytest.fail(f"{variable}={path} is not an executable file")
    return path


def exe() -> str:
    """The kanesens executable."""
    return _executable("KANESENS", "build/kanesens")


def harness() -> str:
    """The work-precision benchmark, kanesens-workprecision."""
    return _executable("KANESENS_WORKPRECISION", "build/bench/kanesens-workprecision")


def run(*args, check=True):
    """`kanesens-workprecision ARGS --repeat 1 --json` from the repository root."""
    p = subprocess.run([harness(), *map(str, args), "--repeat", "1", "--json"],
                       cwd=ROOT, capture_output=True, text=True)
    if check:
        assert p.returncode == 0, p.stderr
        return json.loads(p.stdout)
    return p


def rows(data, method):
    return [r for r in data["rows"] if r["method"] == method]


def row(data, method, **match):
    found = [r for r in rows(data, method) if all(r[k] == v for k, v in match.items())]
    assert len(found) == 1, (method, match, [(r["tol"], r["h"]) for r in rows(data, method)])
    return found[0]
