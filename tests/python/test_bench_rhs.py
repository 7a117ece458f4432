"""`kanesens bench rhs --json`: the timings it reports, and for a constrained scene the
constrained right-hand sides at a state that satisfies the constraints (the state peers are
compared at, docs/peers.md), which must be the one `kanesens eom` finds consistent."""
import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(os.environ.get("KANESENS_SOURCE_DIR") or Path(__file__).resolve().parents[2])


def exe() -> str:
    path = os.environ.get("KANESENS")
    if not path:
        pytest.skip("KANESENS is not set (path of the kanesens executable); ctest sets it")
    return path

FAST = ["--repeat", "3", "--batch-seconds", "1e-4", "--json"]


def bench(scene):
    p = subprocess.run([exe(), "bench", "rhs", scene, *FAST], cwd=ROOT, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def test_unconstrained_scene_has_no_constrained_timings():
    d = bench("configs/nlink_chain_4.yaml")
    for key in ("rhs", "mass_matrix_and_forcing", "jacobian_dual", "jacobian", "jacobian_times"):
        assert d[key]["median_ns"] > 0 and d[key]["evaluations_per_second"] > 0
    assert "rhs_multipliers" not in d and "rhs_embedding" not in d and "constrained_state" not in d


def test_constrained_timings_at_a_consistent_state():
    d = bench("configs/four_bar.yaml")
    assert d["nconstraint_rows"] == 2
    for key in ("rhs_multipliers", "rhs_embedding", "jacobian_times_multipliers"):
        assert d[key]["median_ns"] > 0, key
    y = d["constrained_state"]
    assert len(y) == d["nq"] + d["nu"]
    fmt = lambda xs: ",".join(repr(v) for v in xs)
    eom = json.loads(subprocess.run([exe(), "eom", "configs/four_bar.yaml", "--q=" + fmt(y[:3]), "--u=" + fmt(y[3:])],
                                    cwd=ROOT, capture_output=True, text=True, check=True).stdout)
    assert max(map(abs, eom["constraint_position_residual"])) < 1e-12
    assert max(map(abs, eom["constraint_velocity_residual"])) < 1e-12
    # the crank's initial angle and rate are the scene's (pi/2, 6 rad/s): the state is the scene's own
    assert abs(y[0] - 1.5707963267948966) < 1e-15 and abs(y[3] - 6.0) < 1e-15
