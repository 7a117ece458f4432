"""Sobol' indices from a Saltelli design: Ishigami against its analytic indices and against
OpenTURNS on the same samples; a linear model against its closed-form decomposition, over time;
failed runs drop their whole base point."""
import numpy as np
import pytest

from kanesens_post import sobol
from kanesens_post.io import RunFileError, design, open_run
from post_fixtures import (ishigami, ishigami_indices, saltelli_design, uniform_ppf,
                           uniform_vary, write_function_run)

PI = np.pi


@pytest.fixture(scope="module")
def ishigami_run(tmp_path_factory):
    n = 2 ** 13
    ppfs = [lambda u: uniform_ppf(u, -PI, PI)] * 3
    x, a, b = saltelli_design(n, ppfs, seed=7)
    path = tmp_path_factory.mktemp("ishigami") / "run.h5"
    write_function_run(path, x, ["x1", "x2", "x3"], ishigami(x), method="saltelli",
                       vary=uniform_vary({k: (-PI, PI) for k in ("x1", "x2", "x3")}),
                       output="ishigami")
    return path, x, n


def test_ishigami_analytic_values():
    s1, st = ishigami_indices()
    assert s1 == pytest.approx([0.3139, 0.4424, 0.0], abs=1e-4)
    assert st == pytest.approx([0.5576, 0.4424, 0.2437], abs=1e-4)


def test_ishigami_against_analytic(ishigami_run):
    path, _, n = ishigami_run
    ds = open_run(path)
    r = sobol.analyze(ds, design(ds), "y", at=0.0, n_boot=50)
    s1, st = ishigami_indices()
    assert r["base_points"] == n and r["base_points_dropped"] == 0
    assert np.abs(r["S1"] - s1).max() < 0.02, r["S1"]
    assert np.abs(r["ST"] - st).max() < 0.02, r["ST"]
    lo, hi = r["ST_ci"]
    assert (lo <= r["ST"]).all() and (r["ST"] <= hi).all() and (hi - lo).max() < 0.1
    # the same numbers when the series is an output instead of a state
    r2 = sobol.analyze(ds, design(ds), "ishigami", at=0.0, n_boot=0)
    np.testing.assert_array_equal(r2["S1"], r["S1"])


def test_ishigami_against_openturns(ishigami_run):
    """OpenTURNS on the same samples, in its order [A; B; E_1..E_P] (E_i = A with column i
    from B, as our AB^(i)). OT's MauntzKucherenko first-order estimator is our Saltelli 2010
    one (outputs centred by the design mean) normalised by the unbiased variance of f(A);
    OT's Jansen total divides by 2N − 1 instead of 2N. Undo the normalisations and the
    partial variances must agree to rounding."""
    ot = pytest.importorskip("openturns")
    path, x, n = ishigami_run
    ds = open_run(path)
    blocks, _ = sobol.saltelli_blocks(design(ds), np.asarray(ds.states.values[:, 0, 0]))
    ours = sobol.indices(blocks)
    xb = x.reshape(n, 5, 3)
    x_ot = np.concatenate([xb[:, k] for k in range(5)])       # A, B, E_1, E_2, E_3
    y_ot = ishigami(x_ot)[:, None]
    var_a = np.var(blocks[:, 0], ddof=1)
    mk = np.array(ot.MauntzKucherenkoSensitivityAlgorithm(x_ot, y_ot, n).getFirstOrderIndices())
    jansen = np.array(ot.JansenSensitivityAlgorithm(x_ot, y_ot, n).getTotalOrderIndices())
    np.testing.assert_allclose(mk * var_a * (n - 1) / n, ours["V_i"], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(jansen * var_a * (2 * n - 1) / (2 * n), ours["V_Ti"],
                               rtol=1e-10, atol=1e-12)
    # and the indices themselves agree statistically
    assert np.abs(mk - ours["S1"]).max() < 0.01
    assert np.abs(jansen - ours["ST"]).max() < 0.01


def test_linear_model_over_time(tmp_path):
    """y(t) = a(t)·x with independent uniforms: S_i = ST_i = a_i² Var x_i / Σ a_j² Var x_j."""
    bounds = {"p": (0.0, 1.0), "q": (-2.0, 2.0), "r": (5.0, 6.0)}
    ppfs = [lambda u, lo=lo, hi=hi: uniform_ppf(u, lo, hi) for lo, hi in bounds.values()]
    x, _, _ = saltelli_design(2 ** 11, ppfs, seed=2)
    t = np.linspace(0.0, 2.0, 5)
    a = np.stack([np.ones_like(t), t, 0.5 * np.cos(t)], axis=1)        # (nt, P)
    path = write_function_run(tmp_path / "lin.h5", x, list(bounds), x @ a.T, time=t,
                              method="saltelli", vary=uniform_vary(bounds))
    ds = open_run(path)
    r = sobol.analyze(ds, design(ds), "y", over_time=True, n_boot=0)
    var_x = np.array([(hi - lo) ** 2 / 12 for lo, hi in bounds.values()])
    exact = (a ** 2 * var_x) / (a ** 2 @ var_x)[:, None]              # (nt, P)
    assert r["S1"].shape == (3, 5)
    np.testing.assert_allclose(r["S1"], exact.T, atol=1e-3)
    np.testing.assert_allclose(r["ST"], exact.T, atol=1e-3)


def test_failed_runs_drop_whole_blocks(tmp_path):
    x, _, _ = saltelli_design(64, [lambda u: u] * 2, seed=1)
    status = np.ones(x.shape[0], int)
    status[[0, 3, 9, 10]] = [-1, -2, 0, -1]        # blocks 0 (rows 0, 3), 2 (rows 9, 10)
    path = write_function_run(tmp_path / "f.h5", x, ["a", "b"], x[:, 0] + x[:, 1],
                              method="saltelli", status=status)
    ds = open_run(path)
    r = sobol.analyze(ds, design(ds), "y", at=0.0, n_boot=0)
    assert r["base_points_dropped"] == 2 and r["base_points"] == 62


def test_wrong_design_order_is_refused(tmp_path):
    x, _, _ = saltelli_design(16, [lambda u: u] * 2, seed=1)
    x = x.reshape(16, 4, 2)[:, [0, 1, 3, 2]].reshape(-1, 2)      # AB^(2) before AB^(1)
    path = write_function_run(tmp_path / "w.h5", x, ["a", "b"], x.sum(1), method="saltelli")
    ds = open_run(path)
    with pytest.raises(RunFileError, match="taken from B"):
        sobol.analyze(ds, design(ds), "y", at=0.0, n_boot=0)


def test_explicit_block_labels(tmp_path):
    """/design_block and /design_row let the writer store the runs in any order."""
    x, _, _ = saltelli_design(128, [lambda u: u] * 2, seed=4)
    block, row = np.divmod(np.arange(x.shape[0]), 4)
    perm = np.random.default_rng(0).permutation(x.shape[0])
    from post_fixtures import write_run
    y = (x[:, 0] + 2 * x[:, 1])[perm]
    path = write_run(tmp_path / "p.h5", time=[0.0], state_names=["y"],
                     parameter_names=["a", "b"], parameters=x[perm], states=y[:, None, None],
                     sampling_method="saltelli",
                     design={"design_block": block[perm], "design_row": row[perm]})
    ds = open_run(path)
    r = sobol.analyze(ds, design(ds), "y", at=0.0, n_boot=0)
    np.testing.assert_allclose(r["S1"], [0.2, 0.8], atol=0.05)


def test_older_file_gives_the_same_indices(tmp_path):
    """A file without the design labels and /vary (older kanesens) is read by row order and
    gives the same numbers."""
    from post_fixtures import pendulum_saltelli
    new = open_run(pendulum_saltelli(tmp_path / "new.h5", n_base=64, nt=21))
    old = open_run(pendulum_saltelli(tmp_path / "old.h5", n_base=64, nt=21, legacy=True))
    assert design(new).labels == "file" and design(old).labels == "row order"
    r_new = sobol.analyze(new, design(new), "pivot.q", at=5.0, n_boot=0)
    r_old = sobol.analyze(old, design(old), "pivot.q", at=5.0, n_boot=0)
    np.testing.assert_array_equal(r_new["S1"], r_old["S1"])
    np.testing.assert_array_equal(r_new["ST"], r_old["ST"])


def test_fixed_input_in_the_design(tmp_path):
    """y = a + 2b with a fixed input k between them: kanesens's blocks have P + 2 = 5 runs
    (AB^(k) included); the indices are those of a and b alone."""
    ppfs = [lambda u: u, lambda u: 0 * u + 3.0, lambda u: u]
    x, _, _ = saltelli_design(256, ppfs, seed=5)
    vary = {"a": {"dist": "uniform", "low": 0.0, "high": 1.0}, "k": {"dist": "fixed", "value": 3.0},
            "b": {"dist": "uniform", "low": 0.0, "high": 1.0}}
    path = write_function_run(tmp_path / "f.h5", x, ["a", "k", "b"], x[:, 0] + 2 * x[:, 2],
                              method="saltelli", vary=vary)
    ds = open_run(path)
    r = sobol.analyze(ds, design(ds), "y", at=0.0, n_boot=0)
    assert r["inputs"] == ["a", "b"] and r["base_points"] == 256
    np.testing.assert_allclose(r["S1"], [0.2, 0.8], atol=0.05)
    np.testing.assert_allclose(r["ST"], [0.2, 0.8], atol=0.05)
