"""Synthetic kanesens run files for the post-processing tests (and the docs/post examples).

write_run() writes an HDF5 file with the layout of the run file (docs/reference/hdf5.md) using h5py,
the way the C++ writer does: every dimension has a dimension scale (so xarray shows named dims),
names are fixed-length null-padded strings tagged `_Encoding = utf-8`, per-output series live in the
/outputs group and solver counters in /solver_stats. Designs (Saltelli, Morris) are generated here
too, so a test can put a closed-form function behind them.

Run as a script to write the example file used for docs/post:
    /usr/bin/python3 tests/python/post_fixtures.py pendulum-saltelli OUT.h5
"""
from __future__ import annotations

import sys
from pathlib import Path

import h5py
import numpy as np
import yaml

FILL = {"status": 0}


def _strings(names):
    """Fixed-length, null-padded UTF-8 strings (what parallel HDF5 can write)."""
    encoded = [str(n).encode("utf-8") for n in names]
    width = max([len(e) for e in encoded] + [1])
    return np.array(encoded, dtype=f"S{width}")


def _string_dataset(group, name, values, dims, scales):
    ds = group.create_dataset(name, data=_strings(values))
    ds.attrs["_Encoding"] = "utf-8"
    _attach(ds, dims, scales)
    return ds


def _attach(ds, dims, scales):
    for axis, dim in enumerate(dims):
        ds.dims[axis].attach_scale(scales[dim])


def write_run(path, *, time, state_names, parameter_names, parameters, states,
              sensitivity_names=(), sensitivities=None, constraint_names=(), multipliers=None,
              outputs=None, status=None, message=None, solver_stats=None, initial_state=None,
              sampling_method="mc", seed=1, study=None, scene=None, design=None,
              sample_scale=True, legacy=False):
    """Write a run file. Shapes: parameters (ns, np), states (ns, nt, nx),
    sensitivities (ns, nt, nx, nsens), multipliers (ns, nt, nc), outputs {name: (ns, nt)},
    solver_stats {name: (ns,)}. study/scene: dicts dumped to the root attributes as YAML text.
    As `kanesens run` does, the study's `vary:` distributions go to the /vary group and a
    Saltelli or Morris design's labels to /design_block, /design_row, /design_input (rows in
    the writer's order: blocks of P+2, trajectories of P+1; a Morris step's input is the one
    whose value changed most). design: {label: (ns,)} integer labels instead of those.
    legacy=True writes neither /vary nor labels (a file of an older kanesens).
    sample_scale=False writes the sample dimension as a netCDF pure dimension (no coordinate
    values), the other way a writer may declare it."""
    time = np.asarray(time, dtype=float)
    parameters = np.asarray(parameters, dtype=float)
    states = np.asarray(states, dtype=float)
    ns, nt, nx = states.shape
    status = np.ones(ns, dtype=np.int32) if status is None else np.asarray(status, np.int32)
    message = [""] * ns if message is None else list(message)
    with h5py.File(path, "w") as f:
        scales = {}
        if sample_scale:
            scales["sample"] = f.create_dataset("sample", data=np.arange(ns, dtype=np.int64))
            scales["sample"].make_scale("sample")
        else:
            # netCDF-4's representation of a dimension without a coordinate variable.
            scales["sample"] = f.create_dataset("sample", shape=(ns,), dtype="f4")
            scales["sample"].make_scale(
                "This is a netCDF dimension but not a netCDF variable.%10d" % ns)
        scales["time"] = f.create_dataset("time", data=time)
        scales["time"].make_scale("time")
        scales["time"].attrs["units"] = "s"
        for dim, var, names in (("state", "state_name", state_names),
                                ("parameter", "parameter_name", parameter_names),
                                ("sensitivity", "sensitivity_name", sensitivity_names),
                                ("constraint", "constraint_name", constraint_names)):
            if len(names) == 0:
                continue
            # The name dataset is the dimension scale of its dimension; xarray sees it as a
            # variable `state_name` on dimension `state` (the scale's NAME).
            ds = f.create_dataset(var, data=_strings(names))
            ds.attrs["_Encoding"] = "utf-8"
            ds.make_scale(dim)
            scales[dim] = ds

        def put(name, data, dims, group=f):
            ds = group.create_dataset(name, data=data, chunks=(min(64, len(data)),) + data.shape[1:])
            _attach(ds, dims, scales)
            return ds

        put("parameters", parameters, ("sample", "parameter"))
        if initial_state is None:
            initial_state = states[:, 0, :]
        put("initial_state", np.asarray(initial_state, float), ("sample", "state"))
        put("states", states, ("sample", "time", "state"))
        if multipliers is not None:
            put("multipliers", np.asarray(multipliers, float), ("sample", "time", "constraint"))
        if sensitivities is not None:
            put("sensitivities", np.asarray(sensitivities, float),
                ("sample", "time", "state", "sensitivity"))
        grp = f.create_group("outputs")
        for name, values in (outputs or {}).items():
            put(name, np.asarray(values, float), ("sample", "time"), grp)
        ds = f.create_dataset("status", data=status)
        _attach(ds, ("sample",), scales)
        _string_dataset(f, "message", message, ("sample",), scales)
        grp = f.create_group("solver_stats")
        for name, values in (solver_stats or {}).items():
            put(name, np.asarray(values), ("sample",), grp)
        if design is None and not legacy:
            design = design_labels(sampling_method, parameters)
        for name, values in (design or {}).items():
            ds = f.create_dataset(name, data=np.asarray(values, np.int64))
            _attach(ds, ("sample",), scales)
        if not legacy:
            write_vary(f, (study or {}).get("vary") or {})
        f.attrs["kanesens_version"] = "0.0.0-test"
        f.attrs["scene_yaml"] = yaml.safe_dump(scene or {"kanesens": 1, "scene": {}})
        f.attrs["study_yaml"] = yaml.safe_dump(study or {"kanesens": 1})
        f.attrs["created_utc"] = "2024-01-01T00:00:00Z"
        f.attrs["mpi_ranks"] = np.int32(1)
        f.attrs["sampling_method"] = sampling_method
        f.attrs["seed"] = np.int64(seed)
    return Path(path)


def write_vary(f, vary):
    """/vary/<input>: attribute `distribution` and the parameters under their `vary:` keys."""
    group = f.create_group("vary")
    for name, spec in vary.items():
        sub = group.create_group(name)
        sub.attrs["distribution"] = spec["dist"]
        for key, value in spec.items():
            if key != "dist":
                sub.attrs[key] = np.asarray(value, float) if key == "values" else float(value)


def design_labels(method, x):
    """The labels kanesens writes for runs in its own order, or {} for other designs."""
    ns, p = x.shape
    size = {"saltelli": p + 2, "morris": p + 1}.get(method)
    if size is None or ns % size:
        return {}
    block, row = np.divmod(np.arange(ns), size)
    if method == "saltelli":
        moved = np.where(row >= 2, row - 2, -1)
    else:
        step = np.abs(np.diff(x, axis=0, prepend=x[:1]))
        moved = np.where(row > 0, step.argmax(axis=1), -1)
    return {"design_block": block, "design_row": row, "design_input": moved}


# ---------------------------------------------------------------------------------------------
# Designs

def uniform_ppf(u, low, high):
    return low + (high - low) * u


def saltelli_design(n_base, ppfs, seed=0, qmc=True):
    """Rows ordered per base point j: A_j, B_j, AB_j^(1..P) where AB^(i) is A with column i
    taken from B (Saltelli et al. 2010). Returns (x (N(P+2), P), A, B)."""
    p = len(ppfs)
    if qmc:
        from scipy.stats import qmc as _qmc
        u = _qmc.Sobol(2 * p, scramble=True, seed=seed).random(n_base)
    else:
        u = np.random.default_rng(seed).random((n_base, 2 * p))
    a = np.column_stack([ppf(u[:, i]) for i, ppf in enumerate(ppfs)])
    b = np.column_stack([ppf(u[:, p + i]) for i, ppf in enumerate(ppfs)])
    rows = np.empty((n_base, p + 2, p))
    rows[:, 0], rows[:, 1] = a, b
    for i in range(p):
        rows[:, 2 + i] = a
        rows[:, 2 + i, i] = b[:, i]
    return rows.reshape(-1, p), a, b


def morris_design(r, p, levels=4, seed=0):
    """r one-at-a-time trajectories of P+1 rows on the unit grid {0, 1/(L-1), ..., 1} with
    step Δ = L/(2(L-1)) (Morris 1991). Returns x (r(P+1), P) in [0, 1]."""
    rng = np.random.default_rng(seed)
    delta = levels / (2.0 * (levels - 1))
    grid = np.arange(levels // 2) / (levels - 1)     # start levels that keep x + Δ inside
    out = []
    for _ in range(r):
        x = rng.choice(grid, size=p)
        sign = rng.choice([-1.0, 1.0], size=p)
        x = np.where(sign < 0, x + delta, x)         # start high where the step goes down
        traj = [x.copy()]
        for i in rng.permutation(p):
            x = x.copy()
            x[i] += sign[i] * delta
            traj.append(x)
        out.append(traj)
    return np.array(out).reshape(-1, p)


# ---------------------------------------------------------------------------------------------
# Functions with known answers

def ishigami(x, a=7.0, b=0.1):
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_indices(a=7.0, b=0.1):
    """Analytic first- and total-order indices of the Ishigami function, x ~ U(-π, π)^3."""
    pi = np.pi
    v1 = 0.5 * (1 + b * pi ** 4 / 5) ** 2
    v2 = a ** 2 / 8
    v13 = b ** 2 * pi ** 8 * (1 / 18 - 1 / 50)
    var = v1 + v2 + v13
    return np.array([v1, v2, 0.0]) / var, np.array([v1 + v13, v2, v13]) / var


def study(vary, method="saltelli"):
    """A study dict with the given `vary:` section ({name: {dist: ..., ...}})."""
    return {"kanesens": 1, "scene": "scene.yaml", "time": {"end": 1.0, "outputs": 2},
            "sampling": {"method": method, "samples": 0, "seed": 1}, "vary": vary}


def uniform_vary(bounds):
    return {name: {"dist": "uniform", "low": float(lo), "high": float(hi)}
            for name, (lo, hi) in bounds.items()}


def write_function_run(path, x, names, values, gradient=None, method="mc", vary=None,
                       time=None, status=None, output=None, legacy=False):
    """A run whose single state `y` is a closed-form function of the inputs.
    x (ns, P); values (ns, nt) or (ns,); gradient ∂y/∂x (ns, nt, P) or (ns, P) written as
    /sensitivities with sensitivity names = input names; output: also write y as
    /outputs/<output>."""
    values = np.asarray(values, float)
    if values.ndim == 1:
        values = values[:, None]
        gradient = None if gradient is None else np.asarray(gradient, float)[:, None, :]
    ns, nt = values.shape
    time = np.linspace(0.0, 1.0, nt) if time is None else time
    sens = None if gradient is None else np.asarray(gradient, float)[:, :, None, :]
    return write_run(path, time=time, state_names=["y"], parameter_names=names, parameters=x,
                     states=values[..., None], sensitivity_names=names if sens is not None
                     else (), sensitivities=sens, status=status, sampling_method=method,
                     study=study(vary or {}, method), legacy=legacy,
                     outputs=None if output is None else {output: values})


PENDULUM_VARY = {"L": {"dist": "uniform", "low": 0.95, "high": 1.05},
                 "m": {"dist": "uniform", "low": 0.5, "high": 1.5},
                 "pivot.q0": {"dist": "normal", "mean": 0.3, "std": 0.03}}


def _pendulum_ppfs():
    from scipy.stats import norm
    return [lambda u: uniform_ppf(u, 0.95, 1.05), lambda u: uniform_ppf(u, 0.5, 1.5),
            lambda u: norm.ppf(u, 0.3, 0.03)]


def pendulum_saltelli(path, n_base=256, nt=201, t_end=10.0, seed=3, fail=(5, 77), legacy=False):
    """The pendulum of pendulum_run() in a Saltelli design of n_base base points."""
    x, _, _ = saltelli_design(n_base, _pendulum_ppfs(), seed=seed)
    return pendulum_run(path, x, "saltelli", n_base, nt, t_end, seed, fail, legacy)


def pendulum_morris(path, r=40, nt=201, t_end=10.0, seed=3, fail=(5,)):
    """The pendulum of pendulum_run() in r Morris trajectories (4 levels, mapped through the
    inputs' quantile functions; the normal's 0 and 1 levels are moved to 1/8 and 7/8)."""
    u = np.clip(morris_design(r, 3, levels=4, seed=seed), 0.125, 0.875)
    x = np.column_stack([ppf(u[:, i]) for i, ppf in enumerate(_pendulum_ppfs())])
    return pendulum_run(path, x, "morris", r, nt, t_end, seed, fail)


def pendulum_run(path, x, method, samples, nt, t_end, seed, fail, legacy=False):
    """Small-angle pendulum θ(t) = θ0 cos(ωt), ω = √(g/L), with L ~ U(0.95, 1.05),
    m ~ U(0.5, 1.5) (no effect on θ) and θ0 ~ N(0.3, 0.03) (columns of x); rod tension
    as a multiplier, energy as an output, forward sensitivities ∂(θ, θ̇)/∂(L, m, θ0).
    Samples listed in `fail` are marked failed (status −3)."""
    g = 9.81
    L, m, q0 = x[:, 0:1], x[:, 1:2], x[:, 2:3]
    t = np.linspace(0.0, t_end, nt)[None, :]
    w = np.sqrt(g / L)
    th = q0 * np.cos(w * t)
    thd = -q0 * w * np.sin(w * t)
    dw_dL = -0.5 * w / L
    sens = np.zeros(th.shape + (2, 3))
    sens[..., 0, 0] = -q0 * t * np.sin(w * t) * dw_dL
    sens[..., 1, 0] = -q0 * (np.sin(w * t) + w * t * np.cos(w * t)) * dw_dL
    sens[..., 0, 2] = np.cos(w * t)
    sens[..., 1, 2] = -w * np.sin(w * t)
    energy = 0.5 * m * L ** 2 * thd ** 2 + 0.5 * m * g * L * th ** 2
    energy = energy + 1e-9 * np.random.default_rng(seed).standard_normal(energy.shape)
    tension = m * g * np.cos(th) + m * L * thd ** 2
    ns = x.shape[0]
    status = np.ones(ns, np.int32)
    message = [""] * ns
    states = np.stack([th, thd], axis=-1)
    for i in fail:
        status[i] = -4
        message[i] = "CV_CONV_FAILURE at t = 4.2"
    rng = np.random.default_rng(seed + 1)
    stats = {"steps": rng.integers(300, 500, ns), "rhs_evals": rng.integers(400, 900, ns),
             "jac_evals": rng.integers(10, 40, ns), "error_test_fails": rng.integers(0, 5, ns),
             "wall_seconds": rng.uniform(0.01, 0.05, ns)}
    study = {"kanesens": 1, "scene": "pendulum.yaml", "time": {"end": t_end, "outputs": nt},
             "sampling": {"method": method, "samples": samples, "seed": seed},
             "vary": PENDULUM_VARY,
             "sensitivities": ["L", "m", "pivot.q0"],
             "record": ["states", "multipliers", "sensitivities", "energy"]}
    scene = {"kanesens": 1, "scene": {"name": "pendulum", "gravity": [0, -g, 0],
             "parameters": {"L": 1.0, "m": 1.0},
             "joints": [{"name": "pivot", "type": "revolute", "parent": "ground",
                         "child": "bob", "axis": [0, 0, 1]}],
             "constraints": [{"name": "rod", "type": "distance"}]}}
    return write_run(path, time=t[0], state_names=["pivot.q", "pivot.u"],
                     parameter_names=["L", "m", "pivot.q0"], parameters=x, states=states,
                     sensitivity_names=["L", "m", "pivot.q0"], sensitivities=sens,
                     constraint_names=["rod"], multipliers=tension[..., None],
                     outputs={"energy": energy}, status=status, message=message,
                     solver_stats=stats, sampling_method=method, seed=seed, study=study,
                     scene=scene, legacy=legacy)


EXAMPLES = {"pendulum-saltelli": pendulum_saltelli, "pendulum-morris": pendulum_morris}

if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] not in EXAMPLES:
        sys.exit(f"usage: {sys.argv[0]} {{{','.join(EXAMPLES)}}} OUT.h5")
    EXAMPLES[sys.argv[1]](sys.argv[2])
