"""Morris elementary effects (Morris 1991; μ* of Campolongo, Cariboni & Saltelli 2007).

Design (see io.design): r trajectories of P+1 runs; consecutive runs differ in one input, the one
`kanesens run` records in /design_input.
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

from .io import Design, RunFileError, select


def trajectories(des: Design, y: np.ndarray):
    """Runs arranged per trajectory, failed trajectories dropped. Returns x (r, P+1, p) of the
    reported inputs, y (r, P+1, ...), which (r, P+1): the reported input each step moved (−1:
    the start, or a step of a fixed input; −2: a step that moved several) and n_dropped."""
    if des.method != "morris":
        raise RunFileError(f"morris needs a Morris design; this run's sampling_method is "
                           f"'{des.method}'")
    # A trajectory steps through every design column, fixed inputs included.
    index = des.block_index(len(des.columns) + 1, "Morris")
    r = index.shape[0]
    moved = des.moved[index]
    if (moved >= len(des.columns)).any() or (moved < -2).any():
        raise RunFileError(f"Morris design: /design_input outside -1..{len(des.columns) - 1}")
    reported = np.full(len(des.columns), -1)              # column -> reported input (or −1)
    for i, n in enumerate(des.names):
        reported[des.columns.index(n)] = i
    which = np.where(moved >= 0, reported[np.maximum(moved, 0)], np.where(moved == -2, -2, -1))
    yt = y[index]
    bad = np.isnan(yt.reshape(r, -1)).any(axis=1)
    return des.x[index][~bad], yt[~bad], which[~bad], int(bad.sum())


def unit_scale(des: Design, x: np.ndarray):
    """Inputs mapped to the unit hypercube by their CDFs when every input has a distribution."""
    if des.dists and all(n in des.dists for n in des.names):
        return np.stack([des.dists[n].cdf(x[..., i]) for i, n in enumerate(des.names)], -1), "unit"
    return x, "physical"


def elementary_effects(x: np.ndarray, y: np.ndarray, which: np.ndarray):
    """EE (r, p, ...) from trajectories x (r, S, p), y (r, S, ...) and which (r, S), the input
    step s moved (−1 none). Every input must move exactly once per trajectory, and nothing else
    may change at its step."""
    r, steps, p = x.shape
    dx = np.diff(x, axis=1)                               # (r, S−1, p)
    moved = np.abs(dx) > 1e-12 * (1 + np.abs(x[:, 1:]))
    w = which[:, 1:]
    expected = (w[..., None] == np.arange(p)) & (w[..., None] >= 0)
    once = (expected.sum(axis=1) == 1).all()
    if not once or (moved != expected).any() or (which[:, 0] != -1).any():
        raise RunFileError("Morris trajectories must change exactly one input per step and "
                           "every input once")
    dy = np.diff(y, axis=1)                               # (r, S−1, ...)
    ee = np.empty((r, p) + dy.shape[2:])
    for t in range(r):
        for s in np.flatnonzero(w[t] >= 0):
            ee[t, w[t, s]] = dy[t, s] / dx[t, s, w[t, s]]
    return ee


def analyze(ds, des: Design, name: str, at=None) -> dict:
    """Elementary effects of `name` at time `at`, or of an output that is one number per sample."""
    sel = select(ds, name, at)
    y = sel.y
    x, yt, which, dropped = trajectories(des, y)
    if x.shape[0] < 2:
        raise RunFileError(f"only {x.shape[0]} complete Morris trajectories")
    u, scale = unit_scale(des, x)
    ee = elementary_effects(u, yt, which)
    return {"output": name, "time": sel.time, "inputs": des.names,
            "trajectories": int(x.shape[0]), "trajectories_dropped": dropped, "scale": scale,
            "mu": ee.mean(axis=0), "mu_star": np.abs(ee).mean(axis=0),
            "sigma": ee.std(axis=0, ddof=1)}
