"""Morris elementary effects (Morris 1991; μ* of Campolongo, Cariboni & Saltelli 2007).

Design (see io.design): r trajectories of P+1 runs; consecutive runs differ in one input.
The step of input i between runs k and k+1 gives one elementary effect

    EE_i = (y(x_{k+1}) − y(x_k)) / Δ_i

with Δ_i measured on the unit hypercube, Δ_i = F_i(x_{k+1,i}) − F_i(x_{k,i}) (F_i the input's
CDF from the study's `vary:`), so effects of inputs with different units compare; without the
distributions Δ_i is the raw difference (scale "physical"). Over the r trajectories:
μ_i = mean EE_i, μ*_i = mean |EE_i|, σ_i = standard deviation of EE_i.
Trajectories with a failed run are dropped whole.
"""
from __future__ import annotations

import numpy as np

from .io import Design, RunFileError, response, time_index


def trajectories(des: Design, y: np.ndarray):
    """(r, P+1, P) inputs and (r, P+1, ...) outputs per trajectory, failed ones dropped.
    Returns (x, y, n_dropped)."""
    p = len(des.names)
    if des.method != "morris":
        raise RunFileError(f"morris needs a Morris design; this run's sampling_method is "
                           f"'{des.method}'")
    index = des.block_index(p + 1, "Morris")
    r = index.shape[0]
    yt = y[index]
    bad = np.isnan(yt.reshape(r, -1)).any(axis=1)
    return des.x[index][~bad], yt[~bad], int(bad.sum())


def unit_scale(des: Design, x: np.ndarray):
    """Inputs mapped to the unit hypercube by their CDFs when every input has a distribution."""
    if des.dists and all(n in des.dists for n in des.names):
        return np.stack([des.dists[n].cdf(x[..., i]) for i, n in enumerate(des.names)], -1), "unit"
    return x, "physical"


def elementary_effects(x: np.ndarray, y: np.ndarray):
    """EE (r, P, ...) from trajectories x (r, P+1, P) and y (r, P+1, ...)."""
    r, steps, p = x.shape
    dx = np.diff(x, axis=1)                               # (r, P, P)
    moved = np.abs(dx) > 1e-12 * (1 + np.abs(x[:, 1:]))
    if not (moved.sum(axis=2) == 1).all() or not (moved.sum(axis=1) == 1).all():
        raise RunFileError("Morris trajectories must change exactly one input per step and "
                           "every input once")
    which = moved.argmax(axis=2)                          # (r, P): input moved at each step
    delta = np.take_along_axis(dx, which[..., None], axis=2)[..., 0]
    dy = np.diff(y, axis=1)
    ee = np.empty_like(dy)
    extra = (1,) * (dy.ndim - 2)
    for t in range(r):
        ee[t, which[t]] = dy[t] / delta[t].reshape(-1, *extra)
    return ee


def analyze(ds, des: Design, name: str, at: float) -> dict:
    k = time_index(ds, at)
    y = np.asarray(response(ds, name).isel(time=k).values, float)
    x, yt, dropped = trajectories(des, y)
    if x.shape[0] < 2:
        raise RunFileError(f"only {x.shape[0]} complete Morris trajectories")
    u, scale = unit_scale(des, x)
    ee = elementary_effects(u, yt)
    return {"output": name, "time": ds["time"].values[k], "inputs": des.names,
            "trajectories": int(x.shape[0]), "trajectories_dropped": dropped, "scale": scale,
            "mu": ee.mean(axis=0), "mu_star": np.abs(ee).mean(axis=0),
            "sigma": ee.std(axis=0, ddof=1)}
