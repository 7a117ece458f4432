"""Ensemble plots over time: percentile bands (5–95 %, 25–75 %) and the median of states and
outputs, of forward sensitivities, or of constraint multipliers, over the completed samples.
Units come from the scene (joint types name the unit of each coordinate and speed)."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402

from .io import RunFileError, response, state_sensitivities  # noqa: E402

MAX_PANELS = 6
#: joint type -> {state-name suffix: unit} (docs/reference/scene.md, "Joint coordinates")
JOINT_UNITS = {
    "revolute": {"q": "rad", "u": "rad/s"},
    "prismatic": {"q": "m", "u": "m/s"},
    "cylindrical": {"q1": "rad", "q2": "m", "u1": "rad/s", "u2": "m/s"},
    "universal": {"q1": "rad", "q2": "rad", "u1": "rad/s", "u2": "rad/s"},
    "planar": {"q1": "m", "q2": "m", "q3": "rad", "u1": "m/s", "u2": "m/s", "u3": "rad/s"},
    "spherical": {"qw": "1", "qx": "1", "qy": "1", "qz": "1",
                  "wx": "rad/s", "wy": "rad/s", "wz": "rad/s"},
    "free": {"x": "m", "y": "m", "z": "m", "qw": "1", "qx": "1", "qy": "1", "qz": "1",
             "vx": "m/s", "vy": "m/s", "vz": "m/s", "wx": "rad/s", "wy": "rad/s", "wz": "rad/s"},
}
OUTPUT_UNITS = {"energy": "J", "kinetic_energy": "J", "potential_energy": "J"}
#: constraint type -> unit of its multipliers (forces between points; others are generalized)
CONSTRAINT_UNITS = {"coincident": "N", "distance": "N"}


def units(scene_yaml: str) -> dict:
    """{state, output or constraint name: unit} from the scene text (the run's scene_yaml)."""
    out = dict(OUTPUT_UNITS)
    try:
        doc = yaml.safe_load(scene_yaml or "") or {}
    except yaml.YAMLError:
        return out
    scene = doc.get("scene", doc) if isinstance(doc, dict) else {}
    scene = scene if isinstance(scene, dict) else {}
    for joint in scene.get("joints") or []:
        for suffix, unit in JOINT_UNITS.get(joint.get("type"), {}).items():
            out[f"{joint.get('name')}.{suffix}"] = unit
    for constraint in scene.get("constraints") or []:
        out[f"constraint:{constraint.get('name')}"] = CONSTRAINT_UNITS.get(
            constraint.get("type"), "generalized force")
    return out


def _label(name, unit):
    return f"{name} [{unit}]" if unit else name


def _bands(ax, t, y, color="C0", label=None):
    """Median and 25–75 % band of y (sample, time), and the 5–95 % band unless a label is given
    (several series share the panel); NaN rows (failed samples) are left out."""
    y = y[~np.isnan(y).any(axis=1)]
    if y.shape[0] == 0:
        raise RunFileError("no completed samples to plot")
    p5, p25, p50, p75, p95 = np.percentile(y, [5, 25, 50, 75, 95], axis=0)
    if label is None:
        ax.fill_between(t, p5, p95, color=color, alpha=0.18, lw=0, label="5–95 %")
    ax.fill_between(t, p25, p75, color=color, alpha=0.38 if label is None else 0.3, lw=0,
                    label="25–75 %" if label is None else None)
    ax.plot(t, p50, color=color, lw=1.4, label="median" if label is None else label)
    return y.shape[0]


def _figure(n):
    fig, axes = plt.subplots(n, 1, figsize=(7.5, 1.2 + 2.1 * n), sharex=True, squeeze=False)
    return fig, axes[:, 0]


def _pick(requested, available, what):
    if requested:
        unknown = [r for r in requested if r not in available]
        if unknown:
            raise RunFileError(f"unknown {what}: {', '.join(unknown)}; "
                               f"available: {', '.join(available)}")
        return list(requested)
    return list(available)[:MAX_PANELS]


def plot(ds, kind="states", states=None, outputs=None, title=None):
    """A matplotlib Figure. kind: states (states and outputs), sensitivities, multipliers."""
    t = ds["time"].values
    unit = units(ds.attrs.get("scene_yaml", ""))
    state_names = [str(s) for s in ds["state"].values]
    if kind == "states":
        names = _pick(states, state_names, "states") if states or not outputs else []
        names += list(outputs or [])
        fig, axes = _figure(len(names))
        for ax, name in zip(axes, names):
            n = _bands(ax, t, np.asarray(response(ds, name).values, float))
            ax.set_ylabel(_label(name, unit.get(name)))
    elif kind == "sensitivities":
        names = _pick(states, state_names, "states")
        params = [str(p) for p in ds["sensitivity"].values] if "sensitivity" in ds.coords else []
        fig, axes = _figure(len(names))
        for ax, name in zip(axes, names):
            sens = np.asarray(state_sensitivities(ds, name).values, float)
            for j, p in enumerate(params):
                n = _bands(ax, t, sens[..., j], f"C{j}", f"∂/∂{p} (median, 25–75 %)")
            ax.set_ylabel(f"∂ {name} / ∂p" + (f"\n[{unit[name]} per unit of p]"
                                              if name in unit else ""))
            ax.legend(fontsize=8, loc="best")
    elif kind == "multipliers":
        if "multipliers" not in ds:
            raise RunFileError("the file has no /multipliers (record: [multipliers])")
        names = [str(c) for c in ds["constraint"].values]
        fig, axes = _figure(len(names))
        for ax, name in zip(axes, names):
            n = _bands(ax, t, np.asarray(ds["multipliers"].sel(constraint=name).values, float))
            base = name.split(".")[0].split("[")[0]      # "tip.x" or "tip[0]" -> "tip"
            ax.set_ylabel(_label(f"λ {name}", unit.get(f"constraint:{base}",
                                                        "generalized force")))
    else:
        raise RunFileError(f"unknown --kind {kind}; choose states, sensitivities, multipliers")
    axes[0].legend(fontsize=8, loc="best")
    axes[-1].set_xlabel("time [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.suptitle(f"{title or ''}  ({n} completed samples)".strip())
    fig.tight_layout()
    return fig


def plot_output(ds, name, title=None):
    """One state or output: percentile bands over time, or the histogram of an output that is
    one number per sample."""
    da = response(ds, name)
    values = np.asarray(da.values, float)
    if "time" in da.dims:
        fig, axes = _figure(1)
        n = _bands(axes[0], ds["time"].values, values)
        axes[0].set_ylabel(_label(name, units(ds.attrs.get("scene_yaml", "")).get(name)))
        axes[0].set_xlabel("time [s]")
        axes[0].legend(fontsize=8, loc="best")
    else:
        values = values[~np.isnan(values)]
        if values.size == 0:
            raise RunFileError("no completed samples to plot")
        fig, ax = plt.subplots(figsize=(7.5, 3.6))
        axes = [ax]
        ax.hist(values, bins=min(40, max(5, values.size // 5)), color="C0", alpha=0.8)
        ax.set_xlabel(name)
        ax.set_ylabel("samples")
        n = values.size
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.suptitle(f"{title or ''}  ({n} completed samples)".strip())
    fig.tight_layout()
    return fig


def save(fig, path):
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_sobol_over_time(result: dict):
    """S1 (solid) and ST (dashed) of each input against time, with bootstrap bands if present."""
    t = result["time"]
    fig, ax = plt.subplots(figsize=(9, 3.8))
    for j, name in enumerate(result["inputs"]):
        ax.plot(t, result["S1"][j], color=f"C{j}", lw=1.4, label=f"S1 {name}")
        ax.plot(t, result["ST"][j], color=f"C{j}", lw=1.2, ls="--", label=f"ST {name}")
        if "ST_ci" in result:
            ax.fill_between(t, result["ST_ci"][0][j], result["ST_ci"][1][j], color=f"C{j}",
                            alpha=0.15, lw=0)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"Sobol' index of {result['output']} [-]")
    ax.set_ylim(-0.05, 1.05)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(f"first-order (Saltelli 2010, solid) and total (Jansen, dashed; 95 % band) "
                 f"indices, {result['base_points']} base points", fontsize=10)
    fig.tight_layout()
    return fig


def plot_linear_uq(result: dict, unit=None):
    """Standard deviation from linear propagation against Monte Carlo; the two criteria of the
    verdict (variance ratio, mean bias in MC standard deviations) with their tolerance bands."""
    t, tol = result["time"], result["tolerance"]
    fig, (ax, bx, cx) = plt.subplots(3, 1, figsize=(7.5, 6.8), sharex=True)
    ax.plot(t, np.sqrt(result["variance_mc"]), lw=1.6, label="Monte Carlo")
    ax.plot(t, np.sqrt(result["variance_linear"]), lw=1.2, ls="--",
            label="linear (sensitivities at the mean)")
    ax.set_ylabel(_label(f"std of {result['output']}", unit))
    ax.legend(fontsize=8)
    bx.plot(t, result["variance_ratio"], color="C2", lw=1.2)
    bx.axhspan(1 - tol, 1 + tol, color="C2", alpha=0.15, label=f"1 ± {tol:g}")
    bx.set_ylabel("Var_lin / Var_MC [-]")
    bx.legend(fontsize=8, loc="lower left")
    with np.errstate(invalid="ignore", divide="ignore"):
        bias = np.abs(result["mean_linear"] - result["mean_mc"]) / np.sqrt(result["variance_mc"])
    cx.plot(t, bias, color="C3", lw=1.2)
    cx.axhspan(0, tol, color="C3", alpha=0.15, label=f"≤ {tol:g}")
    cx.set_ylabel("|mean_lin − mean_MC|\n/ std_MC [-]")
    cx.legend(fontsize=8, loc="upper left")
    cx.set_xlabel("time [s]")
    first = result.get("first_breakdown_time")
    for a in (ax, bx, cx):
        a.grid(alpha=0.3)
        if first is not None:
            a.axvline(first, color="k", lw=0.8, ls=":")
    ax.set_title("linearisation holds where both criteria are inside their bands"
                 + (f"; first fails at t = {first:.3g} s (dotted)" if first is not None else ""),
                 fontsize=10)
    fig.tight_layout()
    return fig
