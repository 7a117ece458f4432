"""kanesens-post: summaries, plots and sensitivity analyses of a kanesens run file.

    kanesens-post summary FILE [--output NAME [--at T]]
    kanesens-post plot FILE [--kind states|sensitivities|multipliers] [--states a,b]
                            [--outputs energy] [--output NAME] [--out PNG]
    kanesens-post sobol FILE --output NAME [--at T | --over-time] [--bootstrap B] [--out PNG]
    kanesens-post morris FILE --output NAME [--at T]
    kanesens-post dgsm FILE --output NAME [--at T]
    kanesens-post linear-uq FILE --output NAME [--at T | --over-time] [--tol 0.1] [--out PNG]
    kanesens-post draw SCENE_OR_STUDY.yaml [--q JOINT=V[,V..] ...] [--set NAME=VALUE ...] [-o PNG]
    kanesens-post animate FILE --sample I [-o GIF] [--fps 20] [--frames 100]

draw and animate run the kanesens executable (--kanesens PATH, $KANESENS, PATH, or the
checkout's build/kanesens) for the positions they draw; animate needs `record: [poses]`.
NAME is a state or an output (energy, or one of the study's outputs: a series needs --at T or
--over-time, an output that is one number per sample takes neither). Every subcommand takes
--json (one JSON object on stdout). Errors print one line and exit 2.
"""
from __future__ import annotations

import argparse
import json
import math
import sys

import numpy as np

from . import dgsm, linear_uq, morris, sobol, summary
from .distributions import StudyError
from .geometry import GeometryError
from .io import RunFileError, design, open_run


def _plain(value):
    """JSON-ready: arrays to lists, NaN/inf to null."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return _plain(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _fmt(v):
    return "n/a" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.4g}"


def _table(header, rows):
    widths = [max(len(str(r[i])) for r in [header] + rows) for i in range(len(header))]
    lines = ["  ".join(str(c).rjust(w) for c, w in zip(r, widths)) for r in [header] + rows]
    return "\n".join(lines)


def _csv(text):
    return [s.strip() for s in text.split(",") if s.strip()] if text else None


def _when(time):
    """" at t = … s" for a value at one output time, "" for one number per sample."""
    return "" if time is None else f" at t = {_fmt(time)} s"


def cmd_summary(args, ds):
    if args.output:
        r = summary.output_statistics(ds, args.output, args.at)
        times = r["time"] or [None]
        pick = np.linspace(0, len(times) - 1, min(len(times), 11)).astype(int)
        rows = [["-" if times[i] is None else _fmt(times[i])] + [_fmt(r[k][i]) for k in summary.STATISTICS]
                for i in pick]
        return r, (f"{r['output']} over {r['samples']} completed samples\n"
                   + _table(["t [s]"] + list(summary.STATISTICS), rows))
    r = summary.summarize(ds)
    lines = [f"{args.file}: {r['samples']} samples ({r['sampling_method']}, seed {r['seed']}): "
             f"{r['ok']} ok, {r['failed']} failed, {r['not_run']} not run"]
    for f in r.get("failures", []):
        lines.append(f"  status {f['status']} x{f['count']}: {f['message']}")
    if r["solver_stats"]:
        lines.append("solver statistics over ok samples:")
        lines.append(_table(["", "median", "max"], [[k, _fmt(v["median"]), _fmt(v["max"])]
                                                    for k, v in r["solver_stats"].items()]))
    if "energy_drift" in r:
        d = r["energy_drift"]
        lines.append(f"energy drift max |E(t) - E(0)| = {_fmt(d['max_abs'])} J "
                     f"(relative {_fmt(d['relative'])}, sample {d['sample']})")
    if "position_residual_max" in r or "velocity_residual_max" in r:
        lines.append(f"constraint residuals: max |g| = {_fmt(r.get('position_residual_max'))}, "
                     f"max |A u + a0| = {_fmt(r.get('velocity_residual_max'))}")
    return r, "\n".join(lines)


def _plot():
    from . import plot  # matplotlib: imported only by the commands that draw
    return plot


def cmd_plot(args, ds):
    plot = _plot()
    if args.output:
        fig = plot.plot_output(ds, args.output, title=args.file)
        out = args.out or f"{args.file.rsplit('.', 1)[0]}_{args.output}.png"
        plot.save(fig, out)
        return {"png": out, "output": args.output}, f"wrote {out}"
    fig = plot.plot(ds, args.kind, _csv(args.states), _csv(args.outputs), title=args.file)
    out = args.out or f"{args.file.rsplit('.', 1)[0]}_{args.kind}.png"
    plot.save(fig, out)
    return {"png": out, "kind": args.kind}, f"wrote {out}"


def _time_args(args):
    if args.over_time and args.at is not None:
        raise RunFileError("give either --at T or --over-time, not both")


def cmd_sobol(args, ds):
    _time_args(args)
    r = sobol.analyze(ds, design(ds), args.output, args.at, args.bootstrap, args.seed,
                      args.over_time)
    head = (f"Sobol' indices of {r['output']}: {r['base_points']} base points "
            f"({r['base_points_dropped']} dropped for failed runs)")
    if args.over_time:
        if args.out:
            plot = _plot()
            plot.save(plot.plot_sobol_over_time(r), args.out)
            head += f"\nwrote {args.out}"
        k = np.linspace(0, len(r["time"]) - 1, min(len(r["time"]), 11)).astype(int)
        rows = [[_fmt(r["time"][i])] + [f"{_fmt(r['S1'][j][i])}/{_fmt(r['ST'][j][i])}"
                                        for j in range(len(r["inputs"]))] for i in k]
        return r, head + "\nS1/ST over time\n" + _table(["t [s]"] + r["inputs"], rows)
    rows = []
    for j, name in enumerate(r["inputs"]):
        row = [name, _fmt(r["S1"][j]), _fmt(r["ST"][j])]
        if "S1_ci" in r:
            row[1] += f" [{_fmt(r['S1_ci'][0][j])}, {_fmt(r['S1_ci'][1][j])}]"
            row[2] += f" [{_fmt(r['ST_ci'][0][j])}, {_fmt(r['ST_ci'][1][j])}]"
        rows.append(row)
    return r, (head + f"{_when(r['time'])}, Var = {_fmt(r['variance'])}\n"
               + _table(["input", "S1 (95% CI)", "ST (95% CI)"], rows))


def cmd_morris(args, ds):
    r = morris.analyze(ds, design(ds), args.output, args.at)
    rows = [[n, _fmt(r["mu_star"][j]), _fmt(r["mu"][j]), _fmt(r["sigma"][j])]
            for j, n in enumerate(r["inputs"])]
    return r, (f"Morris elementary effects of {r['output']}{_when(r['time'])}, "
               f"{r['trajectories']} trajectories ({r['trajectories_dropped']} dropped), "
               f"{r['scale']} scale\n" + _table(["input", "mu*", "mu", "sigma"], rows))


def cmd_dgsm(args, ds):
    r = dgsm.analyze(ds, design(ds), args.output, args.at)
    rows = [[n, _fmt(r["nu"][j]), _fmt(r["total_index_bound"][j]), r["constant_used"][j]]
            for j, n in enumerate(r["inputs"])]
    text = (f"DGSM of {r['output']}{_when(r['time'])} over {r['samples']} samples, "
            f"Var = {_fmt(r['variance'])}\n"
            + _table(["input", "nu = E[(dy/dx)^2]", "S_T bound", "Poincare constant"], rows))
    if r["inputs_without_sensitivity"]:
        text += f"\nno sensitivity recorded for: {', '.join(r['inputs_without_sensitivity'])}"
    return r, text


def cmd_linear_uq(args, ds):
    _time_args(args)
    r = linear_uq.analyze(ds, design(ds), args.output, args.at, args.tol, args.over_time)
    head = (f"linear UQ of {r['output']} from sensitivities at sample "
            f"{r['linearisation_sample']} (nearest the input mean) vs Monte Carlo over "
            f"{r['mc_samples']} samples")
    if args.over_time:
        if args.out:
            plot = _plot()
            unit = plot.units(ds.attrs.get("scene_yaml", "")).get(args.output)
            plot.save(plot.plot_linear_uq(r, unit), args.out)
            head += f"\nwrote {args.out}"
        first = r["first_breakdown_time"]
        head += (f"\nlinearisation holds (|ratio-1| <= {args.tol:g} and |mean bias| <= "
                 f"{args.tol:g} std) at "
                 f"{100 * r['holds_fraction']:.0f}% of output times; "
                 + ("everywhere" if first is None else f"first fails at t = {_fmt(first)} s"))
        k = np.linspace(0, len(r["time"]) - 1, min(len(r["time"]), 11)).astype(int)
        rows = [[_fmt(r["time"][i]), _fmt(r["mean_linear"][i]), _fmt(r["mean_mc"][i]),
                 _fmt(r["variance_linear"][i]), _fmt(r["variance_mc"][i]),
                 _fmt(r["variance_ratio"][i]), "yes" if r["holds"][i] else "no"] for i in k]
    else:
        rows = [["-" if r["time"] is None else _fmt(r["time"]), _fmt(r["mean_linear"]), _fmt(r["mean_mc"]),
                 _fmt(r["variance_linear"]), _fmt(r["variance_mc"]),
                 _fmt(r["variance_ratio"]), "yes" if r["holds"] else "no"]]
    text = head + "\n" + _table(["t [s]", "mean lin", "mean MC", "var lin", "var MC", "ratio",
                                 "holds"], rows)
    if "warning" in r:
        text += "\nwarning: " + r["warning"]
    return r, text


def cmd_draw(args):
    from . import draw, geometry
    geo = geometry.scene_geometry(args.file, args.q, args.set or [], args.kanesens)
    out = args.o or f"{args.file.rsplit('.', 1)[0]}.png"
    fig = draw.draw(geo)
    fig.savefig(out, dpi=args.dpi)
    view = draw.planar_view(geo)
    result = {"png": out, "scene": geo["scene"], "view": "3d" if view is None else "2d",
              "bodies": {b: v["position"] for b, v in geo["bodies"].items()},
              "joints": {j["name"]: j["child_point"] for j in geo["joints"]}}
    return result, f"wrote {out} ({result['view']})"


def cmd_animate(args):
    import tempfile
    from pathlib import Path

    import h5py
    import yaml

    from . import draw, geometry
    with h5py.File(args.file, "r") as f:
        if "poses" not in f:
            raise RunFileError(f"{args.file}: no /poses (the study needs record: [poses])")
        n = f["poses"].shape[0]
        if not 0 <= args.sample < n:
            raise RunFileError(f"--sample {args.sample}: the file has samples 0..{n - 1}")
        status = int(f["status"][args.sample])
        if status != 1:
            raise RunFileError(f"sample {args.sample} has status {status} (not ok): nothing to draw")
        text = lambda v: v.decode() if isinstance(v, bytes) else str(v)  # noqa: E731
        bodies = [text(b).rstrip("\x00") for b in f["body"][()]]
        times = np.asarray(f["time"][()], float)
        poses = np.asarray(f["poses"][args.sample], float)
        scene_text = text(f.attrs["scene_yaml"])
        try:  # the study's points (position outputs) are drawn too
            study_outputs = (yaml.safe_load(text(f.attrs.get("study_yaml", ""))) or {}).get("outputs")
        except (yaml.YAMLError, AttributeError):
            study_outputs = None
        sets = [s for s in text(f.attrs.get("set_arguments", "")).split()
                if s.split("=")[0].split(".")[0] not in ("time", "solver", "sampling")]
        if "parameters" in f:
            names = [text(p).rstrip("\x00") for p in f["parameter"][()]]
            sets += [f"{p}={v!r}" for p, v in zip(names, f["parameters"][args.sample])]
    with tempfile.TemporaryDirectory(prefix="kanesens-animate-") as tmp:
        scene = Path(tmp) / "scene.yaml"
        scene.write_text(scene_text, encoding="utf-8")
        geo = geometry.scene_geometry(scene, None, sets, args.kanesens, study_outputs)
    out = args.o or f"{args.file.rsplit('.', 1)[0]}_sample{args.sample}.gif"
    frames, _ = draw.animate(geo, times, poses, bodies, out, fps=args.fps, max_frames=args.frames,
                             title=f"{geo['scene']}, sample {args.sample}", dpi=args.dpi)
    return ({"gif": out, "sample": args.sample, "frames": len(frames)},
            f"wrote {out} ({len(frames)} frames)")


def parser():
    p = argparse.ArgumentParser(prog="kanesens-post", description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="command", required=True)

    def add(name, func, help_):
        s = sub.add_parser(name, help=help_)
        s.add_argument("file", help="run file written by kanesens run")
        s.add_argument("--json", action="store_true", help="print one JSON object")
        s.set_defaults(func=func)
        return s

    s = add("summary", cmd_summary, "sample counts, solver statistics, energy drift; or statistics of one output")
    s.add_argument("--output", help="a state or output: its mean, std and percentiles")
    s.add_argument("--at", type=float, help="time [s] of a series (default: every output time)")
    s = add("plot", cmd_plot, "percentile bands over time")
    s.add_argument("--kind", default="states", choices=["states", "sensitivities", "multipliers"])
    s.add_argument("--states", help="comma-separated state names (default: the first 6)")
    s.add_argument("--outputs", help="comma-separated output names, e.g. energy")
    s.add_argument("--output", help="one state or output: bands over time, or a histogram of an "
                                    "output that is one number per sample")
    s.add_argument("--out", help="PNG path (default FILE_KIND.png)")
    for name, func, help_ in (("sobol", cmd_sobol, "first/total Sobol' indices (Saltelli design)"),
                              ("morris", cmd_morris, "Morris mu*, mu, sigma"),
                              ("dgsm", cmd_dgsm, "derivative-based measures and S_T bounds"),
                              ("linear-uq", cmd_linear_uq, "linearised mean/variance vs MC")):
        s = add(name, func, help_)
        s.add_argument("--output", required=True, help="a state name or an output name")
        s.add_argument("--at", type=float, help="time [s] of a series (nearest output time is used)")
        if name in ("sobol", "linear-uq"):
            s.add_argument("--over-time", action="store_true", help="at every output time")
            s.add_argument("--out", help="PNG of the --over-time result")
        if name == "sobol":
            s.add_argument("--bootstrap", type=int, default=200, help="resamplings (0: none)")
            s.add_argument("--seed", type=int, default=0, help="bootstrap seed")
        if name == "linear-uq":
            s.add_argument("--tol", type=float, default=0.1,
                           help="relative tolerance on variance (and mean, in std units)")
    s = sub.add_parser("draw", help="a picture of a scene at its initial state or a given one")
    s.add_argument("file", help="scene YAML")
    s.add_argument("--q", action="append", metavar="JOINT=V[,V..]",
                   help="a joint's coordinates (repeatable; others keep their q0)")
    s.add_argument("--set", action="append", metavar="NAME=VALUE",
                   help="a parameter or initial condition, as kanesens --set (repeatable)")
    s.add_argument("-o", help="PNG path (default SCENE.png)")
    s.add_argument("--dpi", type=int, default=100)
    s.add_argument("--kanesens", help="path of the kanesens executable")
    s.add_argument("--json", action="store_true", help="print one JSON object")
    s.set_defaults(func=cmd_draw, run_file=False)
    s = sub.add_parser("animate", help="an animated GIF of one sample's recorded poses")
    s.add_argument("file", help="run file written by kanesens run with record: [poses]")
    s.add_argument("--sample", type=int, required=True, help="sample index")
    s.add_argument("-o", help="GIF path (default FILE_sampleI.gif)")
    s.add_argument("--fps", type=int, default=20)
    s.add_argument("--frames", type=int, default=100, help="at most this many frames")
    s.add_argument("--dpi", type=int, default=60)
    s.add_argument("--kanesens", help="path of the kanesens executable")
    s.add_argument("--json", action="store_true", help="print one JSON object")
    s.set_defaults(func=cmd_animate, run_file=False)
    return p


def main(argv=None):
    args = parser().parse_args(argv)
    try:
        if getattr(args, "run_file", True):
            result, text = args.func(args, open_run(args.file))
        else:
            result, text = args.func(args)
    except (RunFileError, StudyError, GeometryError, OSError, KeyError) as err:
        print(f"kanesens-post {args.command}: {err}", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps(_plain(result), indent=1))
    else:
        print(text)
    return 0
