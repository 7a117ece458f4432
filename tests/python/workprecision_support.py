"""Shared helpers of the stability-atlas tests (tests/python/test_stability_*.py,
test_bench_workprecision.py): run `$KANESENS bench workprecision ... --json` and pick rows.
Environment: KANESENS = path of the kanesens executable (the tests skip without it; ctest sets
it), KANESENS_SOURCE_DIR = the repository (default: two levels up)."""
import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(os.environ.get("KANESENS_SOURCE_DIR") or Path(__file__).resolve().parents[2])


def exe() -> str:
    path = os.environ.get("KANESENS")
    if not path:
        pytest.skip("KANESENS is not set (path of the kanesens executable); "
                    "ctest sets it, or run: KANESENS=build/kanesens pytest tests/python")
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        pytest.fail(f"KANESENS={path} is not an executable file")
    return path


def run(*args, check=True):
    """`kanesens bench workprecision ARGS --repeat 1 --json` from the repository root."""
    p = subprocess.run([exe(), "bench", "workprecision", *map(str, args), "--repeat", "1", "--json"],
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
