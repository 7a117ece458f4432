"""`kanesens run` records each sample's place in a Saltelli or Morris design (/design_block,
/design_row, /design_input) and the distributions of `vary:` (/vary/<input>), and the
post-processing package reads those (docs/reference/hdf5.md).

The labels are checked against the sampled values the same file holds, not against the
writer's index arithmetic: AB_j^(k) must equal A_j with column k taken from B_j, and a Morris
step must change exactly the input it names. The distributions must be the study's.

Environment: KANESENS = kanesens executable (skips without it). Needs mpirun, h5py.
"""
import os
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

from kanesens_post import morris, sobol
from kanesens_post.io import design, open_run

ROOT = Path(os.environ.get("KANESENS_SOURCE_DIR") or Path(__file__).resolve().parents[2])
KANESENS = os.environ.get("KANESENS")
pytestmark = pytest.mark.skipif(not KANESENS, reason="needs KANESENS (the kanesens executable)")

VARY = """vary:
  L: {dist: uniform, low: 0.9, high: 1.1}
  m: {dist: fixed, value: 1.3}
  pivot.q0: {dist: choice, values: [0.3, 0.1, 0.2]}
  pivot.u0: {dist: truncnormal, mean: 0.0, std: 0.2, low: -0.3, high: 0.4}
"""
EXPECTED_VARY = {"L": {"distribution": "uniform", "low": 0.9, "high": 1.1},
                 "m": {"distribution": "fixed", "value": 1.3},
                 "pivot.q0": {"distribution": "choice", "values": [0.1, 0.2, 0.3]},
                 "pivot.u0": {"distribution": "truncnormal", "mean": 0.0, "std": 0.2, "low": -0.3, "high": 0.4}}


def run(tmp_path, sampling):
    study = tmp_path / "study.yaml"
    study.write_text(f"kanesens: 1\nscene: {ROOT / 'configs' / 'simple_pendulum.yaml'}\n"
                     "time: {end: 0.5, outputs: 3}\nsolver: {rtol: 1.0e-8, atol: 1.0e-10}\n"
                     f"sampling: {sampling}\n{VARY}")
    out = tmp_path / "run.h5"
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    p = subprocess.run(["mpirun", "--oversubscribe", "-np", "2", KANESENS, "run", str(study), "-o", str(out)],
                       capture_output=True, text=True, env=env)
    assert p.returncode == 0, p.stderr
    return out


def labels(path):
    with h5py.File(path, "r") as f:
        names = [n.decode() for n in f["parameter_name"][()]]
        return (names, f["parameters"][()], f["design_block"][()], f["design_row"][()],
                f["design_input"][()])


def test_saltelli_labels_match_the_values(tmp_path):
    path = run(tmp_path, "{method: saltelli, samples: 8, seed: 3, randomize: true}")
    names, x, block, row, moved = labels(path)
    p = len(names)
    assert x.shape == (8 * (p + 2), p) and block.dtype == np.int64
    assert sorted(zip(block, row)) == [(j, r) for j in range(8) for r in range(p + 2)]
    for j in range(8):
        a = x[(block == j) & (row == 0)][0]
        b = x[(block == j) & (row == 1)][0]
        assert (moved[(block == j) & (row < 2)] == -1).all()
        for k in range(p):
            i = np.flatnonzero((block == j) & (row == 2 + k))[0]
            assert moved[i] == k
            np.testing.assert_array_equal(x[i], np.where(np.arange(p) == k, b, a))
    # ... and the analyses use them: the fixed mass is a design column but not reported.
    ds = open_run(path)
    des = design(ds)
    assert des.labels == "file" and des.columns == names and "m" not in des.names
    r = sobol.analyze(ds, des, "pivot.q", at=0.5, n_boot=0)
    assert r["inputs"] == [n for n in names if n != "m"] and r["base_points"] == 8


def test_morris_labels_name_the_input_each_step_moved(tmp_path):
    path = run(tmp_path, "{method: morris, trajectories: 4, levels: 4, seed: 5}")
    names, x, block, row, moved = labels(path)
    p = len(names)
    assert sorted(zip(block, row)) == [(t, s) for t in range(4) for s in range(p + 1)]
    fixed = names.index("m")
    for t in range(4):
        order = np.flatnonzero(block == t)[np.argsort(row[block == t])]
        assert moved[order[0]] == -1
        assert sorted(moved[order[1:]]) == list(range(p))          # every input once
        for prev, cur in zip(order[:-1], order[1:]):
            changed = np.flatnonzero(x[cur] != x[prev])
            expected = [] if moved[cur] == fixed else [moved[cur]]  # a fixed input's step changes nothing
            assert changed.tolist() == expected, (t, row[cur])
    ds = open_run(path)
    r = morris.analyze(ds, design(ds), "pivot.q", at=0.5)
    assert r["inputs"] == [n for n in names if n != "m"] and r["trajectories"] == 4


def test_distributions_are_the_studys(tmp_path):
    path = run(tmp_path, "{method: lhs, samples: 4, seed: 1}")
    with h5py.File(path, "r") as f:
        assert "design_block" not in f                                # plain designs: no labels
        got = {name: {k: (v.decode() if isinstance(v, bytes) else
                          v.tolist() if isinstance(v, np.ndarray) else float(v))
                      for k, v in group.attrs.items()}
               for name, group in f["vary"].items()}
    assert got == EXPECTED_VARY
    assert open_run(path).attrs["vary"] == EXPECTED_VARY
