#!/usr/bin/python3
"""Instructions per evaluation of the right-hand side, binary against binary: callgrind counts of
`kanesens bench rhs SCENE --profile N` (inclusive Ir of each evaluation function / N). Counts do
not depend on the machine's load, so two builds compare exactly where wall times are noisy.

    /usr/bin/python3 bench/rhs_instructions.py OLD/kanesens,NEW/kanesens SCENE,SCENE,... N OUT.json

Needs valgrind (callgrind, callgrind_annotate). Raw counts of the layered-engine change (issue
"one layered engine"): bench/results/rhs_instructions_layers.json.
"""
import subprocess, sys, re, json, os, tempfile
bins = sys.argv[1].split(','); scenes = sys.argv[2].split(','); N = int(sys.argv[3])
pats = {
 "solve_accelerations<double>": r"solve_accelerations<double>",
 "solve_accelerations<Dual>": r"solve_accelerations<kanesens::(math::)?DualT<double> >",
 "solve_constrained<double>": r"solve_constrained_accelerations<double>",
 "solve_constrained<Dual>": r"solve_constrained_accelerations<kanesens::(math::)?DualT<double> >",
 "KaneProblem::rhs": r"KaneProblem::rhs",
 "embedded_rhs<double>": r"embedded_rhs<double>",
 "evaluate_rhs<double>": r"evaluate_rhs<double>",
 "evaluate_rhs<Dual>": r"evaluate_rhs<kanesens::(math::)?DualT<double> >",
 # The stages of evaluate_rhs<double>; position to forcing also run in the N
 # evaluate_mass_matrix_and_forcing calls of the N-set, so their counts are of 2N calls.
 "compute_position<double>": r"compute_position<double>",
 "compute_velocity<double>": r"compute_velocity<double>",
 "compute_mass_matrix<double>": r"compute_mass_matrix<double>",
 "compute_forcing<double>": r"compute_forcing<double>",
}
res = {}
for sc in scenes:
    for b in bins:
        f = tempfile.mktemp(suffix=".cg")
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={f}", b, "bench", "rhs", sc, "--profile", str(N)],
                       capture_output=True, check=True)
        ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", f], capture_output=True, text=True).stdout
        os.remove(f)
        tot = int(re.search(r"([\d,]+) \(100.0%\)\s+PROGRAM TOTALS", ann).group(1).replace(",", ""))
        row = {"total": tot / N}
        for k, p in pats.items():
            for line in ann.splitlines():
                m = re.match(r"\s*([\d,]+) \([^)]*\)\s+\S*:(.*)$", line)
                if m and re.search(r"kanesens::(\w+::)?" + p + r"\(", m.group(2)):
                    row[k] = int(m.group(1).replace(",", "")) / N
                    break
        res[(sc, b)] = row
keys = ["total"] + list(pats)
print(f"{'scene':24s} {'Ir per N-set':28s} " + " ".join(f"{b.split('/')[-1]:>16s}" for b in bins) + "  ratio")
for sc in scenes:
    for k in keys:
        v = [res[(sc, b)].get(k) for b in bins]
        if any(x is None for x in v): continue
        print(f"{sc.split('/')[-1]:24s} {k:28s} " + " ".join(f"{x:16.0f}" for x in v) + f"  {v[-1]/v[0]:.3f}")
json.dump({f"{sc}|{b}": res[(sc, b)] for (sc, b) in res}, open(sys.argv[4], "w"), indent=1)
