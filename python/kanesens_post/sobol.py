"""Variance-based (Sobol') indices from a Saltelli design.

Design (see io.design): N base points, each a block of P+2 runs A_j, B_j, AB_j^(1..P), where
AB_j^(i) is A_j with input i taken from B_j; `kanesens run` labels every run with its block and
row (/design_block, /design_row). With y centred by its design mean,

    V      = Var over the 2N runs of A and B                       (total variance)
    V_i    = 1/N Σ_j y(B_j) (y(AB_j^(i)) − y(A_j))                   Saltelli et al. 2010, Table 2 (b)
    V_Ti   = 1/(2N) Σ_j (y(A_j) − y(AB_j^(i)))²                      Jansen 1999
    S_i = V_i / V,  S_Ti = V_Ti / V

Bootstrap confidence intervals resample base points (whole blocks) with replacement. A block
with a failed run is dropped whole (the estimators need all P+2 runs of a base point).
"""
from __future__ import annotations

import numpy as np

from .io import Design, RunFileError, select


def saltelli_blocks(des: Design, y: np.ndarray):
    """Arrange runs as (N, p+2, ...) blocks [A_j, B_j, AB_j^(i) for the p reported inputs],
    check the design is the Saltelli one, drop blocks with any NaN (failed run) in y.
    Returns (blocks, n_dropped)."""
    p = len(des.names)
    if des.method != "saltelli":
        raise RunFileError(f"sobol needs a Saltelli design; this run's sampling_method is "
                           f"'{des.method}'")
    # A block holds AB^(k) for every design column, fixed inputs included; keep the reported ones.
    index = des.block_index(len(des.columns) + 2, "Saltelli")
    index = index[:, [0, 1] + [2 + des.columns.index(n) for n in des.names]]
    nblock = index.shape[0]
    x = des.x[index]                                     # (N, p+2, p)
    a, b = x[:, 0], x[:, 1]
    for i in range(p):
        expected = a.copy()
        expected[:, i] = b[:, i]
        if not np.allclose(x[:, 2 + i], expected, rtol=1e-12, atol=0.0):
            raise RunFileError(
                f"run {2 + i} of each Saltelli block should be A with input '{des.names[i]}' "
                f"taken from B (blocks A, B, AB^(1..P) per base point); the file's rows are not "
                f"arranged that way")
    blocks = y[index]
    bad = np.isnan(blocks.reshape(nblock, -1)).any(axis=1)
    return blocks[~bad], int(bad.sum())


def indices(blocks: np.ndarray) -> dict:
    """S1, ST and the variances from (N, P+2, ...) blocks; trailing axes (time) are kept."""
    y = blocks - blocks.mean(axis=(0, 1))
    ya, yb, ye = y[:, 0], y[:, 1], y[:, 2:]
    var = np.concatenate([ya, yb]).var(axis=0)
    vi = np.mean(yb[:, None] * (ye - ya[:, None]), axis=0)
    vti = 0.5 * np.mean((ya[:, None] - ye) ** 2, axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        good = var > 0
        s1 = np.where(good, vi / np.where(good, var, 1), np.nan)
        st = np.where(good, vti / np.where(good, var, 1), np.nan)
    return {"S1": s1, "ST": st, "variance": var, "V_i": vi, "V_Ti": vti}


def bootstrap(blocks: np.ndarray, n_boot: int, seed: int = 0, level: float = 0.95) -> dict:
    """Percentile intervals of S1 and ST over n_boot resamplings of the base points."""
    rng = np.random.default_rng(seed)
    n = blocks.shape[0]
    draws = {"S1": [], "ST": []}
    for _ in range(n_boot):
        est = indices(blocks[rng.integers(0, n, n)])
        draws["S1"].append(est["S1"])
        draws["ST"].append(est["ST"])
    q = [50 * (1 - level), 50 * (1 + level)]
    return {k + "_ci": np.nanpercentile(np.array(v), q, axis=0) for k, v in draws.items()}


def analyze(ds, des: Design, name: str, at=None, n_boot: int = 200, seed: int = 0,
            over_time: bool = False) -> dict:
    """Indices of `name` at time `at` (nearest output time), at every time, or of an output
    that is one number per sample (neither)."""
    sel = select(ds, name, at, over_time)
    y, times = sel.y, sel.time
    blocks, dropped = saltelli_blocks(des, y)
    if blocks.shape[0] < 2:
        raise RunFileError(f"only {blocks.shape[0]} complete Saltelli base points")
    out = {"output": name, "time": times, "inputs": des.names,
           "base_points": int(blocks.shape[0]), "base_points_dropped": dropped,
           "estimators": {"first_order": "Saltelli 2010", "total_order": "Jansen 1999"}}
    out.update(indices(blocks))
    if n_boot > 0:
        out.update(bootstrap(blocks, n_boot, seed))
        out["bootstrap"] = n_boot
        out["confidence_level"] = 0.95
    return out
