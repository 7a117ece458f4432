#!/usr/bin/python3
"""CVODES's sensitivity correctors side by side: `solver.sensitivity.method` simultaneous,
staggered and staggered1 on the same study, with BDF and Adams and Ns sensitivities.

  sensitivity_corrector.py OUT.json [--exe build/kanesens] [--runs K] [--scenes a,b] [--methods m,n]
                           [--ns 1,2,6] [--correctors simultaneous,staggered,staggered1]
                           [--error-control true,false]
  sensitivity_corrector.py --table OUT.json      # every configuration
  sensitivity_corrector.py --summary OUT.json    # the default against the former default

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
                    times[c].append(d["stats"]["wall_seconds"])
                    last[c] = d
            ref = flat(last[correctors[0]])
            scale = max(abs(v) for v in ref)
            row = {"scene": name, "study": study, "method": method, "error_control": ec == "true",
                   "ns": ns, "sensitivities": sens, "max_abs_sensitivity": scale,
                   "constrained": constrained, "projection": (name, method) in PROJECTION, "set": extra,
                   "results": {}}
            for c in correctors:
                s = flat(last[c])
                diff = max(abs(a - b) for a, b in zip(s, ref))
                row["results"][c] = {"wall_s": times[c], "stats": last[c]["stats"],
                                     "max_abs_diff": diff}
            result["rows"].append(row)
            print(name, method, ec, ns, " ".join(f"{c}={statistics.median(times[c]) * 1e3:.2f}ms"
                                             for c in correctors), file=sys.stderr)
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
        med = {c: statistics.median(row["results"][c]["wall_s"]) for c in cs}
        base = med.get("staggered", med[cs[0]])
        cells = [f"{med[c] * 1e3:.2f} ({med[c] / base:.2f})" for c in cs]
        steps = " / ".join(str(row["results"][c]["stats"]["steps"]) for c in cs)
        diff = max(row["results"][c]["max_abs_diff"] for c in cs)
        ec = "on" if row["error_control"] else "off"
        print(f"| {row['scene']} | {row['method']} | {ec} | {row['ns']} | " + " | ".join(cells) +
              f" | {min(cs, key=med.get)} | {steps} | {diff:.1e} | {row['max_abs_sensitivity']:.1e} |")


def summary(path):
    """simultaneous against staggered (the former default): medians and their ratio per scene, method
    and error control, one column per Ns; what sensitivity.method: auto picks there."""
    with open(path) as f:
        r = json.load(f)
    groups, counts, auto = {}, [], {}
    for row in r["rows"]:
        groups.setdefault((row["scene"], row["method"], row["error_control"]), []).append(row)
        auto[(row["scene"], row["method"], row["error_control"])] = "staggered" if row["projection"] else "simultaneous"
        if row["ns"] not in counts:
            counts.append(row["ns"])
    print(f"Median of {r['runs']} interleaved runs: `simultaneous` / `staggered` in ms (ratio); "
          "the largest difference between the correctors' sensitivities relative to the largest "
          "|sensitivity|.\n")
    print("| scene | method | error control | " + " | ".join(f"Ns = {k}" for k in counts) + " | max rel. diff | auto |")
    print("|---|---|---|" + "---:|" * len(counts) + "---:|---|")
    for (scene, method, ec), rows in groups.items():
        cells, rel = [], 0.0
        for k in counts:
            row = next((x for x in rows if x["ns"] == k), None)
            if row is None:
                cells.append("—")
                continue
            a = statistics.median(row["results"]["simultaneous"]["wall_s"])
            b = statistics.median(row["results"]["staggered"]["wall_s"])
            cells.append(f"{a * 1e3:.1f} / {b * 1e3:.1f} ({a / b:.2f})")
            if row["max_abs_sensitivity"] > 1e-12:
                rel = max(rel, max(v["max_abs_diff"] for v in row["results"].values()) / row["max_abs_sensitivity"])
        print(f"| {scene} | {method} | {'on' if ec else 'off'} | " + " | ".join(cells) + f" | {rel:.0e} | "
              f"{auto[(scene, method, ec)]} |")


if __name__ == "__main__":
    argv = sys.argv[1:]
    if len(argv) == 2 and argv[0] in ("--table", "--summary"):
        (table if argv[0] == "--table" else summary)(argv[1])
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
