"""What a run file holds and how the run went: sample counts by status, solver effort, energy
drift and constraint residual (the outputs `energy` and `constraint_residual`, when recorded)."""
from __future__ import annotations

from collections import Counter

import numpy as np

from .io import OK, OUTPUT_PREFIX, STATS_PREFIX, output_names, solver_stat_names


def summarize(ds) -> dict:
    status = np.asarray(ds["status"].values)
    ok = status == OK
    out = {"samples": int(status.size), "ok": int(ok.sum()), "failed": int((status < 0).sum()),
           "not_run": int((status == 0).sum()),
           "sampling_method": ds.attrs.get("sampling_method"), "seed": ds.attrs.get("seed"),
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
    if "constraint_residual" in out["outputs"] and ok.any():
        residual = np.abs(np.asarray(ds[OUTPUT_PREFIX + "constraint_residual"].values)[ok])
        out["constraint_residual_max"] = float(residual.max())
    return out
