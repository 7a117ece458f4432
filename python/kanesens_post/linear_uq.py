"""First-order (linear) uncertainty propagation from forward sensitivities, against Monte Carlo.

Linearise y at the input mean μ (first-order Taylor / "delta method"):

    E[y]   ≈ y(μ)
    Var y  ≈ Σ_i (∂y/∂x_i)² Var(x_i)          (independent inputs)

The file need not hold a run at μ exactly: the run x_s nearest to μ (in standard deviations)
is taken and extrapolated, y(μ) ≈ y(x_s) + Σ_i ∂y/∂x_i(x_s) (μ_i − x_s,i), with the gradient at
x_s. Mean and variance of each input come from its distribution in the study (sample moments
of the design column if the study has none). The Monte Carlo mean and variance of the same file
are the reference; linearisation is judged to hold where |Var_lin/Var_MC − 1| ≤ tol and
|mean_lin − mean_MC| ≤ tol·sd_MC.
"""
from __future__ import annotations

import numpy as np

from .io import Design, input_gradient, response, select


def input_moments(des: Design, names) -> tuple:
    mean, var, source = [], [], []
    for n in names:
        column = des.x[:, des.names.index(n)]
        if n in des.dists:
            mean.append(des.dists[n].mean())
            var.append(des.dists[n].variance())
            source.append(des.dists[n].kind)
        else:
            mean.append(column.mean())
            var.append(column.var(ddof=1))
            source.append("sample moments")
    return np.array(mean), np.array(var), source


def nearest_to_mean(x: np.ndarray, ok: np.ndarray, mean: np.ndarray, var: np.ndarray) -> int:
    sd = np.sqrt(np.where(var > 0, var, 1.0))
    distance = np.sum(((x - mean) / sd) ** 2, axis=1)
    distance[~ok] = np.inf
    return int(np.argmin(distance))


def propagate(y_s, gradient_s, x_s, mean, var):
    """Linearised mean and variance at the mean point from one run s (arrays over time ok):
    y_s (...), gradient_s (..., P), x_s (P,)."""
    return y_s + gradient_s @ (mean - x_s), (gradient_s ** 2) @ var


def verdict(mean_lin, var_lin, mean_mc, var_mc, tol):
    """Boolean (per time) 'linearisation holds' and the variance ratio."""
    scale = np.maximum(np.abs(mean_mc), 1.0) * 1e-12
    tiny = (var_mc <= scale ** 2) & (var_lin <= scale ** 2)   # nothing varies (e.g. t = 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(tiny, 1.0, var_lin / np.where(var_mc > 0, var_mc, np.nan))
    holds = (np.abs(ratio - 1) <= tol) & (np.abs(mean_lin - mean_mc) <= tol * np.sqrt(var_mc)
                                            + scale)
    return holds, ratio


def analyze(ds, des: Design, name: str, at=None, tol: float = 0.1, over_time=None) -> dict:
    """At time `at`, at every time (over_time; by default when `at` is None and `name` is a
    series), or of an output that is one number per sample."""
    if over_time is None:
        over_time = at is None and "time" in response(ds, name).dims
    sel = select(ds, name, at, over_time)
    gradient, found, missing = input_gradient(ds, des, name, sel.k)
    y = sel.y
    ok = ~np.isnan(y.reshape(y.shape[0], -1)).any(axis=1)
    mean, var, source = input_moments(des, found)
    x = des.x[:, [des.names.index(n) for n in found]]
    s = nearest_to_mean(x, ok, mean, var)
    mean_lin, var_lin = propagate(y[s], gradient[s], x[s], mean, var)
    mean_mc, var_mc = y[ok].mean(axis=0), y[ok].var(axis=0, ddof=1)
    holds, ratio = verdict(mean_lin, var_lin, mean_mc, var_mc, tol)
    out = {"output": name, "time": sel.time, "inputs": found,
           "input_mean": mean, "input_variance": var, "input_moments_from": source,
           "inputs_without_sensitivity": missing, "linearisation_sample": s,
           "linearisation_point": x[s], "mc_samples": int(ok.sum()),
           "mean_linear": mean_lin, "variance_linear": var_lin,
           "mean_mc": mean_mc, "variance_mc": var_mc, "variance_ratio": ratio,
           "tolerance": tol, "holds": holds}
    if over_time:
        broken = np.flatnonzero(~holds)
        out["holds_fraction"] = float(holds.mean())
        out["first_breakdown_time"] = float(sel.time[broken[0]]) if broken.size else None
    if missing:
        out["warning"] = (f"varied inputs without recorded sensitivities are left out of the "
                          f"linear variance: {', '.join(missing)}")
    return out
