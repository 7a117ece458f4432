#!/usr/bin/python3
"""Cost of forward sensitivities: `kanesens simulate` with and without Ns sensitivities.

  sensitivity_cost.py OUT.json LABEL=EXE [LABEL=EXE ...] [--runs K] [--scenes a,b] [--methods m,n]
                      [--ns 1,2,6] [--repeat R]
  sensitivity_cost.py --table OUT.json

--ns: the first Ns of each scene's sensitivities, for each Ns given (default: all of them).
--repeat R (R ≥ 2): each run integrates R times in one process (`simulate --repeat R`) and its
time is the median of the repeats after the first: the steady cost of a sample on an ensemble
rank, without the first solve's one-time cost of touching code and memory (which inflates a
short plain solve far more than one with sensitivities). Without it, one solve per process.

For every scene, method and executable: K runs of the plain solve and K runs with the Ns
sensitivities, all interleaved (plain, sens, next executable, ...) so that machine load hits
every configuration alike; the figure per configuration is the minimum and the median of
stats.wall_seconds (the integration itself). Cost per added sensitivity =
(t_sens − t_plain) / (Ns · t_plain), from the minima. Raw times go to OUT.json, with each
configuration's solver statistics; `evaluations` splits DOP853's figure into evaluation counts
and the cost of one evaluation (bench/make_tables.py: sensitivity_cost_evaluations).
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

from common import chain_scene_yaml, load_json, provenance, table_or_usage

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))

# name: (study text, sensitivities, methods)
SCENES = {
    "chain4_planar": ("""kanesens: 1
scene: {root}/configs/nlink_chain_4.yaml
time: {{end: 2.0, outputs: 21}}
solver: {{rtol: 1.0e-8, atol: 1.0e-10}}
""", "m,L,c,j1.q0,j2.q0,j1.u0", ["bdf", "dop853"]),
    "arm_3d": ("""kanesens: 1
scene: {root}/configs/arm_3d.yaml
time: {{end: 5.0, outputs: 51}}
solver: {{rtol: 1.0e-8, atol: 1.0e-10}}
""", "m1,m2,m3,k_tele,c_tele,wrist.q0[0]", ["bdf", "dop853"]),
    "four_bar_multipliers": ("""kanesens: 1
scene: {root}/configs/four_bar.yaml
time: {{end: 3.0, outputs: 31}}
solver: {{rtol: 1.0e-8, atol: 1.0e-10,
         constraints: {{formulation: multipliers, stabilization: projection, correct_initial: true}}}}
""", "r,c,b,m1,m2,m3", ["bdf", "dop853"]),
    "four_bar_embedding": ("""kanesens: 1
scene: {root}/configs/four_bar.yaml
time: {{end: 3.0, outputs: 31}}
solver: {{rtol: 1.0e-8, atol: 1.0e-10,
         constraints: {{formulation: embedding, stabilization: projection, correct_initial: true}}}}
""", "r,c,b,m1,m2,m3", ["bdf", "dop853"]),
    "rolling_disc": ("""kanesens: 1
scene: {root}/configs/rolling_disc.yaml
time: {{end: 2.0, outputs: 21}}
solver: {{rtol: 1.0e-9, atol: 1.0e-11, constraints: {{formulation: multipliers, stabilization: baumgarte}}}}
""", "m,r,base.u0[0],base.u0[4],base.u0[5],base.q0[4]", ["bdf", "dop853"]),
    "chain16_planar": ("""kanesens: 1
scene: {root}/bench/configs/nlink_chain_16.yaml
time: {{end: 2.0, outputs: 21}}
solver: {{rtol: 1.0e-8, atol: 1.0e-10}}
""", "m,L,j1.q0,j2.q0,j1.u0,j3.q0", ["bdf", "dop853"]),
    "andrews": ("""kanesens: 1
scene: {root}/configs/andrews.yaml
time: {{end: 0.03, outputs: 31}}
solver: {{rtol: 1.0e-8, atol: 1.0e-10,
         constraints: {{formulation: multipliers, stabilization: projection, correct_initial: true}}}}
""", "mom,c0,m1,m3,I1,d", ["bdf", "dop853"]),
    "chain8_spatial": ("""kanesens: 1
scene: {tmp}/chain8_spatial_scene.yaml
time: {{end: 2.0, outputs: 21}}
solver: {{rtol: 1.0e-8, atol: 1.0e-10}}
""", "m,L,j1.q0,j2.q0,j3.u0,j4.q0", ["bdf", "dop853"]),
}

# Scenes made by the driver (written beside the studies): 8 links about alternating z and x
# axes, released from 0.5 rad at the first joint (at rest it would hang still); and the rolling
# disc with base.u0[5] = -0.3 instead of its steady turn's -0.4992: its lean wobbles, so the plain
# solve no longer follows a steady motion that its sensitivities do not share (its study is the
# steady disc's, on that scene).
def wobbling_disc_yaml():
    with open(os.path.join(ROOT, "configs", "rolling_disc.yaml")) as f:
        text = f.read()
    steady = "-0.49923771269461059]"
    if steady not in text:
        raise RuntimeError("configs/rolling_disc.yaml: its steady turn's u0[5] is not " + steady[:-1])
    return text.replace(steady, "-0.3]")


GENERATED = {"chain8_spatial_scene.yaml":
             lambda: chain_scene_yaml(8, axes="z,x").replace("{name: j1, type: revolute,", "{name: j1, q0: 0.5, type: revolute,"),
             "rolling_disc_wobbling_scene.yaml": wobbling_disc_yaml}
_steady_study, *_steady_rest = SCENES["rolling_disc"]
SCENES["rolling_disc_wobbling"] = (_steady_study.replace("{root}/configs/rolling_disc.yaml",
                                                         "{tmp}/rolling_disc_wobbling_scene.yaml"), *_steady_rest)


def studies(tmp, names):
    """Writes the generated scenes and each named scene's study into tmp; yields (name, study
    file, its sensitivities, its methods)."""
    for file, make in GENERATED.items():
        with open(os.path.join(tmp, file), "w") as f:
            f.write(make())
    for name in names:
        text, sens, methods = SCENES[name]
        study = os.path.join(tmp, name + ".yaml")
        with open(study, "w") as f:
            f.write(text.format(root=ROOT, tmp=tmp))
        yield name, study, sens, methods


def run(exe, study, method, sens, extra, repeat=1):
    args = [exe, "simulate", study, "--set", f"solver.method={method}", "--sens", sens] + extra
    if repeat > 1:
        args += ["--repeat", str(repeat)]
    p = subprocess.run(args, capture_output=True, text=True)
    d = json.loads(p.stdout)
    if d["status"] != 1:
        raise RuntimeError(f"{exe} {method} {sens}: {d.get('message')}")
    if repeat > 1:
        return statistics.median(d["stats"]["wall_seconds_repeats"][1:]), d["stats"]
    return d["stats"]["wall_seconds"], d["stats"]


def instruction_set(exe):
    """The `instruction set` line of `EXE --version`: the figures depend on the vector width the
    build uses (the tangents of a multi-tangent pass travel in SIMD packs)."""
    out = subprocess.run([exe, "--version"], capture_output=True, text=True).stdout
    return next((line.split("instruction set", 1)[1].strip() for line in out.splitlines() if "instruction set" in line), "?")


def measure(out, exes, runs, scenes, extra, methods_only=None, counts=None, repeat=1):
    result = {"command": "/usr/bin/python3 bench/sensitivity_cost.py " + " ".join(sys.argv[1:]), "runs": runs,
              "repeat": repeat, "machine": provenance(), "builds": {label: instruction_set(exe) for label, exe in exes},
              "rows": []}
    with tempfile.TemporaryDirectory() as tmp:
        for name, study, all_sens, methods in studies(tmp, scenes):
            for method, ns in [(m, k) for m in methods if not methods_only or m in methods_only
                               for k in (counts or [len(all_sens.split(","))])]:
                sens = ",".join(all_sens.split(",")[:ns])
                times = {label: {"plain": [], "sens": []} for label, _ in exes}
                stats = {}
                for _ in range(runs):
                    for label, exe in exes:
                        for kind, s in (("plain", "none"), ("sens", sens)):
                            w, st = run(exe, study, method, s, extra, repeat)
                            times[label][kind].append(w)
                            stats[(label, kind)] = st
                for label, _ in exes:
                    row = {"scene": name, "method": method, "exe": label, "ns": len(sens.split(",")),
                           "sensitivities": sens, "plain_s": times[label]["plain"], "sens_s": times[label]["sens"],
                           "stats_plain": stats[(label, "plain")], "stats_sens": stats[(label, "sens")]}
                    result["rows"].append(row)
                    print(name, method, label, row["ns"], f"{min(row['plain_s'])*1e3:.2f} ms",
                          f"{per_added(row):.2f}", file=sys.stderr)
    with open(out, "w") as f:
        json.dump(result, f, indent=1)


def per_added(row, pick=min):
    tp, ts = pick(row["plain_s"]), pick(row["sens_s"])
    return (ts - tp) / (row["ns"] * tp)


def table(path):
    r = load_json(path)
    steady = (f", each the median of {r['repeat'] - 1} repeated solves after the first in one process"
              if r.get("repeat", 1) > 1 else "")
    machine = r.get("machine")
    where = (f" On {machine['cpu']} ({machine['nproc']} cores), "
             + ", ".join(f"{label}: {isa}" for label, isa in r["builds"].items()) + "." if machine else "")
    print(f"Minimum (median) of {r['runs']} interleaved runs{steady}; per added sensitivity = "
          f"(t_sens − t_plain) / (Ns · t_plain).{where}\n")
    print("| scene | method | build | Ns | plain solve (ms) | with Ns sensitivities (ms) | per added sensitivity | steps plain / sens |")
    print("|---|---|---|---:|---:|---:|---:|---:|")
    for row in r["rows"]:
        tp, ts = row["plain_s"], row["sens_s"]
        print(f"| {row['scene']} | {row['method']} | {row['exe']} | {row['ns']} | {min(tp)*1e3:.2f} ({statistics.median(tp)*1e3:.2f}) | "
              f"{min(ts)*1e3:.2f} ({statistics.median(ts)*1e3:.2f}) | {per_added(row):.2f}x ({per_added(row, statistics.median):.2f}x) | "
              f"{row['stats_plain']['steps']} / {row['stats_sens']['steps']} |")


def evaluations(path, target=0.4):
    """DOP853's figure split in two: per added sensitivity = (e_s/e_p · c − 1) / Ns, with e_p and
    e_s the right-hand-side evaluations of the plain and the sensitivity solve (more of the latter
    where the sensitivities' error test adds steps) and c the time of one evaluation with the Ns
    tangents (stepper work included) over that of one plain evaluation. The last column is the c
    that would give `target` at these evaluation counts."""
    r = load_json(path)
    print(f"The DOP853 rows of that run (minimum times); per added sensitivity = (e_s/e_p · c − 1) / Ns; "
          f"c for {target}× = (1 + {target} Ns) e_p / e_s.\n")
    print("| scene | build | evaluations plain / sens | µs per evaluation, plain / with Ns tangents | c | "
          f"per added sensitivity | c for {target}× |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for row in r["rows"]:
        if row["method"] != "dop853":
            continue
        ep, es = row["stats_plain"]["rhs_evals"], row["stats_sens"]["rhs_evals"]
        tp, ts = min(row["plain_s"]) / ep, min(row["sens_s"]) / es
        c, ns = ts / tp, row["ns"]
        print(f"| {row['scene']} | {row['exe']} | {ep} / {es} | {tp*1e6:.3f} / {ts*1e6:.3f} | {c:.2f} | "
              f"{per_added(row):.2f}x | {(1 + target * ns) * ep / es:.2f} |")


if __name__ == "__main__":
    argv = sys.argv[1:]
    table_or_usage(argv, table, __doc__)
    runs, scenes, extra, methods, counts, repeat = 7, list(SCENES), [], None, None, 1
    out, rest = argv[0], []
    i = 1
    while i < len(argv):
        if argv[i] == "--runs":
            runs = int(argv[i + 1]); i += 2
        elif argv[i] == "--scenes":
            scenes = argv[i + 1].split(","); i += 2
        elif argv[i] == "--methods":
            methods = argv[i + 1].split(","); i += 2
        elif argv[i] == "--ns":
            counts = [int(k) for k in argv[i + 1].split(",")]; i += 2
        elif argv[i] == "--repeat":
            repeat = int(argv[i + 1]); i += 2
        elif argv[i] == "--set":
            extra += ["--set", argv[i + 1]]; i += 2
        else:
            rest.append(argv[i]); i += 1
    exes = [tuple(a.split("=", 1)) for a in rest]
    measure(out, exes, runs, scenes, extra, methods, counts, repeat)
    table(out)
