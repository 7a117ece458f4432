#!/usr/bin/python3
"""The sensitivity correctors side by side: `solver.sensitivity.method` simultaneous, staggered
and staggered1 (CVODES's sensitivity module) and stacked on the same study, with BDF and Adams
and Ns sensitivities.

  sensitivity_corrector.py OUT.json [--exe build/kanesens] [--runs K] [--scenes a,b] [--methods m,n]
                           [--ns 1,2,6] [--correctors simultaneous,staggered,staggered1,stacked]
                           [--error-control true,false]
  sensitivity_corrector.py --table OUT.json      # every configuration
  sensitivity_corrector.py --summary OUT.json    # simultaneous against staggered
  sensitivity_corrector.py --stacked OUT.json    # stacked against the module's corrector auto takes

A corrector a configuration does not offer (stacked with the embedding's restarts) is left out of
that configuration's row.

For every scene, method and Ns: K rounds, each running every corrector once (interleaved, so that
machine load hits them alike). The figure per configuration is the median of stats.wall_seconds
(the integration itself); the counters (steps, RHS and sensitivity-RHS evaluations, error test
failures) are those of the last run (they do not vary between runs). The sensitivities of every
corrector are compared with those of the first: the largest absolute difference over all outputs,
states and parameters, next to the largest |sensitivity| (a parameter the motion does not depend
on, as the rolling disc's mass, has sensitivities at round-off). Raw times to OUT.json.
"""
import json
import os
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
CORRECTORS = ["simultaneous", "staggered", "staggered1"]

# name: (study, sensitivities in the order taken for Ns, {method: extra --set}, constrained)
SCENES = {
    "chain4_planar": ("configs/chain4_scaling_study.yaml", "m,L,c,j1.q0,j2.q0,j1.u0", {}, False),
    "arm_3d": ("configs/arm_3d_study.yaml", "m1,k_tele,wrist.q0[0],m2,c_tele,m3", {}, False),
    # Projection needs BDF: Adams on the four-bar runs with Baumgarte stabilisation.
    "four_bar_multipliers": ("configs/four_bar_study.yaml", "c,m2,r,b,m1,m3",
                             {"adams": ["solver.constraints.stabilization=baumgarte"]}, True),
    "rolling_disc": ("configs/rolling_disc_study.yaml", "m,r,base.u0[0],base.u0[4],base.u0[5],base.q0[4]", {}, True),
    # Two more scenes with projection, to see whether what the four-bar shows is projection's.
    "four_bar_embedding": ("configs/four_bar_study.yaml", "c,m2,r,b,m1,m3",
                           {"bdf": ["solver.constraints.formulation=embedding"],
                            "adams": ["solver.constraints.formulation=embedding", "solver.constraints.stabilization=none"]},
                           True),
    "slider_crank": ("configs/slider_crank_study.yaml", "l,ms,r,m1,m2,w",
                     {"adams": ["solver.constraints.stabilization=baumgarte"]}, True),
}
# Scenes and methods whose constraints are stabilised by projection (what sensitivity.method: auto
# looks at).
PROJECTION = {("four_bar_multipliers", "bdf"), ("four_bar_embedding", "bdf"), ("slider_crank", "bdf")}


def run(exe, study, method, sens, corrector, extra):
    args = [exe, "simulate", os.path.join(ROOT, study), "--set", f"solver.method={method}",
            "--set", f"solver.sensitivity.method={corrector}", "--sens", sens]
    for s in extra:
        args += ["--set", s]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0 and f"sensitivity.method = {corrector}:" in p.stderr:
        return None  # not offered for this configuration
    d = json.loads(p.stdout)
    if d["status"] != 1:
        raise RuntimeError(f"{' '.join(args)}: {d.get('message')}")
    return d


def flat(d):
    out = []

    def walk(x):
        if isinstance(x, list):
            for y in x:
                walk(y)
        elif x is not None:
            out.append(float(x))
    walk(d["sensitivities"])
    return out


def measure(out, exe, runs, scenes, methods, counts, correctors, controls):
    load_start = common.loadavg()
    result = {"command": "/usr/bin/python3 bench/sensitivity_corrector.py " + " ".join(sys.argv[1:]),
              "runs": runs, "correctors": correctors, "rows": []}
    for name in scenes:
        study, all_sens, extras, constrained = SCENES[name]
        for method, ec, ns in [(m, e, k) for m in methods for e in controls for k in counts]:
            sens = ",".join(all_sens.split(",")[:ns])
            extra = extras.get(method, []) + [f"solver.sensitivity.error_control={ec}"]
            times = {c: [] for c in correctors}
            last = {}
            for _ in range(runs):
                for c in correctors:
                    d = run(exe, study, method, sens, c, extra)
                    if d is None:
                        continue
                    times[c].append(d["stats"]["wall_seconds"])
                    last[c] = d
            ref = flat(last[correctors[0]])
            scale = max(abs(v) for v in ref)
            row = {"scene": name, "study": study, "method": method, "error_control": ec == "true",
                   "ns": ns, "sensitivities": sens, "max_abs_sensitivity": scale,
                   "constrained": constrained, "projection": (name, method) in PROJECTION, "set": extra,
                   "results": {}}
            for c in correctors:
                if c not in last:
                    continue
                s = flat(last[c])
                diff = max(abs(a - b) for a, b in zip(s, ref))
                row["results"][c] = {"wall_s": times[c], "stats": last[c]["stats"],
                                     "max_abs_diff": diff}
            result["rows"].append(row)
            print(name, method, ec, ns, " ".join(f"{c}={statistics.median(times[c]) * 1e3:.2f}ms"
                                             for c in correctors if times[c]), file=sys.stderr)
    result["meta"] = common.provenance(load_start)
    with open(out, "w") as f:
        json.dump(result, f, indent=1)


def table(path):
    with open(path) as f:
        r = json.load(f)
    cs = r["correctors"]
    print(f"Median of {r['runs']} interleaved runs (ms) and, in brackets, the ratio to `staggered`; "
          "steps; the largest difference of the sensitivities from `simultaneous`'s and the largest "
          "|sensitivity|.\n")
    print("| scene | method | error control | Ns | " + " | ".join(cs) + " | fastest | steps " + " / ".join(cs) +
          " | max diff | max abs |")
    print("|---|---|---|---:|" + "---:|" * len(cs) + "---|---:|---:|---:|")
    for row in r["rows"]:
        res = row["results"]
        med = {c: statistics.median(res[c]["wall_s"]) for c in cs if c in res}
        base = med.get("staggered", med[cs[0]])
        cells = [f"{med[c] * 1e3:.2f} ({med[c] / base:.2f})" if c in med else "—" for c in cs]
        steps = " / ".join(str(res[c]["stats"]["steps"]) if c in res else "—" for c in cs)
        diff = max(res[c]["max_abs_diff"] for c in med)
        ec = "on" if row["error_control"] else "off"
        print(f"| {row['scene']} | {row['method']} | {ec} | {row['ns']} | " + " | ".join(cells) +
              f" | {min(med, key=med.get)} | {steps} | {diff:.1e} | {row['max_abs_sensitivity']:.1e} |")


def grouped(path):
    """The run, its rows grouped by (scene, method, error control), and the Ns values in order."""
    with open(path) as f:
        r = json.load(f)
    groups, counts = {}, []
    for row in r["rows"]:
        groups.setdefault((row["scene"], row["method"], row["error_control"]), []).append(row)
        if row["ns"] not in counts:
            counts.append(row["ns"])
    return r, groups, counts


def per_ns(rows, counts, cell):
    """One cell per Ns of a group's rows: cell(row) gives (text, relative difference) or None (—);
    the cells and the largest difference."""
    cells, rel = [], 0.0
    for k in counts:
        row = next((x for x in rows if x["ns"] == k), None)
        got = cell(row) if row is not None else None
        cells.append(got[0] if got else "—")
        rel = max(rel, got[1] if got else 0.0)
    return cells, rel


def relative(row, results):
    """The largest of the results' differences from the first corrector's sensitivities, relative to
    the largest |sensitivity| (0 for a parameter whose sensitivities are round-off)."""
    if row["max_abs_sensitivity"] <= 1e-12:
        return 0.0
    return max(v["max_abs_diff"] for v in results) / row["max_abs_sensitivity"]


def header(lead, counts, tail, tail_align):
    """A summary table's header: the `lead` columns, one per Ns (right-aligned), the `tail` ones."""
    names = lead + [f"Ns = {k}" for k in counts] + tail
    print("| " + " | ".join(names) + " |")
    print("|" + "---|" * len(lead) + "---:|" * len(counts) + "".join(a + "|" for a in tail_align))


def stacked_summary(path):
    """stacked against the corrector of CVODES's module that auto takes where stacked does not apply
    (staggered with projection, simultaneous without): medians, ratio and steps per scene, method and
    error control, one column per Ns."""
    r, groups, counts = grouped(path)
    print(f"Median of {r['runs']} interleaved runs, one solve per process: `stacked` / the module's corrector "
          "(`staggered` with projection, `simultaneous` without) in ms (ratio) [steps]; the largest difference "
          "of either's sensitivities from `simultaneous`'s, relative to the largest |sensitivity|.\n")
    header(["scene", "method", "error control", "module"], counts, ["max rel. diff"], ["---:"])
    for (scene, method, ec), rows in groups.items():
        module = "staggered" if rows[0]["projection"] else "simultaneous"

        def cell(row):
            if "stacked" not in row["results"]:
                return None
            a, b = row["results"]["stacked"], row["results"][module]
            ta, tb = statistics.median(a["wall_s"]), statistics.median(b["wall_s"])
            return (f"{ta * 1e3:.1f} / {tb * 1e3:.1f} ({ta / tb:.2f}) [{a['stats']['steps']} / {b['stats']['steps']}]",
                    relative(row, [a, b]))
        cells, rel = per_ns(rows, counts, cell)
        print(f"| {scene} | {method} | {'on' if ec else 'off'} | {module} | " + " | ".join(cells) + f" | {rel:.0e} |")


def summary(path):
    """simultaneous against staggered: medians and their ratio per scene, method and error control, one
    column per Ns; which of the two sensitivity.method: auto picks there when stacked does not apply."""
    r, groups, counts = grouped(path)
    print(f"Median of {r['runs']} interleaved runs: `simultaneous` / `staggered` in ms (ratio); "
          "the largest difference between the correctors' sensitivities relative to the largest "
          "|sensitivity|.\n")
    header(["scene", "method", "error control"], counts, ["max rel. diff", "auto, where stacked does not apply"],
           ["---:", "---"])
    for (scene, method, ec), rows in groups.items():
        def cell(row):
            a = statistics.median(row["results"]["simultaneous"]["wall_s"])
            b = statistics.median(row["results"]["staggered"]["wall_s"])
            return f"{a * 1e3:.1f} / {b * 1e3:.1f} ({a / b:.2f})", relative(row, row["results"].values())
        cells, rel = per_ns(rows, counts, cell)
        print(f"| {scene} | {method} | {'on' if ec else 'off'} | " + " | ".join(cells) + f" | {rel:.0e} | "
              f"{'staggered' if rows[0]['projection'] else 'simultaneous'} |")


if __name__ == "__main__":
    argv = sys.argv[1:]
    if len(argv) == 2 and argv[0] in ("--table", "--summary", "--stacked"):
        {"--table": table, "--summary": summary, "--stacked": stacked_summary}[argv[0]](argv[1])
        sys.exit(0)
    if not argv:
        sys.exit(__doc__)
    exe, runs, scenes, methods, counts = os.path.join(ROOT, "build", "kanesens"), 5, list(SCENES), ["bdf", "adams"], [1, 2, 6]
    correctors, controls = CORRECTORS, ["true"]
    out = argv[0]
    i = 1
    while i < len(argv):
        key, val = argv[i], argv[i + 1]
        if key == "--exe":
            exe = val
        elif key == "--runs":
            runs = int(val)
        elif key == "--scenes":
            scenes = val.split(",")
        elif key == "--methods":
            methods = val.split(",")
        elif key == "--ns":
            counts = [int(k) for k in val.split(",")]
        elif key == "--error-control":
            controls = val.split(",")
        elif key == "--correctors":
            correctors = val.split(",")
        else:
            sys.exit(f"unknown option {key}")
        i += 2
    measure(out, exe, runs, scenes, methods, counts, correctors, controls)
    table(out)
