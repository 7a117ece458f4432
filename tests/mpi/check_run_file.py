"""Checks a file written by run_file_writer (tests/mpi/run_file_writer.cpp) with h5py and xarray.

    check_run_file.py complete PATH RANKS      every sample written (sample 7 failed, status -4)
    check_run_file.py killed PATH RANKS K      rank 0 was killed after its K-th sample

The expected values mirror write_demo_sample() in run_file_writer.cpp.
"""
import sys

import h5py
import numpy as np
import xarray as xr

T, N, STATES = 5, 10, ["shoulder.q", "elbow.q", "shoulder.u", "elbow.u"]
FAILED = 7


def expected(i):
    t = np.arange(T)[:, None]
    j = np.arange(len(STATES))[None, :]
    return {
        "parameters": i + 0.1 * np.arange(2),
        "initial_state": 10.0 * i + np.arange(4),
        "states": 1000.0 * i + 10 * t + j,
        "multipliers": -(1000.0 * i + 10 * t + np.arange(2)[None, :]),
        "sensitivities": (1000.0 * i + 100 * t + 10 * j)[:, :, None],
        "outputs/energy": i + 0.01 * np.arange(T),
        "outputs/constraint_residual": i + 0.01 * np.arange(T) + 100,
        "solver_stats/steps": 10.0 * i,
        "solver_stats/rhs_evals": 10.0 * i + 1,
        "solver_stats/wall_seconds": 10.0 * i + 2,
    }


def check_row(f, i):
    for name, want in expected(i).items():
        got = f[name][i]
        assert np.array_equal(got, want), f"sample {i} {name}: {got} != {want}"


def check_complete(path, ranks):
    with h5py.File(path, "r") as f:
        status = f["status"][:]
        want = np.ones(N, dtype=np.int32)
        want[FAILED] = -4
        assert np.array_equal(status, want), status
        for i in range(N):
            check_row(f, i)

    ds = xr.open_dataset(path, engine="h5netcdf")
    assert ds.states.dims == ("sample", "time", "state"), ds.states.dims
    assert ds.sensitivities.dims == ("sample", "time", "state", "sensitivity")
    assert ds.multipliers.dims == ("sample", "time", "constraint")
    assert ds.parameters.dims == ("sample", "parameter")
    assert ds.initial_state.dims == ("sample", "state")
    assert ds.status.dims == ("sample",) and ds.message.dims == ("sample",)
    assert list(ds.state.values) == STATES and all(isinstance(s, str) for s in ds.state.values)
    assert list(ds.parameter.values) == ["m2", "shoulder.q0"]
    assert list(ds.constraint.values) == ["tip.x", "tip.y"]
    assert list(ds.sensitivity.values) == ["m2"]
    assert list(ds.state_name.values) == STATES
    assert list(ds.sample.values) == list(range(N))
    assert np.allclose(ds.time.values, [0, 0.25, 0.5, 0.75, 1.0])
    elbow = ds.states.sel(state="elbow.q", sample=3).values
    assert np.array_equal(elbow, 3000.0 + 10 * np.arange(T) + 1), elbow
    sens = ds.sensitivities.sel(state="shoulder.u", sensitivity="m2", sample=2).values
    assert np.array_equal(sens, 2000.0 + 100 * np.arange(T) + 20), sens
    assert ds.multipliers.sel(constraint="tip.y", sample=1, time=0.5).item() == -(1000 + 20 + 1)

    message = ds.message.values[FAILED]
    assert isinstance(message, str) and message.startswith("CVODE failed at t = 0.5: xxx")
    assert message.endswith("...") and len(message.encode()) == 160, message
    assert ds.message.values[0] == ""

    assert ds.attrs["scene_yaml"] == "scene:\n  name: démo α\n", ds.attrs
    assert ds.attrs["sampling_method"] == "sobol" and ds.attrs["study_hash"] == "hash-1"
    assert ds.attrs["mpi_ranks"] == ranks and ds.attrs["seed"] == 42
    for name in ["kanesens_version", "study_yaml", "created_utc"]:
        assert isinstance(ds.attrs[name], str), name

    outputs = xr.open_dataset(path, engine="h5netcdf", group="outputs")
    assert outputs.energy.dims == ("sample", "time")
    stats = xr.open_dataset(path, engine="h5netcdf", group="solver_stats")
    assert stats.rhs_evals.dims == ("sample",)


def check_killed(path, ranks, k):
    with h5py.File(path, "r") as f:
        status = f["status"][:]
        assert set(status) <= {0, 1, -4}, status
        for i in np.flatnonzero(status == 1):
            check_row(f, i)
        done_by_rank0 = [ranks * m for m in range(k)]
        assert all(status[i] == 1 for i in done_by_rank0), status
        unwritten = ranks * k  # rank 0 died before starting this sample
        assert status[unwritten] == 0, status
        assert np.isnan(f["states"][unwritten]).all() and f["message"][unwritten] == b""
        print(f"killed file: {int((status == 1).sum())} samples complete, status {status}")


if __name__ == "__main__":
    mode, path, ranks = sys.argv[1], sys.argv[2], int(sys.argv[3])
    if mode == "complete":
        check_complete(path, ranks)
    else:
        check_killed(path, ranks, int(sys.argv[4]))
    print(f"{mode}: ok")
