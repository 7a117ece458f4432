"""summary: counts by status, solver statistics over completed samples, energy drift."""
import numpy as np
import pytest

from kanesens_post.io import open_run
from kanesens_post.summary import summarize
from post_fixtures import write_run


def test_counts_stats_drift(tmp_path):
    ns, nt = 6, 4
    t = np.linspace(0, 1, nt)
    energy = np.tile(np.array([1.0, 1.0 + 1e-6, 1.0 - 3e-6, 1.0]), (ns, 1))
    energy[2] += np.array([0, 0, 0.5, 0.5])            # failed sample: excluded from drift
    residual = np.full((ns, nt), 1e-9)
    residual[4, 3] = -2e-7
    path = write_run(tmp_path / "s.h5", time=t, state_names=["a.q"], parameter_names=["k"],
                     parameters=np.arange(ns)[:, None], states=np.zeros((ns, nt, 1)),
                     status=[1, 1, -3, 0, 1, -7],
                     message=["", "", "CV_ERR_FAILURE", "", "", "CV_TOO_MUCH_WORK"],
                     outputs={"energy": energy, "constraint_residual": residual},
                     solver_stats={"steps": [10, 30, 999, 0, 20, 5],
                                   "wall_seconds": [0.1, 0.3, 9.0, 0, 0.2, 0.1]})
    r = summarize(open_run(path))
    assert (r["samples"], r["ok"], r["failed"], r["not_run"]) == (6, 3, 2, 1)
    assert r["solver_stats"]["steps"] == {"median": 20.0, "max": 30.0, "total": 60.0}
    assert r["solver_stats"]["wall_seconds"]["max"] == pytest.approx(0.3)
    assert r["energy_drift"]["max_abs"] == pytest.approx(3e-6, rel=1e-6)
    assert r["constraint_residual_max"] == pytest.approx(2e-7)
    assert {f["message"] for f in r["failures"]} == {"CV_ERR_FAILURE", "CV_TOO_MUCH_WORK"}
