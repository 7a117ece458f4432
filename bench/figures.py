"""The benchmark pages' figures, drawn from the committed result JSON (bench/make_tables.py
calls draw_all()).

Conventions, the same on every page: error on x, logarithmic, growing to the right (more
accurate to the left); work on y. A reference run is never drawn against itself (an error of
exactly zero is dropped, not clamped to a floor). Axis labels name the reference.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
PEERS = ROOT / "docs" / "peers"
WP = ROOT / "docs" / "workprecision"
TARGETS = [1e-4, 1e-6, 1e-8, 1e-10]

KS_STYLE = {"bdf": ("black", "D", "-", "kanesens BDF"), "adams": ("tab:gray", "P", "--", "kanesens Adams"),
            "dop853": ("tab:olive", "*", "-.", "kanesens DOP853")}
SB_STYLE = {"rkm": ("tab:purple", "o", "-", "Simbody RK-Merson"), "rkf": ("tab:pink", "h", "-", "Simbody RK-Feldberg"),
            "rk3": ("goldenrod", "<", "-", "Simbody RK3"), "verlet": ("tab:green", ">", ":", "Simbody Verlet"),
            "cpodes": ("tab:brown", "s", "-", "Simbody CPodes BDF"),
            "cpodes-adams": ("tab:orange", "v", "-", "Simbody CPodes Adams"),
            "cpodes-adams-newton": ("tab:red", "^", "-", "Simbody CPodes Adams/Newton")}
SCIPY_STYLE = {"RK45": ("tab:blue", "o", "-"), "DOP853": ("tab:orange", "s", "-"), "Radau": ("tab:green", "^", "-"),
               "LSODA": ("tab:red", "v", "-"), "BDF": ("tab:purple", "<", "-")}
FB_STYLE = {"bdf/multipliers/projection": ("black", "D", "-"), "adams/multipliers/baumgarte": ("tab:blue", "X", "--"),
            "adams/embedding/none": ("tab:gray", "P", "--"), "bdf/embedding/projection": ("tab:brown", "d", ":"),
            "dop853/embedding/none": ("tab:olive", "*", "-."), "dop853/multipliers/baumgarte": ("darkcyan", "p", "-.")}


def _load(p):
    import json
    return json.loads(Path(p).read_text())


def _line(ax, pts, style, label, lw=1.4):
    """pts: [(setting, error, time)] loose -> tight; zero errors (a run identical to the
    reference) are not drawn."""
    pts = [p for p in pts if p[1] is not None and p[1] > 0 and p[2] is not None]
    if not pts:
        return
    col, mk, ls = style[:3]
    ax.loglog([p[1] for p in pts], [p[2] for p in pts], color=col, marker=mk, ls=ls, lw=lw, ms=5, label=label)


def _finish(ax, xlabel):
    for e in TARGETS:
        ax.axvline(e, color="0.85", lw=0.8, zorder=0)
    ax.set_xlabel(xlabel)
    ax.grid(True, which="major", alpha=0.3)


def chains(json_path: Path, png: Path, peer: str) -> Path:
    """Work-precision on the planar N-link chains: kanesens against Simbody or SymPy + SciPy."""
    d = _load(json_path)
    if peer == "simbody":
        rows = [dict(r, setting=r["tol"]) for r in d["tta"]["rows"]]
        ns = sorted({r["n"] for r in rows})
        series = [(("simbody", m), SB_STYLE[m]) for m in (d.get("integrators") or ["rkm", "cpodes"])]
        ref = "kanesens Adams at rtol 1e-14"
    else:
        rows = [dict(r, setting=r["rtol"]) for r in d["runs"]]
        ns = sorted({r["n"] for r in rows})
        methods = [m for m in SCIPY_STYLE if any(r["tool"] == "scipy" and r["method"] == m for r in rows)]
        series = [(("scipy", m), SCIPY_STYLE[m] + (f"SciPy {m}",)) for m in methods]
        ref = f"kanesens Adams at rtol {d['meta']['ref_rtol']:.0e}"
    series += [(("kanesens", m), KS_STYLE[m]) for m in ("bdf", "adams", "dop853")]
    fig, axes = plt.subplots(1, len(ns), figsize=(5.0 * len(ns), 4.8), sharey=True, squeeze=False,
                             layout="constrained")
    for ax, n in zip(axes[0], ns):
        for (tool, m), st in series:
            pts = sorted([(r["setting"], r["error"], r["time_s"]) for r in rows
                          if r["n"] == n and r["tool"] == tool and r["method"] == m], key=lambda p: -p[0])
            _line(ax, pts, st, st[3], lw=1.6 if tool == "kanesens" else 1.1)
        ax.set_title(f"planar {n}-link chain, t ∈ [0, 10]", fontsize=10)
        _finish(ax, f"final-time max abs error (reference: {ref})")
    axes[0][0].set_ylabel("wall time per solve (s)")
    axes[0][0].legend(fontsize=7.5, loc="upper right")
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return png


def fourbar_sympy(json_path: Path, png: Path) -> Path:
    import fourbar_kanesens as fk
    d = _load(json_path)
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.8), layout="constrained")
    names = list(SCIPY_STYLE) + list(FB_STYLE)
    for name in names:
        rs = sorted([r for r in d["runs"] if r["method"] == name], key=lambda r: -r["rtol"])
        if not rs:
            continue
        tool = rs[0]["tool"]
        st = SCIPY_STYLE.get(name) or FB_STYLE[name]
        label = f"SciPy {name}" if tool == "scipy" else f"kanesens {fk.label(name)}"
        _line(ax, [(r["rtol"], r["error"], r["time_s"]) for r in rs], st, label, 1.6 if tool == "kanesens" else 1.1)
        g = [(r["rtol"], r["g_end"]) for r in rs if r.get("g_end") is not None and r["g_end"] > 0]
        if g:
            ax2.loglog([p[0] for p in g], [p[1] for p in g], color=st[0], marker=st[1], ls=st[2], ms=5, label=label)
    ax.set_title("four-bar, t ∈ [0, 10]: work-precision", fontsize=10)
    _finish(ax, "final-time max abs error over (q, u) (reference: energy quadrature)")
    ax.set_ylabel("wall time per solve (s)")
    ax.legend(fontsize=7, loc="upper right")
    ax2.set_title("loop-closure residual |g(q(10))|", fontsize=10)
    ax2.set_xlabel("rtol (atol = rtol·1e-2)")
    ax2.set_ylabel("max |g| at t = 10 (m)")
    ax2.grid(True, which="major", alpha=0.3)
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return png


def fourbar(json_path: Path, png: Path) -> Path:
    import fourbar_kanesens as fk
    tta = _load(json_path)["tta"]
    fig, ax = plt.subplots(figsize=(11, 5.4), layout="constrained")
    peer_style = dict(SB_STYLE)
    peer_style.update({"rk4": ("tab:red", "^", ":", "MuJoCo RK4 (fixed dt)"),
                       "euler": ("tab:orange", "v", ":", "MuJoCo Euler (fixed dt)"),
                       "implicit": ("tab:pink", "<", ":", "MuJoCo implicit (fixed dt)")})
    seen = []
    for r in tta["rows"]:
        if (r["tool"], r["method"]) not in seen:
            seen.append((r["tool"], r["method"]))
    for tool, m in seen:
        rs = sorted([r for r in tta["rows"] if (r["tool"], r["method"]) == (tool, m)], key=lambda r: -r["setting"])
        pts = [(r["setting"], r["error"], r["time_s"]) for r in rs]
        if tool == "kanesens":
            _line(ax, pts, FB_STYLE[m], "kanesens " + fk.label(m), 1.6)
        else:
            st = peer_style.get(m, ("0.5", "x", "-", f"{tool} {m}"))
            _line(ax, pts, st, st[3], 1.1)
    _finish(ax, "final-time max abs error over the six states (reference: energy quadrature)")
    ax.set_ylabel("wall time per solve (s)")
    ax.set_title("four-bar (configs/four_bar.yaml), t ∈ [0, 10]: tolerance sweeps; MuJoCo: dt sweep", fontsize=10)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return png


def workprecision() -> list[Path]:
    """docs/workprecision/*.png from docs/workprecision/*.json (bench/run_workprecision.py's
    problems and second views)."""
    import plot_workprecision as pw
    import run_workprecision as rw
    out = []
    for name in rw.PROBLEMS:
        p = WP / f"{name}.json"
        if p.exists():
            out.append(Path(pw.plot_file(str(p), str(WP), "final_rel_error", "wall_seconds")))
    for names, args in rw.VIEWS:
        opts = dict(zip(args[::2], args[1::2]))
        for name in names:
            p = WP / f"{name}.json"
            if p.exists():
                out.append(Path(pw.plot_file(str(p), str(WP), opts.get("--error", "final_rel_error"),
                                             opts.get("--work", "wall_seconds"), suffix=opts.get("--suffix", ""))))
    return out


def draw_all() -> list[Path]:
    out = []
    if (PEERS / "simbody.json").exists():
        out.append(chains(PEERS / "simbody.json", PEERS / "simbody_workprecision.png", "simbody"))
    if (PEERS / "sympy_scipy.json").exists():
        out.append(chains(PEERS / "sympy_scipy.json", PEERS / "sympy_scipy_workprecision.png", "sympy"))
    if (PEERS / "fourbar_sympy_scipy.json").exists():
        out.append(fourbar_sympy(PEERS / "fourbar_sympy_scipy.json", PEERS / "fourbar_sympy_scipy_workprecision.png"))
    if (PEERS / "fourbar.json").exists():
        out.append(fourbar(PEERS / "fourbar.json", PEERS / "fourbar_workprecision.png"))
    return out + workprecision()
