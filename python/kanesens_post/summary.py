"""What a run file holds and how the run went: sample counts by status, solver effort, energy
drift and constraint residuals (the outputs `energy`, `position_residual` and
`velocity_residual`, when recorded)."""
from __future__ import annotations

from collections import Counter

import numpy as np

from .io import (OK, OUTPUT_PREFIX, STATS_PREFIX, RunFileError, output_names, response, select,
                 solver_stat_names)

#: what output_statistics() reports, per time (or once for one number per sample)
STATISTICS = ("mean", "std", "min", "p5", "median", "p95", "max")


def _whole(x):
    """A whole number stored as float64 (the run file's numeric attributes) as an int."""
    return int(x) if isinstance(x, (float, np.floating)) and float(x).is_integer() else x


def summarize(ds) -> dict:
    status = np.asarray(ds["status"].values)
    ok = status == OK
    out = {"samples": int(status.size), "ok": int(ok.sum()), "failed": int((status < 0).sum()),
           "not_run": int((status == 0).sum()),
           "sampling_method": ds.attrs.get("sampling_method"), "seed": _whole(ds.attrs.get("seed")),
           "kanesens_version": ds.attrs.get("kanesens_version"),
           "created_utc": ds.attrs.get("created_utc"), "mpi_ranks": ds.attrs.get("mpi_ranks"),
           "time": [float(ds["time"].values[0]), float(ds["time"].values[-1])],
           "states": [str(s) for s in ds["state"].values],
           "outputs": output_names(ds)}
    if "message" in ds and out["failed"]:
        messages = Counter(zip(status[status < 0].tolist(),
                               np.asarray(ds["message"].values)[status < 0].tolist()))
        out["failures"] = [{"status": s, "message": m, "count": c}
                           for (s, m), c in messages.most_common()]
    stats = {}
    for name in solver_stat_names(ds):
        values = np.asarray(ds[STATS_PREFIX + name].values, float)[ok]
        if values.size:
            stats[name] = {"median": float(np.median(values)), "max": float(values.max()),
                           "total": float(values.sum())}
    out["solver_stats"] = stats
    if "energy" in out["outputs"] and ok.any():
        energy = np.asarray(ds[OUTPUT_PREFIX + "energy"].values, float)[ok]
        drift = np.abs(energy - energy[:, :1]).max(axis=1)
        worst = int(np.argmax(drift))
        out["energy_drift"] = {"max_abs": float(drift[worst]),
                               "sample": int(np.flatnonzero(ok)[worst]),
                               "relative": float(drift[worst] / max(abs(energy[worst, 0]),
                                                                    np.finfo(float).tiny))}
    # record: constraint_residual writes max |g| and max |A u + a0| per output time.
    for name in ("position_residual", "velocity_residual"):
        if name in out["outputs"] and ok.any():
            residual = np.abs(np.asarray(ds[OUTPUT_PREFIX + name].values, float)[ok])
            out[name + "_max"] = float(np.nanmax(residual))
    return out


def output_statistics(ds, name: str, at=None) -> dict:
    """Mean, standard deviation and percentiles of state or output `name` over the completed
    samples: at time `at`, at every output time (a series without `at`), or once for an output
    that is one number per sample. Each statistic is a list (one entry per time)."""
    over_time = at is None and "time" in response(ds, name).dims
    sel = select(ds, name, at, over_time)
    y = sel.y[~np.isnan(sel.y.reshape(sel.y.shape[0], -1)).any(axis=1)]
    if y.shape[0] < 2:
        raise RunFileError(f"only {y.shape[0]} completed samples with a value of '{name}'")
    p5, p50, p95 = np.percentile(y, [5, 50, 95], axis=0)
    stats = {"mean": y.mean(axis=0), "std": y.std(axis=0, ddof=1), "min": y.min(axis=0), "p5": p5,
             "median": p50, "p95": p95, "max": y.max(axis=0)}
    time = None if sel.time is None else np.atleast_1d(sel.time).astype(float).tolist()
    out = {"output": name, "samples": int(y.shape[0]), "time": time}
    out.update({k: np.atleast_1d(v).astype(float).tolist() for k, v in stats.items()})
    return out
