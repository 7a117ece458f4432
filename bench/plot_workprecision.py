#!/usr/bin/python3
"""Work-precision diagrams from `kanesens-workprecision --json` output.

    /usr/bin/python3 bench/plot_workprecision.py RESULT.json [RESULT2.json ...] \
        [-o docs/workprecision] [--error final_rel_error] [--work wall_seconds]

One PNG per JSON file (named after the file: chain4.json -> chain4.png): error on x, work on y,
both logarithmic, one curve per method over its tolerance sweep (RK4: over its step sizes).
Runs that failed (RK4 blow-up, CV_TOO_MUCH_WORK, ...) have no error; they are drawn as crosses
at the right edge of the plot, at their work, and counted in the legend. So are runs that ended
but whose error exceeds --max-error (default 10: no correct digit, e.g. an RK4 run that grew
without overflowing). When the rows carry
sensitivity errors, a second panel shows them (sens_final_rel_error) against the same work.

Uses matplotlib only (Debian's python3-matplotlib).
"""

import argparse
import json
import math
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {
    "bdf-exact": ("tab:blue", "o", "-"),
    "bdf-dq": ("tab:cyan", "s", "--"),
    "adams-newton": ("tab:orange", "^", "-"),
    "adams-functional": ("tab:red", "v", "--"),
    "dop853": ("tab:olive", "P", "-"),
    "rk4": ("black", "D", ":"),
    "sens-exact": ("tab:green", "o", "-"),
    "sens-dq": ("tab:purple", "s", "--"),
}

LABEL = {
    "final_rel_error": "final-time max relative error (floor {floor:g})",
    "l2_error": "L2 error over output times",
    "linf_error": "max abs error over output times",
    "sens_final_rel_error": "sensitivities: final-time max relative error",
    "sens_l2_error": "sensitivities: L2 error over output times",
    "energy_drift": "max |E(t) - E(0)|",
    "quaternion_norm_drift": "max | |q| - 1 |",
    "wall_seconds": "wall time, s (median)",
    "rhs_evals_total": "RHS evaluations",
}


def finite(x):
    return x is not None and isinstance(x, (int, float)) and math.isfinite(x) and x > 0


def panel(ax, data, error_key, work_key, title, max_error, reference=""):
    rows = [r for r in data["rows"] if not r.get("skipped")]
    if error_key.startswith("sens_"):  # only the runs that integrated sensitivities
        rows = [r for r in rows if r.get("with_sens")]
    methods = []
    for r in rows:
        if r["method"] not in methods:
            methods.append(r["method"])
    def usable(r):
        return r["ok"] and finite(r.get(error_key)) and r[error_key] <= max_error and finite(r.get(work_key))

    good = [r for r in rows if usable(r)]
    xs = [r[error_key] for r in good]
    xmax = max(xs) if xs else 1.0
    xmin = min(xs) if xs else 1e-12
    fail_x = xmax * 10
    plotted = False
    for m in methods:
        color, marker, ls = STYLE.get(m, ("gray", "x", "-"))
        pts = [r for r in rows if r["method"] == m and usable(r)]
        fails = [r for r in rows if r["method"] == m and not usable(r) and finite(r.get(work_key))]
        if not pts and not fails:
            continue
        label = m
        if fails:
            label += f" ({len(fails)} failed/diverged)"
        if pts:
            pts.sort(key=lambda r: r.get("tol") or 0 if m != "rk4" else -(r.get("h") or 0))
            ax.plot([r[error_key] for r in pts], [r[work_key] for r in pts], ls=ls, marker=marker, color=color,
                    label=label, ms=5, lw=1.4)
            plotted = True
        if fails:
            ax.plot([fail_x] * len(fails), [r[work_key] for r in fails], ls="none", marker="x", color=color, ms=8,
                    mew=2, label=None if pts else label)
            plotted = True
    ax.set_xscale("log")
    ax.set_yscale("log")
    xlabel = LABEL.get(error_key, error_key).format(floor=data.get("error_floor", 0))
    if reference and error_key not in ("energy_drift", "quaternion_norm_drift"):
        xlabel += f"\nagainst {reference}"
    ax.set_xlabel(xlabel)
    ax.set_ylabel(LABEL.get(work_key, work_key))
    ax.set_title("\n".join(textwrap.wrap(title, 70)) if "\n" not in title else title, fontsize=9)
    ax.grid(True, which="major", alpha=0.4)
    ax.grid(True, which="minor", alpha=0.12)
    if any(not usable(r) for r in rows):
        ax.axvline(fail_x / 2, color="0.6", lw=0.8, ls="--")
        ax.text(fail_x, 0.99, "failed", ha="center", va="top", fontsize=8, color="0.3",
                transform=ax.get_xaxis_transform())
        ax.set_xlim(min(xmin / 3, fail_x / 10), fail_x * 3)
    if plotted:
        ax.legend(fontsize=8, loc="best")


def plot_file(path, outdir, error_key, work_key, max_error=10.0, suffix=""):
    with open(path) as f:
        data = json.load(f)
    has_sens = any(finite(r.get("sens_final_rel_error")) for r in data["rows"])
    ncols = 2 if has_sens else 1
    fig, axes = plt.subplots(1, ncols, figsize=(6.4 * ncols, 5.0), squeeze=False, layout="constrained")
    ref = data.get("reference", {})
    if ref.get("kind") == "computed":
        rr = ref["row"]
        refdesc = f"a {rr.get('method', 'bdf-exact')} reference at rtol {rr['rtol']:.0e}"
    else:
        refdesc = f"the reference {ref.get('file', '?')}"
    title = (f"{os.path.basename(data['study'])} ({data['scene']}):\nt = {data['t0']:g}..{data['t_end']:g}, "
             f"{data['outputs']} outputs, atol = {data['atol_ratio']:g} rtol"
             + ("\n" + " ".join(data["set"]).replace("solver.constraints.", "") if data.get("set") else ""))
    panel(axes[0][0], data, error_key, work_key, title, max_error, refdesc)
    if has_sens:
        panel(axes[0][1], data, "sens_final_rel_error", work_key,
              "sensitivities to " + ", ".join(data.get("sensitivity_names", [])), max_error, refdesc)
    name = os.path.splitext(os.path.basename(path))[0] + suffix + ".png"
    out = os.path.join(outdir, name)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def fmt(x, f="{:.2e}"):
    return "–" if x is None else f.format(x)


def table(path, extra=()):
    """The rows of one JSON file as a Markdown table (docs/workprecision.md)."""
    with open(path) as f:
        data = json.load(f)
    has_sens = any(r.get("sens_final_rel_error") is not None for r in data["rows"])
    cols = ["method", "tol", "h", "final rel. error", "L2 error"] + (["sens. rel. error"] if has_sens else []) + \
        [c for c in extra] + ["time (ms)", "steps", "RHS evals", "status"]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in data["rows"]:
        status = "skipped" if r["skipped"] else ("ok" if r["ok"] else r["message"].split(":")[0])
        if r["ok"] and r.get("final_rel_error") is not None and r["final_rel_error"] > 10:
            status = "diverged"
        cells = [r["method"], fmt(r["tol"], "{:.0e}"), fmt(r["h"], "{:.2e}"), fmt(r["final_rel_error"]),
                 fmt(r["l2_error"])]
        if has_sens:
            cells.append(fmt(r["sens_final_rel_error"]))
        cells += [fmt(r.get(c)) for c in extra]
        cells += [fmt(None if r["skipped"] else r["wall_seconds"] * 1e3, "{:.2f}"), str(r["steps"]),
                  str(r["rhs_evals_total"]), status]
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("json", nargs="+", help="output of kanesens-workprecision --json")
    ap.add_argument("-o", "--outdir", default="docs/workprecision")
    ap.add_argument("--error", default="final_rel_error", help="row key for the x axis")
    ap.add_argument("--work", default="wall_seconds", help="row key for the y axis (wall_seconds, rhs_evals_total)")
    ap.add_argument("--max-error", type=float, default=10.0, help="errors above this count as failures")
    ap.add_argument("--suffix", default="", help="appended to the PNG name (chain4_rhs.png)")
    ap.add_argument("--table", action="store_true", help="print a Markdown table of the rows instead of plotting")
    ap.add_argument("--columns", default="", help="extra row keys for --table (comma-separated)")
    a = ap.parse_args(argv)
    if a.table:
        for p in a.json:
            print(table(p, [c for c in a.columns.split(",") if c]))
        return 0
    os.makedirs(a.outdir, exist_ok=True)
    for p in a.json:
        print(plot_file(p, a.outdir, a.error, a.work, a.max_error, a.suffix))
    return 0


if __name__ == "__main__":
    sys.exit(main())
