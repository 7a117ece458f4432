"""Morris elementary effects on functions whose effects are known."""
import numpy as np
import pytest

from kanesens_post import morris
from kanesens_post.io import RunFileError, design, open_run
from post_fixtures import morris_design, uniform_vary, write_function_run

VARY = uniform_vary({"a": (0, 1), "b": (0, 1), "c": (0, 1)})


def run(tmp_path, y_of_x, r=20, status=None):
    x = morris_design(r, 3, seed=3)
    return x, write_function_run(tmp_path / "m.h5", x, ["a", "b", "c"], y_of_x(x),
                                 method="morris", vary=VARY, status=status)


def test_linear_function(tmp_path):
    """y = 4a − 2b + 0c: every elementary effect of input i is its coefficient."""
    _, path = run(tmp_path, lambda x: x @ [4.0, -2.0, 0.0])
    ds = open_run(path)
    r = morris.analyze(ds, design(ds), "y", at=0.0)
    np.testing.assert_allclose(r["mu_star"], [4, 2, 0], atol=1e-12)
    np.testing.assert_allclose(r["mu"], [4, -2, 0], atol=1e-12)
    np.testing.assert_allclose(r["sigma"], 0, atol=1e-12)
    assert r["scale"] == "unit" and r["trajectories"] == 20


def test_interaction_and_curvature(tmp_path):
    """y = a·b + c²: EE_a = b at the point (its mean over the design), σ_a > 0;
    EE_c = 2c + Δ (signed step), so μ*_c = mean |2c + Δ|."""
    x, path = run(tmp_path, lambda x: x[:, 0] * x[:, 1] + x[:, 2] ** 2)
    ds = open_run(path)
    r = morris.analyze(ds, design(ds), "y", at=0.0)
    traj = x.reshape(20, 4, 3)
    ee_a, ee_c = [], []
    for t in traj:
        for k in range(3):
            d = t[k + 1] - t[k]
            i = int(np.flatnonzero(d)[0])
            if i == 0:
                ee_a.append(t[k, 1])
            if i == 2:
                ee_c.append(2 * t[k, 2] + d[2])
    assert r["mu"][0] == pytest.approx(np.mean(ee_a), abs=1e-12)
    assert r["sigma"][0] > 0.1
    assert r["mu_star"][2] == pytest.approx(np.mean(np.abs(ee_c)), abs=1e-12)
    assert r["mu_star"][1] > 0 and r["mu_star"][0] > 0


def test_failed_trajectory_dropped(tmp_path):
    status = np.ones(80, int)
    status[[6, 7]] = -1                       # both in trajectory 1
    _, path = run(tmp_path, lambda x: x @ [1.0, 1.0, 1.0], status=status)
    ds = open_run(path)
    r = morris.analyze(ds, design(ds), "y", at=0.0)
    assert r["trajectories"] == 19 and r["trajectories_dropped"] == 1


def test_not_one_at_a_time(tmp_path):
    x = np.random.default_rng(0).random((8, 3))
    path = write_function_run(tmp_path / "bad.h5", x, ["a", "b", "c"], x.sum(1),
                              method="morris", vary=VARY)
    ds = open_run(path)
    with pytest.raises(RunFileError, match="exactly one input"):
        morris.analyze(ds, design(ds), "y", at=0.0)


def test_labels_let_the_runs_come_in_any_order(tmp_path):
    """With /design_block, /design_row and /design_input the analysis does not depend on the
    order in which the runs are stored."""
    from post_fixtures import design_labels, write_run
    x = morris_design(12, 3, seed=5)
    y = x @ [4.0, -2.0, 1.0] + x[:, 0] * x[:, 1]
    labels = design_labels("morris", x)
    perm = np.random.default_rng(1).permutation(x.shape[0])
    ordered = write_function_run(tmp_path / "o.h5", x, ["a", "b", "c"], y, method="morris", vary=VARY)
    shuffled = write_run(tmp_path / "s.h5", time=[0.0], state_names=["y"], parameter_names=["a", "b", "c"],
                         parameters=x[perm], states=y[perm, None, None], sampling_method="morris",
                         study={"kanesens": 1, "vary": VARY}, design={k: v[perm] for k, v in labels.items()})
    r = [morris.analyze(ds, design(ds), "y", at=0.0) for ds in map(open_run, (ordered, shuffled))]
    for key in ("mu", "mu_star", "sigma"):
        np.testing.assert_allclose(r[1][key], r[0][key], rtol=1e-12)
    assert r[0]["mu_star"][2] == pytest.approx(1.0)


def test_fixed_input_step_is_skipped(tmp_path):
    """A fixed input still takes a step in kanesens's trajectories (nothing changes there): it
    is left out, the other inputs' effects are exact."""
    x = morris_design(10, 3, seed=2)
    x[:, 1] = 0.5                                    # input k: fixed
    y = 3 * x[:, 0] - x[:, 2]
    labels_x = morris_design(10, 3, seed=2)          # the design kanesens ran, k's steps included
    from post_fixtures import design_labels, write_run
    vary = {"a": VARY["a"], "k": {"dist": "fixed", "value": 0.5}, "c": VARY["c"]}
    path = write_run(tmp_path / "k.h5", time=[0.0], state_names=["y"], parameter_names=["a", "k", "c"],
                     parameters=x, states=y[:, None, None], sampling_method="morris",
                     study={"kanesens": 1, "vary": vary}, design=design_labels("morris", labels_x))
    ds = open_run(path)
    r = morris.analyze(ds, design(ds), "y", at=0.0)
    assert r["inputs"] == ["a", "c"]
    np.testing.assert_allclose(r["mu"], [3, -1], atol=1e-12)
