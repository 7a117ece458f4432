"""The reference data under tests/data/ is what its header says it is.

tests/data/andrews_reference.csv: the `recomputed` column is reproduced by the script named in
the header (tests/data/andrews_reference.py), and the initial values in `y0` are consistent with
the test set's equations (the published q̈0 and λ0 solve the augmented system at q0).

Run: /usr/bin/python3 -m pytest -q tests/python/test_reference_data.py
"""

import csv
import importlib.util
import io
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("scipy", reason="needs SciPy (use Debian's /usr/bin/python3)")
pytest.importorskip("sympy", reason="needs SymPy (use Debian's /usr/bin/python3)")

DATA = Path(__file__).resolve().parents[1] / "data"


def load_script():
    spec = importlib.util.spec_from_file_location("andrews_reference", DATA / "andrews_reference.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def read_table(text):
    rows = list(csv.reader(line for line in io.StringIO(text) if not line.startswith("#")))
    assert rows[0] == ["index", "name", "y0", "published", "recomputed"]
    return rows[1:]


@pytest.fixture(scope="module")
def andrews():
    return load_script(), read_table((DATA / "andrews_reference.csv").read_text())


def test_andrews_header_names_its_sources(andrews):
    header = [line for line in (DATA / "andrews_reference.csv").read_text().splitlines()
              if line.startswith("#")]
    text = " ".join(header)
    for must in ("Test Set for IVP Solvers", "Report 43/2006", "tests/data/andrews_reference.py"):
        assert must in text


def test_andrews_published_columns_are_the_scripts(andrews):
    mod, rows = andrews
    assert len(rows) == 27
    assert [r[2] for r in rows] == mod.Y0
    assert [r[3] for r in rows] == mod.PUBLISHED
    assert [r[1] for r in rows] == mod.NAMES


def test_andrews_recomputed_column_is_reproduced(andrews):
    mod, rows = andrews
    y, g_end = mod.end_state(mod.model(), 1e-13)
    stored = np.array([float(r[4]) for r in rows])
    rel = np.abs(y - stored) / np.abs(stored)
    # Same script: identical up to library round-off, which differs between processors (NumPy's
    # and OpenBLAS's kernels are chosen by the instruction set) by up to about 1e-11 relative in
    # the velocities and accelerations. A column made at rtol 1e-12 instead of 1e-13 differs by
    # 5e-11, so 2e-11 still catches a stale file.
    assert rel.max() < 2e-11, rel
    assert g_end < 1e-13


def test_andrews_initial_values_are_consistent(andrews):
    """The published q̈0, λ0 solve M q̈ + Gᵀλ = f, G q̈ = −(∂(G q̇)/∂q) q̇ at q0, q̇0 = 0."""
    mod, rows = andrews
    fns = mod.model()
    y0 = np.array([float(r[2]) for r in rows])
    a, lam = mod.solve(*fns, y0[:7], y0[7:14])
    np.testing.assert_allclose(a, y0[14:21], rtol=1e-12, atol=1e-12 * np.abs(y0[14:21]).max())
    np.testing.assert_allclose(lam, y0[21:], rtol=1e-12, atol=1e-12 * np.abs(y0[21:]).max())
    assert np.abs(np.ravel(fns[4](y0[:7], y0[7:14]))).max() < 1e-16
