"""Checks on `kanesens run` output files for the MPI tests (run with Debian's python3).

  check_ensemble.py same A.h5 B.h5        datasets bitwise equal (timings excepted)
  check_ensemble.py xarray A.h5           named dimensions, coordinates, attributes via xarray
  check_ensemble.py status A.h5 OK FAIL NOTRUN   counts of status 1, < 0 and 0
  check_ensemble.py stat-at-least A.h5 NAME MIN  every sample's /solver_stats/NAME >= MIN
  check_ensemble.py initial-residual A.h5 MAX    every sample's position residual at t0 <= MAX
"""
import sys

import h5py
import numpy as np

TIMING = {"solver_stats/wall_seconds"}


def datasets(f):
    out = {}
    f.visititems(lambda name, obj: out.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None)
    return out


def same(a, b):
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        da, db = datasets(fa), datasets(fb)
        assert set(da) == set(db), (set(da) ^ set(db))
        for name in sorted(da):
            if name in TIMING:
                continue
            x, y = da[name], db[name]
            assert x.shape == y.shape and x.dtype == y.dtype, name
            if x.dtype.kind == "f":
                # bitwise, NaN included
                assert np.array_equal(x.view(np.uint64 if x.itemsize == 8 else np.uint32),
                                      y.view(np.uint64 if y.itemsize == 8 else np.uint32)), name
            else:
                assert np.array_equal(x, y), name
        for key in ("scene_yaml", "study_yaml", "study_hash", "sampling_method"):
            assert fa.attrs[key] == fb.attrs[key], key
    print(f"same: {a} == {b} ({len(da)} datasets)")


def check_xarray(path):
    import xarray as xr
    ds = xr.open_dataset(path, engine="h5netcdf")
    assert ds["states"].dims == ("sample", "time", "state"), ds["states"].dims
    assert ds["sensitivities"].dims == ("sample", "time", "state", "sensitivity")
    assert ds["parameters"].dims == ("sample", "parameter")
    assert list(ds["state"].values) == ["shoulder.q", "elbow.q", "shoulder.u", "elbow.u"], ds["state"].values
    assert list(ds["sensitivity"].values) == ["m2", "L1"]
    assert list(ds["parameter"].values) == ["m2", "elbow.q0"]
    x = ds["states"].sel(state="elbow.q").isel(time=0).values
    p = ds["initial_state"].sel(state="elbow.q").values
    assert np.allclose(x, p)
    # The elbow's initial angle is the sampled one; its sensitivity to m2 starts at 0.
    assert np.allclose(ds["parameters"].sel(parameter="elbow.q0").values, p)
    assert np.all(ds["sensitivities"].isel(time=0).values == 0)
    for key in ("kanesens_version", "scene_yaml", "study_yaml", "created_utc", "mpi_ranks", "sampling_method", "seed"):
        assert key in ds.attrs, key
    assert "double_pendulum" in ds.attrs["scene_yaml"]
    st = xr.open_dataset(path, engine="h5netcdf", group="solver_stats")
    assert "steps" in st and st["steps"].dims == ("sample",)
    out = xr.open_dataset(path, engine="h5netcdf", group="outputs")
    assert out["energy"].dims == ("sample", "time")
    # The study's outputs: series (sample, time), scalars (sample), and their sensitivities.
    assert out["tip.y"].dims == ("sample", "time") and out["work"].dims == ("sample",)
    assert np.array_equal(out["tip_y_end"].values, out["tip.y"].isel(time=-1).values, equal_nan=True)
    assert ds["stopped_at"].dims == ("sample",)
    sens = xr.open_dataset(path, engine="h5netcdf", group="output_sensitivities")
    assert sens["tip.y"].dims == ("sample", "time", "sensitivity"), sens["tip.y"].dims
    assert sens["work"].dims == ("sample", "sensitivity")
    assert np.all(np.isfinite(sens["work"].values))
    assert ds["poses"].dims == ("sample", "time", "body", "pose"), ds["poses"].dims
    assert list(ds["body"].values) == ["rod1", "rod2"] and list(ds["pose"].values) == ["x", "y", "z", "qw", "qx", "qy", "qz"]
    print(f"xarray: {path} ok, dims {dict(ds.sizes)}")


def status(path, ok, fail, notrun):
    with h5py.File(path, "r") as f:
        s = f["status"][()]
        msg = f["message"][()]
    counts = (int(np.sum(s == 1)), int(np.sum(s < 0)), int(np.sum(s == 0)))
    assert counts == (int(ok), int(fail), int(notrun)), f"status counts {counts} != {(ok, fail, notrun)}"
    for i in np.flatnonzero(s < 0):
        assert len(msg[i]) > 0, f"failed sample {i} has no message"
    print(f"status: {path} ok={counts[0]} failed={counts[1]} not_run={counts[2]}")


def events(path):
    """The study's stopping event `low`: /stopped_at is its time (NaN when it did not stop), the
    output times after it are NaN in the states and series outputs, the ones before are not, and
    the message says it stopped; some samples stop and some do not."""
    with h5py.File(path, "r") as f:
        stop = f["stopped_at"][()]
        low = f["outputs/low.time"][()]
        count = f["outputs/low.count"][()]
        t = f["time"][()]
        states = f["states"][()]
        tip = f["outputs/tip.y"][()]
        msg = [m.decode() if isinstance(m, bytes) else m for m in f["message"][()]]
        status = f["status"][()]
    assert np.all(status == 1), status
    assert np.array_equal(stop, low, equal_nan=True)
    stopped = np.isfinite(stop)
    assert 0 < stopped.sum() < len(stop), stopped
    assert np.array_equal(count, stopped.astype(float))
    with h5py.File(path, "r") as f:
        # /events/<name>: the first occurrence is NAME.time, the count NAME.count, NaN-padded rows.
        for name in ("low", "cross"):
            times = f[f"events/{name}/time"][()]
            n = f[f"events/{name}/count"][()]
            assert times.shape == (len(stop), f["occurrence"].shape[0])
            assert np.array_equal(times[:, 0], f[f"outputs/{name}.time"][()], equal_nan=True), name
            assert np.array_equal(n, f[f"outputs/{name}.count"][()]), name
            assert np.array_equal(f[f"events/{name}/time_sensitivities"][:, 0, :],
                                  f[f"output_sensitivities/{name}.time"][()], equal_nan=True), name
            for i in range(len(stop)):
                assert np.all(np.isfinite(times[i, :int(n[i])])) and np.all(np.isnan(times[i, int(n[i]):])), (name, i)
                assert np.all(np.diff(times[i, :int(n[i])]) > 0), (name, i)
        assert np.array_equal(f["events/low/time"][:, 0], stop, equal_nan=True)
    for i in range(len(stop)):
        after = t > stop[i] if stopped[i] else np.zeros(len(t), bool)
        assert np.all(np.isnan(states[i][after])) and np.all(np.isfinite(states[i][~after])), i
        assert np.all(np.isnan(tip[i][after])) and np.all(np.isfinite(tip[i][~after])), i
        assert msg[i].startswith("stopped by an event at t = ") == bool(stopped[i]), (i, msg[i])
    print(f"events: {path} {int(stopped.sum())} of {len(stop)} samples stopped by an event")


def stat_at_least(path, name, least):
    with h5py.File(path, "r") as f:
        v = f["solver_stats/" + name][()]
    assert np.all(v >= float(least)), f"{name}: {v}"
    print(f"stat: {path} {name} from {v.min():g} to {v.max():g}")


def initial_residual(path, most):
    with h5py.File(path, "r") as f:
        r = f["outputs/position_residual"][:, 0]
    assert np.all(r <= float(most)), r
    print(f"initial position residual: {path} at most {r.max():.1e}")


if __name__ == "__main__":
    cmd = sys.argv[1]
    if cmd == "same":
        same(sys.argv[2], sys.argv[3])
    elif cmd == "events":
        events(sys.argv[2])
    elif cmd == "xarray":
        check_xarray(sys.argv[2])
    elif cmd == "status":
        status(*sys.argv[2:6])
    elif cmd == "stat-at-least":
        stat_at_least(*sys.argv[2:5])
    elif cmd == "initial-residual":
        initial_residual(*sys.argv[2:4])
    else:
        raise SystemExit(f"unknown check {cmd}")
