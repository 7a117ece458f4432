"""Stability atlas (docs/explanation/stability.md), singular configurations: the parallelogram four-bar
(configs/parallelogram_four_bar.yaml) driven fast enough (crank 12 rad/s) that the crank turns
about three times in 3 s and passes through the collinear toggle positions, where the loop
constraint's matrix A loses rank (the parallelogram/anti-parallelogram bifurcation). Pinned:
with multipliers, the pivoted Cholesky of A M^-1 A^T keeps lambda bounded (no blow-up) and the
mechanism stays a parallelogram (rocker angle = crank angle); with embedding, every partition
degrades at the toggle for an instant only (the integrator steps over it; a re-choice would not
help and is not taken) and the two formulations agree."""
import json
import os
import subprocess

import numpy as np

ROOT = os.environ.get("KANESENS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
EXE = os.environ.get("KANESENS", os.path.join(ROOT, "build", "kanesens"))


def simulate(formulation, tmp_path):
    study = tmp_path / "toggle.yaml"
    study.write_text(
        "kanesens: 1\n"
        f"scene: {os.path.abspath(os.path.join(ROOT, 'configs', 'parallelogram_four_bar.yaml'))}\n"
        "time: {end: 3.0, outputs: 301}\n"
        "solver: {rtol: 1.0e-8, atol: 1.0e-10, constraints: {formulation: " + formulation + ", stabilization: projection}}\n")
    p = subprocess.run([EXE, "simulate", str(study), "--set", "w1=12"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def test_toggle_positions_multipliers_and_embedding(tmp_path):
    runs = {f: simulate(f, tmp_path) for f in ("multipliers", "embedding")}
    crank = {}
    for f, d in runs.items():
        assert d["status"] == 1, d["message"]
        s = np.array(d["states"], dtype=float)
        crank[f] = s[:, 0]
        assert s[:, 0].max() - s[:, 0].min() > 4 * np.pi          # passes the toggle positions 0, pi, ... repeatedly
        assert np.max(np.abs(s[:, 2] - s[:, 0])) < 1e-9          # still a parallelogram
        lam = np.array(d["multipliers"], dtype=float)
        assert np.all(np.isfinite(lam)) and np.max(np.abs(lam)) < 100  # bounded (about 56 N)
        assert max(d["constraint_residuals"]["position"]) < 1e-10
    assert np.max(np.abs(crank["multipliers"] - crank["embedding"])) < 1e-4
