"""summary: counts by status, solver statistics over completed samples, energy drift and
constraint residuals, on a synthetic file and on one that kanesens writes."""
import json
import os
import pathlib
import subprocess
import sys

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
    residual[4, 3] = 2e-7
    velocity = np.full((ns, nt), 1e-12)
    velocity[1, 2] = 3e-10
    velocity[2, 2] = 1.0                                # failed sample: excluded
    path = write_run(tmp_path / "s.h5", time=t, state_names=["a.q"], parameter_names=["k"],
                     parameters=np.arange(ns)[:, None], states=np.zeros((ns, nt, 1)),
                     status=[1, 1, -3, 0, 1, -7],
                     message=["", "", "CV_ERR_FAILURE", "", "", "CV_TOO_MUCH_WORK"],
                     outputs={"energy": energy, "position_residual": residual,
                              "velocity_residual": velocity},
                     solver_stats={"steps": [10, 30, 999, 0, 20, 5],
                                   "wall_seconds": [0.1, 0.3, 9.0, 0, 0.2, 0.1]})
    r = summarize(open_run(path))
    assert (r["samples"], r["ok"], r["failed"], r["not_run"]) == (6, 3, 2, 1)
    assert r["solver_stats"]["steps"] == {"median": 20.0, "max": 30.0, "total": 60.0}
    assert r["solver_stats"]["wall_seconds"]["max"] == pytest.approx(0.3)
    assert r["energy_drift"]["max_abs"] == pytest.approx(3e-6, rel=1e-6)
    assert r["position_residual_max"] == pytest.approx(2e-7)
    assert r["velocity_residual_max"] == pytest.approx(3e-10)
    assert {f["message"] for f in r["failures"]} == {"CV_ERR_FAILURE", "CV_TOO_MUCH_WORK"}


ROOT = pathlib.Path(os.environ.get("KANESENS_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
KANESENS = os.environ.get("KANESENS")


@pytest.mark.skipif(not KANESENS, reason="needs the kanesens executable (KANESENS)")
def test_residuals_of_a_real_run(tmp_path):
    """The residual outputs the writer creates (record: constraint_residual) are the ones the
    summary reads."""
    study = tmp_path / "s.yaml"
    study.write_text(f"kanesens: 1\nscene: {ROOT / 'configs/four_bar.yaml'}\ntime: {{end: 0.2, outputs: 5}}\n"
                     "sampling: {method: mc, samples: 2, seed: 1}\nrecord: [states, constraint_residual]\n")
    run = tmp_path / "s.h5"
    r = subprocess.run([KANESENS, "run", str(study), "-o", str(run)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    s = summarize(open_run(run))
    assert 0 <= s["position_residual_max"] < 1e-6 and 0 <= s["velocity_residual_max"] < 1e-6, s
    env = dict(os.environ, PYTHONPATH=str(ROOT / "python"))
    text = subprocess.run([sys.executable, "-m", "kanesens_post", "summary", str(run)], capture_output=True,
                          text=True, env=env, timeout=120)
    assert text.returncode == 0 and "constraint residuals: max |g| = " in text.stdout, text.stdout + text.stderr
    js = subprocess.run([sys.executable, "-m", "kanesens_post", "summary", str(run), "--json"],
                        capture_output=True, text=True, env=env, timeout=120)
    assert "position_residual_max" in json.loads(js.stdout)
    # no vary: (no /parameters) and no record: states (no /states): still a run file
    study.write_text(study.read_text().replace("record: [states, constraint_residual]", "record: [energy]"))
    r = subprocess.run([KANESENS, "run", str(study), "-o", str(run), "--overwrite"], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert summarize(open_run(run))["ok"] == 2
    stats = subprocess.run([sys.executable, "-m", "kanesens_post", "summary", str(run), "--output", "energy"],
                           capture_output=True, text=True, env=env, timeout=120)
    assert stats.returncode == 0, stats.stderr
    sobol = subprocess.run([sys.executable, "-m", "kanesens_post", "sobol", str(run), "--output", "energy"],
                           capture_output=True, text=True, env=env, timeout=120)
    assert sobol.returncode == 2 and "varies no input" in sobol.stderr, sobol.stderr
    plot = subprocess.run([sys.executable, "-m", "kanesens_post", "plot", str(run), "--out", str(tmp_path / "p.png")],
                          capture_output=True, text=True, env=env, timeout=120)
    assert plot.returncode == 2 and "no /states (record: [states])" in plot.stderr, plot.stderr
