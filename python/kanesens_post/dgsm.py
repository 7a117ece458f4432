"""Derivative-based global sensitivity measures from the recorded forward sensitivities.

    ν_i = E[(∂y/∂x_i)²]                          (Sobol' & Kucherenko 2009)
    S_Ti ≤ C_i ν_i / Var y                       (Lamboni et al. 2013)

C_i is the Poincaré constant of input i's distribution (distributions.py): (b − a)²/π² for
uniform inputs, σ² for normal ones. Expectations run over the completed samples of the file,
whatever the design (every row of a Saltelli design is distributed as the inputs are; a Morris
grid only approximately). y is a state or one of the study's outputs (their sensitivities are
recorded with them).
"""
from __future__ import annotations

import numpy as np

from .io import Design, RunFileError, input_gradient, select


def measures(gradient: np.ndarray, y: np.ndarray, constants) -> dict:
    """ν (…, P), Var y and the bound C ν / Var y from gradient (sample, …, P) and y (sample, …);
    rows with NaN (failed samples) are left out. constants: C_i per input (None: no bound)."""
    ok = ~np.isnan(y).reshape(y.shape[0], -1).any(axis=1)
    g, y = gradient[ok], y[ok]
    if g.shape[0] < 2:
        raise RunFileError(f"only {g.shape[0]} completed samples")
    nu = np.mean(g ** 2, axis=0)
    var = np.var(y, axis=0, ddof=1)
    c = np.array([np.nan if v is None else v for v in constants], float)
    with np.errstate(invalid="ignore", divide="ignore"):
        bound = c * nu / np.asarray(var)[..., None]
    return {"nu": nu, "variance": var, "poincare_constant": c, "total_index_bound": bound,
            "samples": int(g.shape[0])}


def analyze(ds, des: Design, name: str, at=None) -> dict:
    sel = select(ds, name, at)
    gradient, found, missing = input_gradient(ds, des, name, sel.k)
    y = sel.y
    constants, reasons = [], []
    for n in found:
        if n in des.dists:
            c, why = des.dists[n].poincare_constant()
        else:
            c, why = None, "no distribution in the study's vary: section"
        constants.append(c)
        reasons.append(why)
    out = {"output": name, "time": sel.time, "inputs": found,
           "inputs_without_sensitivity": missing, "constant_used": reasons}
    out.update(measures(gradient, y, constants))
    return out
