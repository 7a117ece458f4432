"""Open a kanesens run file (docs/reference/hdf5.md) as one lazy xarray.Dataset.

What open_run() returns, whatever the file's dimension-scale details:

    dims    sample, time, state, parameter, sensitivity, constraint, output, body, pose
    coords  sample (int), time (s), state / parameter / sensitivity / constraint / output /
            body / pose (str names)
    vars    parameters (sample, parameter)          inputs: never masked
            initial_state (sample, state)
            states (sample, time, state)            results: NaN where status != 1
            multipliers (sample, time, constraint)
            sensitivities (sample, time, state, sensitivity)
            output_<name> (sample, time) or (sample)
                                                    from /outputs/<name>: energy, residuals and
                                                    the study's outputs (series or one number)
            output_sensitivity_<name> (sample, [time,] sensitivity)
                                                    from /output_sensitivities/<name>
            poses (sample, time, body, pose)        record: poses; pose = x y z qw qx qy qz
            solver_stats_<name> (sample)            from /solver_stats/<name>: not masked (the
                                                    counters of a failed sample say how it failed)
            status (sample), message (sample)
            design_block, design_row, design_input (sample)
                                                    Saltelli and Morris labels (see design())
    attrs   the root attributes, text ones decoded to str, and
            vary: {input: {"distribution": kind, parameter: value, ...}} from the /vary group

Nothing is read until asked for: result variables are wrapped in a lazy masking array, so
`ds.states.isel(time=-1)` reads one time slice of every sample and nothing else.
"""
from __future__ import annotations

import difflib
from dataclasses import dataclass

import numpy as np
import xarray as xr
from xarray.backends import BackendArray
from xarray.core import indexing

from . import distributions

OK = 1
#: name dataset in the file -> dimension it labels
NAME_VARIABLES = {"state_name": "state", "parameter_name": "parameter",
                  "sensitivity_name": "sensitivity", "constraint_name": "constraint",
                  "output_name": "output", "body_name": "body", "pose_name": "pose"}
#: variables whose values are meaningless unless the sample completed
RESULT_VARIABLES = ("states", "multipliers", "sensitivities", "poses")
OUTPUT_PREFIX = "output_"
OUTPUT_SENSITIVITY_PREFIX = "output_sensitivity_"
#: outputs written by record: items (not the study's outputs:); they have no sensitivities
RECORDED_OUTPUTS = ("energy", "position_residual", "velocity_residual")
STATS_PREFIX = "solver_stats_"
#: per-sample design labels (Saltelli, Morris) and the group of input distributions
DESIGN_LABELS = ("design_block", "design_row", "design_input")
VARY_GROUP = "vary"


class RunFileError(ValueError):
    """The file does not follow the layout the analysis needs; the message says what is off."""


class _MaskedSamples(BackendArray):
    """Lazy view of a (sample, ...) variable reading NaN for the samples that did not complete.

    Indexing goes through xarray's explicit-indexing adapter (the backend-array protocol), so
    only the requested hyperslab is read from the file."""

    def __init__(self, variable: xr.Variable, ok: np.ndarray):
        self._variable = variable
        self._ok = ok
        self.shape = variable.shape
        self.dtype = np.dtype(np.result_type(variable.dtype, np.float32))

    def __getitem__(self, key):
        return indexing.explicit_indexing_adapter(
            key, self.shape, indexing.IndexingSupport.OUTER, self._read)

    def _read(self, key):
        values = np.array(self._variable[key].values, dtype=self.dtype)
        ok = self._ok[key[0]]
        if np.ndim(ok) == 0:
            if not ok:
                values[...] = np.nan
        else:
            values[~ok] = np.nan
        return values


def _masked(variable: xr.Variable, ok: np.ndarray) -> xr.Variable:
    data = indexing.LazilyIndexedArray(_MaskedSamples(variable, ok))
    return xr.Variable(variable.dims, data, attrs=variable.attrs)


def _text(value):
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray) and value.dtype.kind in "SO" and value.size == 1:
        return _text(value.item())
    return value


def _name_dims(ds: xr.Dataset, n_sample: int) -> xr.Dataset:
    """Canonical dims and string coordinates, whichever way the writer declared them: the name
    dataset as the dimension scale (h5netcdf then calls the dim `state_name`) or a separate
    dimension `state` that `state_name` lives on."""
    for var, dim in NAME_VARIABLES.items():
        if var not in ds.variables:
            continue
        names = [str(_text(v)) for v in ds[var].values]
        ds = ds.rename({var: dim}) if var in ds.dims else ds.drop_vars(var)
        ds = ds.assign_coords({dim: names})
    if "sample" not in ds.coords and "sample" in ds.dims:
        ds = ds.assign_coords(sample=np.arange(n_sample))
    return ds


def _group(path, group: str, prefix: str, ok, mask: bool) -> dict:
    try:
        sub = xr.open_dataset(path, engine="h5netcdf", group=group)
    except OSError:
        return {}
    out = {}
    for name, var in sub.variables.items():
        if name in sub.dims:  # a coordinate that leaked into the group
            continue
        out[prefix + name] = _masked(var, ok) if mask else var
    return out


def open_run(path) -> xr.Dataset:
    """Open a run file lazily (see the module docstring for what the Dataset holds)."""
    ds = xr.open_dataset(path, engine="h5netcdf", phony_dims="access")
    # /parameters exists only with vary: entries, /states only with record: states.
    for needed in ("status", "time"):
        if needed not in ds.variables:
            raise RunFileError(f"{path}: no /{needed} dataset; is this a kanesens run file?")
    status = np.asarray(ds["status"].values)
    ok = status == OK
    ds = _name_dims(ds, status.size)
    ds = ds.assign({name: _masked(ds[name].variable, ok)
                    for name in RESULT_VARIABLES if name in ds.variables})
    ds = ds.assign(_group(path, "outputs", OUTPUT_PREFIX, ok, mask=True))
    ds = ds.assign(_group(path, "output_sensitivities", OUTPUT_SENSITIVITY_PREFIX, ok, mask=True))
    ds = ds.assign(_group(path, "solver_stats", STATS_PREFIX, ok, mask=False))
    if "message" in ds.variables:
        ds["message"] = ("sample", [str(_text(m)) for m in ds["message"].values])
    ds.attrs = {k: _text(v) for k, v in ds.attrs.items()}
    vary = _vary(path)
    if vary is not None:
        ds.attrs["vary"] = vary
    ds["time"].attrs.setdefault("units", "s")
    return ds


def _vary(path):
    """{input: {"distribution": kind, parameter: value}} from /vary/<input> (one group per
    varied input, its attributes), or None for a file written without the group."""
    import h5py
    with h5py.File(path, "r") as f:
        group = f.get(VARY_GROUP)
        if not isinstance(group, h5py.Group):
            return None
        out = {}
        for name, sub in group.items():
            spec = {}
            for key, value in sub.attrs.items():
                value = _text(value)
                if isinstance(value, np.ndarray):
                    value = value.astype(float).tolist()
                elif isinstance(value, np.generic):
                    value = value.item()
                spec[key] = value
            out[name] = spec
        return out


def output_names(ds: xr.Dataset) -> list[str]:
    return [n[len(OUTPUT_PREFIX):] for n in ds.data_vars
            if n.startswith(OUTPUT_PREFIX) and not n.startswith(OUTPUT_SENSITIVITY_PREFIX)]


def solver_stat_names(ds: xr.Dataset) -> list[str]:
    return [n[len(STATS_PREFIX):] for n in ds.data_vars if n.startswith(STATS_PREFIX)]


def response(ds: xr.Dataset, name: str) -> xr.DataArray:
    """The values called `name`: a state (from /states, (sample, time)) or an output (from
    /outputs: (sample, time), or (sample) for an output that is one number per sample)."""
    if "state" in ds.coords and name in ds["state"].values:
        if "states" not in ds:
            raise RunFileError(f"'{name}' is a state, but the file has no /states (record: [states])")
        return ds["states"].sel(state=name, drop=True).rename(name)
    if OUTPUT_PREFIX + name in ds:
        return ds[OUTPUT_PREFIX + name].rename(name)
    raise RunFileError(unknown_name(ds, name))


def unknown_name(ds: xr.Dataset, name: str) -> str:
    """The one-line error for a name that is neither a state nor an output: the components of a
    vector output named bare (tip → tip.x, tip.y, tip.z), or the closest name, then the lists."""
    states = [str(s) for s in ds["state"].values] if "state" in ds.coords else []
    outputs = output_names(ds)
    components = [n for n in states + outputs if n.startswith(name + ".")]
    if components:
        hint = f"; name one of its components: {', '.join(components)}"
    else:
        close = difflib.get_close_matches(name, states + outputs, n=1)
        hint = f" (did you mean '{close[0]}'?)" if close else ""
    return (f"no state or output named '{name}'{hint}; states are: {', '.join(states) or '(none)'}; "
            f"outputs are: {', '.join(outputs) or '(none)'}")


def state_sensitivities(ds: xr.Dataset, name: str) -> xr.DataArray:
    """∂(state `name`)/∂p for every recorded sensitivity parameter p: (sample, time, sensitivity).
    An output's sensitivities: sensitivities()."""
    if "sensitivities" not in ds:
        raise RunFileError("the file has no /sensitivities (record: [sensitivities] in the study)")
    if name not in ds["state"].values:
        raise RunFileError(f"'{name}' is not a state; states are: {', '.join(ds['state'].values)}")
    return ds["sensitivities"].sel(state=name, drop=True)


def sensitivities(ds: xr.Dataset, name: str) -> xr.DataArray:
    """∂(`name`)/∂p for every recorded sensitivity p: a state's (sample, time, sensitivity) from
    /sensitivities, or an output's (sample, [time,] sensitivity) from /output_sensitivities."""
    if OUTPUT_SENSITIVITY_PREFIX + name in ds:
        return ds[OUTPUT_SENSITIVITY_PREFIX + name]
    if "state" in ds.coords and name in ds["state"].values:
        return state_sensitivities(ds, name)
    if name in RECORDED_OUTPUTS and name in output_names(ds):
        raise RunFileError(f"no sensitivities of output '{name}': the record: items energy and "
                           f"constraint_residual have none; a study output has them (outputs: "
                           f"{{e: {{type: energy, kind: total}}}} with sensitivities:)")
    if name in output_names(ds):
        raise RunFileError(f"no sensitivities of output '{name}' in the file: the study's outputs "
                           f"have them when the study lists sensitivities:")
    response(ds, name)  # raises: no such state or output
    raise RunFileError(f"no sensitivities of '{name}'")


@dataclass(frozen=True)
class Selection:
    """What an analysis reads of one state or output.

    y:    (sample,) values at one time, (sample, time) over time, or (sample,) of an output
          that is one number per sample
    time: the output time used (float), all output times (array), or None (one number)
    k:    the time index, slice(None) over time, or None (one number)"""
    name: str
    y: np.ndarray
    time: object
    k: object


def select(ds: xr.Dataset, name: str, at=None, over_time: bool = False) -> Selection:
    """`name` at --at T (nearest output time), over time, or, for an output that is one number
    per sample, as it is (it takes neither)."""
    da = response(ds, name)
    if "time" not in da.dims:
        if at is not None or over_time:
            raise RunFileError(f"'{name}' is one number per sample: it takes no --at or --over-time")
        return Selection(name, np.asarray(da.values, float), None, None)
    if over_time:
        return Selection(name, np.asarray(da.values, float), ds["time"].values, slice(None))
    if at is None:
        raise RunFileError(f"'{name}' is a series over time: give --at T")
    k = time_index(ds, at)
    return Selection(name, np.asarray(da.isel(time=k).values, float), ds["time"].values[k], k)


def time_index(ds: xr.Dataset, t: float) -> int:
    """Index of the output time nearest to t; t outside the recorded span is an error."""
    times = ds["time"].values
    if not times[0] - 1e-12 <= t <= times[-1] + 1e-12:
        raise RunFileError(f"--at {t}: the run covers t = {times[0]} .. {times[-1]} s")
    return int(np.argmin(np.abs(times - t)))


@dataclass(frozen=True)
class Design:
    """The sampled inputs and their arrangement.

    method:  root attribute sampling_method (saltelli, morris, mc, ...)
    columns: every input of the design, in /parameter_name order (`fixed` ones included)
    names:   the inputs the analyses report: the columns without `fixed` ones
    x:       (sample, len(names)) their values
    block:   (sample,) Saltelli base point j / Morris trajectory t (other designs: the sample)
    row:     (sample,) run inside the block: Saltelli 0 = A_j, 1 = B_j, 2 + k = AB_j^(k) (A_j
             with column k taken from B_j, k = 0..P−1 over `columns`); Morris step 0..P
    moved:   (sample,) the column k that the run changes: Saltelli AB_j^(k), the input a Morris
             step moved; −1 for A_j, B_j, a trajectory's start and other designs (−2: a step
             that changed more than one input, only when inferred from the values)
    dists:   {name: Distribution} ({} if unknown)
    labels:  where block/row/moved come from: "file" (/design_block, /design_row,
             /design_input), "row order" (a file without them: blocks of P+2 Saltelli runs,
             trajectories of P+1 Morris runs, moves from the value changes) or "none"
    """
    method: str
    columns: list
    names: list
    x: np.ndarray
    block: np.ndarray
    row: np.ndarray
    moved: np.ndarray
    dists: dict
    labels: str

    def block_index(self, size: int, what: str) -> np.ndarray:
        """(nblock, size) run indices, row by row; a missing or extra run is an error."""
        nblock = int(self.block.max()) + 1
        index = np.full((nblock, size), -1)
        if (self.row < 0).any() or (self.row >= size).any():
            raise RunFileError(f"{what} design: /design_row outside 0..{size - 1}")
        index[self.block, self.row] = np.arange(self.block.size)
        if (index < 0).any() or self.block.size != nblock * size:
            raise RunFileError(f"{what} design incomplete: {self.block.size} runs for {nblock} "
                               f"blocks of {size} runs")
        return index


def _distributions(ds: xr.Dataset) -> dict:
    """{name: Distribution} from the file's /vary group; files written without it (older
    kanesens) fall back to the `vary:` section of the study text in study_yaml."""
    if "vary" in ds.attrs:
        return distributions.from_attributes(ds.attrs["vary"])
    return distributions.from_study_yaml(ds.attrs.get("study_yaml", ""))


def _moves_from_values(x: np.ndarray, width: int) -> np.ndarray:
    """Morris labels of a file without /design_input: the column whose value changed from the
    previous run of the trajectory (−1: none changed, e.g. a fixed input; −2: several did)."""
    moved = np.full(x.shape[0], -1)
    steps = np.arange(x.shape[0]) % width != 0
    changed = np.abs(np.diff(x, axis=0, prepend=x[:1])) > 1e-12 * (1 + np.abs(x))
    count = changed.sum(axis=1)
    moved[steps & (count == 1)] = changed.argmax(axis=1)[steps & (count == 1)]
    moved[steps & (count > 1)] = -2
    return moved


def design(ds: xr.Dataset) -> Design:
    """Read the design: labels from /design_block, /design_row and /design_input (written by
    `kanesens run` for Saltelli and Morris designs), distributions from /vary. Files written
    before those existed are still read: Saltelli runs as blocks of P+2 consecutive rows per
    base point, Morris runs as trajectories of P+1 consecutive rows, the distributions from the
    study text."""
    method = str(ds.attrs.get("sampling_method", "")).lower()
    if "parameters" not in ds:
        raise RunFileError("the run varies no input (no /parameters: the study has no vary: entries)")
    dists = _distributions(ds)
    columns = [str(n) for n in ds["parameter"].values]
    params = np.asarray(ds["parameters"].values, dtype=float)
    names = [n for n in columns if not (n in dists and dists[n].kind == "fixed")] or columns
    x = params[:, [columns.index(n) for n in names]]
    ns, p = params.shape
    if all(label in ds for label in DESIGN_LABELS):
        block, row, moved = (np.asarray(ds[label].values, dtype=np.int64) for label in DESIGN_LABELS)
        labels = "file"
    elif "design_block" in ds and "design_row" in ds:  # labels without moves (older writers)
        block = np.asarray(ds["design_block"].values, dtype=np.int64)
        row = np.asarray(ds["design_row"].values, dtype=np.int64)
        moved = np.where(row >= 2, row - 2, -1)
        if method == "morris":
            order = np.lexsort((row, block))
            moved[order] = _moves_from_values(params[order], p + 1)
        labels = "file"
    elif method in ("saltelli", "morris"):
        size = p + 2 if method == "saltelli" else p + 1
        if ns % size:
            raise RunFileError(f"{ns} samples do not form {method} blocks of {size} rows "
                               f"(P = {p} design inputs: {', '.join(columns)})")
        block, row = np.divmod(np.arange(ns), size)
        moved = np.where(row >= 2, row - 2, -1) if method == "saltelli" else \
            _moves_from_values(params, size)
        labels = "row order"
    else:
        block, row, moved = np.arange(ns), np.zeros(ns, np.int64), np.full(ns, -1)
        labels = "none"
    return Design(method, columns, names, x, block, row, moved, dists, labels)


def input_gradient(ds: xr.Dataset, des: Design, name: str, k=None):
    """∂y/∂x_i of state or output `name` for the varied inputs that have recorded sensitivities
    (the /sensitivity_name entry equals the input's name). Returns (gradient (sample, [time,] n),
    names with sensitivities, varied names without). k: a time index, or None / slice(None)
    for all times (and for an output that is one number per sample)."""
    sens = sensitivities(ds, name)
    if isinstance(k, (int, np.integer)) and "time" in sens.dims:
        sens = sens.isel(time=k)
    recorded = [str(s) for s in ds["sensitivity"].values]
    found = [n for n in des.names if n in recorded]
    missing = [n for n in des.names if n not in recorded]
    if not found:
        raise RunFileError(f"none of the varied inputs ({', '.join(des.names)}) has a recorded "
                           f"sensitivity (sensitivities: {', '.join(recorded)})")
    gradient = np.asarray(sens.sel(sensitivity=found).values, float)
    return gradient, found, missing
