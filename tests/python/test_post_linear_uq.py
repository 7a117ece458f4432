"""Linear propagation from sensitivities: exact on a linear model, visibly wrong on a strongly
nonlinear one, and on the pendulum valid early and failing once the phases spread."""
import numpy as np
import pytest

from kanesens_post import linear_uq
from kanesens_post.io import design, open_run
from post_fixtures import pendulum_saltelli, write_function_run


def test_linear_model_is_exact(tmp_path):
    """y = 2 p − 3 q + 0.5 r: E y = Σ a_i μ_i, Var y = Σ a_i² Var x_i, whichever sample the
    linearisation starts from."""
    rng = np.random.default_rng(3)
    n = 4000
    vary = {"p": {"dist": "uniform", "low": 1, "high": 3},
            "q": {"dist": "normal", "mean": -1, "std": 0.2},
            "r": {"dist": "triangular", "low": 0, "mode": 1, "high": 4}}
    x = np.column_stack([rng.uniform(1, 3, n), rng.normal(-1, 0.2, n),
                         rng.triangular(0, 1, 4, n)])
    a = np.array([2.0, -3.0, 0.5])
    path = write_function_run(tmp_path / "l.h5", x, list(vary), x @ a,
                              gradient=np.tile(a, (n, 1)), vary=vary)
    ds = open_run(path)
    r = linear_uq.analyze(ds, design(ds), "y", at=0.0)
    mean = a @ [2.0, -1.0, 5 / 3]
    var = a ** 2 @ [4 / 12, 0.04, (0 + 1 + 16 - 0 - 0 - 4) / 18]
    assert r["mean_linear"] == pytest.approx(mean, rel=1e-13)
    assert r["variance_linear"] == pytest.approx(var, rel=1e-13)
    assert r["variance_ratio"] == pytest.approx(1.0, abs=0.06)     # MC sampling error only
    assert r["holds"]


def test_strongly_nonlinear_breaks(tmp_path):
    """y = exp(3x), x ~ N(0, 0.5): Var y = (e^{9σ²} − 1) e^{9σ²} ≈ 80.6, linear ≈ 2.25."""
    rng = np.random.default_rng(4)
    x = rng.normal(0, 0.5, (20000, 1))
    y = np.exp(3 * x[:, 0])
    path = write_function_run(tmp_path / "e.h5", x, ["x"], y, gradient=3 * y[:, None],
                              vary={"x": {"dist": "normal", "mean": 0, "std": 0.5}})
    ds = open_run(path)
    r = linear_uq.analyze(ds, design(ds), "y", at=0.0)
    assert r["variance_linear"] == pytest.approx(9 * 0.25, rel=0.01)
    assert r["variance_ratio"] < 0.1 and not r["holds"]


def test_pendulum_over_time(tmp_path):
    """θ = θ0 cos(√(g/L) t): linear in θ0; the L-dependence is a phase that spreads with t.
    At t = 0 linearisation is exact; by t = 10 s it has broken down."""
    path = pendulum_saltelli(tmp_path / "p.h5", n_base=128, nt=101)
    ds = open_run(path)
    r = linear_uq.analyze(ds, design(ds), "pivot.q", at=None)
    assert r["holds"][0] and r["variance_ratio"][0] == pytest.approx(1.0, abs=0.1)
    assert not r["holds"][-1]
    assert 0 < r["first_breakdown_time"] < 10.0
    assert r["mc_samples"] == 128 * 5 - 2
