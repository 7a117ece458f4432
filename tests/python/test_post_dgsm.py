"""DGSM from recorded sensitivities against closed forms."""
import numpy as np
import pytest

from kanesens_post import dgsm
from kanesens_post.io import design, open_run
from post_fixtures import write_function_run

N = 40000


def test_quadratic_uniform_and_normal(tmp_path):
    """y = x1² + 3 x2, x1 ~ U(0, 2), x2 ~ N(1, 0.5):
    ν1 = E[4 x1²] = 16/3, ν2 = 9; Var y = Var x1² + 9·0.25 = 64/45 + 2.25.
    Bounds: (b−a)²/π² ν1 / Var y ≥ S_T1 = (64/45)/Var y; for the linear, normal term the
    Poincaré inequality is an equality: σ² ν2 / Var y = S_T2 = 2.25 / Var y."""
    rng = np.random.default_rng(5)
    x = np.column_stack([rng.uniform(0, 2, N), rng.normal(1, 0.5, N)])
    y = x[:, 0] ** 2 + 3 * x[:, 1]
    grad = np.column_stack([2 * x[:, 0], np.full(N, 3.0)])
    vary = {"x1": {"dist": "uniform", "low": 0, "high": 2},
            "x2": {"dist": "normal", "mean": 1, "std": 0.5}}
    path = write_function_run(tmp_path / "q.h5", x, ["x1", "x2"], y, gradient=grad, vary=vary)
    ds = open_run(path)
    r = dgsm.analyze(ds, design(ds), "y", at=0.0)
    var = 64 / 45 + 2.25
    np.testing.assert_allclose(r["nu"], [16 / 3, 9], rtol=0.02)
    assert r["variance"] == pytest.approx(var, rel=0.03)
    np.testing.assert_allclose(r["poincare_constant"], [4 / np.pi ** 2, 0.25], rtol=1e-14)
    st = np.array([64 / 45, 2.25]) / var
    assert r["total_index_bound"][0] >= st[0]
    assert r["total_index_bound"][0] == pytest.approx(4 / np.pi ** 2 * 16 / 3 / var, rel=0.04)
    assert r["total_index_bound"][1] == pytest.approx(st[1], rel=0.03)


def test_linear_uniform_bound_ratio(tmp_path):
    """y = Σ a_i x_i, x_i ~ U(0, w_i): bound / S_Ti = 12/π² for every input."""
    rng = np.random.default_rng(1)
    a, w = np.array([1.0, -2.0, 0.5]), np.array([1.0, 0.5, 3.0])
    x = rng.random((N, 3)) * w
    vary = {f"p{i}": {"dist": "uniform", "low": 0, "high": float(w[i])} for i in range(3)}
    path = write_function_run(tmp_path / "l.h5", x, list(vary), x @ a,
                              gradient=np.tile(a, (N, 1)), vary=vary)
    ds = open_run(path)
    r = dgsm.analyze(ds, design(ds), "y", at=0.0)
    np.testing.assert_allclose(r["nu"], a ** 2, rtol=1e-12)
    st = a ** 2 * w ** 2 / 12 / np.sum(a ** 2 * w ** 2 / 12)
    np.testing.assert_allclose(r["total_index_bound"] / st, 12 / np.pi ** 2, rtol=0.03)


def test_lognormal_has_no_bound(tmp_path):
    rng = np.random.default_rng(2)
    x = rng.lognormal(0, 0.3, (200, 1))
    path = write_function_run(tmp_path / "ln.h5", x, ["k"], x[:, 0], gradient=np.ones((200, 1)),
                              vary={"k": {"dist": "lognormal", "mu": 0, "sigma": 0.3}})
    ds = open_run(path)
    r = dgsm.analyze(ds, design(ds), "y", at=0.0)
    assert np.isnan(r["total_index_bound"][0]) and "no Poincare" in r["constant_used"][0]
