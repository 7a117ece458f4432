"""The reference pages (docs/reference/) against the code, so the docs cannot fall behind it.

* scene.md names every key and every choice the scene parser accepts, study.md every key and
  choice the study parser accepts: both lists are read from the parsers' own sources (the
  allowed-key lists behind the "unknown key" errors, and the name tables of read_choice).
* cli.md names every subcommand and every option of `kanesens --help` and of each
  subcommand's --help; python.md every subcommand and option of `kanesens-post`.
* hdf5.md names every dataset, group and attribute of a run file written by `kanesens run` with
  everything recorded (states, sensitivities, multipliers, outputs, events, poses, a design),
  with the dimensions each dataset has.
* exit-codes.md lists every exit code the command line returns and every sample status the
  ensemble writes.

And the other way round: every option cli.md and python.md name (and every option of a
`kanesens ...` or `kanesens-post ...` command line on the README, getting-started and tutorial
pages) exists; every key of the JSON that eom, linearize, simulate and run print is named in its
command's section of cli.md; and the defaults study.md states for `solver:` and `sampling:` are
the ones the option structs start with.
"""
import os
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(os.environ.get("KANESENS_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
REF = ROOT / "docs" / "reference"
KANESENS = os.environ.get("KANESENS")

IDENT = re.compile(r'"([a-z][a-z0-9_]*)"')


def accepted_names(sources):
    """Keys of every check_keys(...{...}) list, key tables, and the names of read_choice /
    kind tables ({"name", Enum::value}) in the given C++ sources."""
    names = set()
    for src in sources:
        text = src.read_text(encoding="utf-8")
        for lst in re.findall(r"check_keys\([^;]*?\{([^}]*)\}", text, re.S):
            names |= set(IDENT.findall(lst))
        names |= set(re.findall(r'\{"([a-z][a-z0-9_]*)",\s*[A-Z]\w*::', text))
        # read_choice tables of other namespaces' enums, numbers or booleans ({"rising", 1})
        names |= set(re.findall(r'\{"([a-z][a-z0-9_]*)",\s*(?:-?\d+|true|false|(?:\w+::)+\w+)\}', text))
        # key tables: parse_sampling's keys_of, parse_vary's distribution table
        for lst in re.findall(r"keys(?:\s*=|\.push_back\(|\.insert\([^{]*)\s*\{?([^;]*);", text):
            names |= set(IDENT.findall(lst))
        for lst in re.findall(r'\{"[a-z]+",\s*\{([^}]*)\}\}', text):
            names |= set(IDENT.findall(lst))
        names |= set(re.findall(r'\{"([a-z]+)",\s*\{"dist"', text))
        names |= set(re.findall(r'shape == "([a-z]+)"', text))
        for lst in re.findall(r"_methods\s*=\s*\{([^}]*)\}", text):
            names |= set(IDENT.findall(lst))
    return names


def documented(page_text, name):
    """`name` appears as code (`...name...`) or as a YAML key (name:) on the page."""
    fenced = re.findall(r"```.*?```", page_text, re.S)
    prose = re.sub(r"```.*?```", "", page_text, flags=re.S)
    for code in re.findall(r"`([^`]+)`", prose):  # a code span may wrap onto the next line
        if re.search(rf"(?<![\w]){re.escape(name)}(?![\w])", code):
            return True
    if re.search(rf"(?<![\w]){re.escape(name)}:", page_text):
        return True
    # inside fenced/indented code blocks
    blocks = "\n".join(fenced)
    blocks += "\n".join(l for l in page_text.splitlines() if l.startswith("    "))
    return re.search(rf"(?<![\w]){re.escape(name)}(?![\w])", blocks) is not None


def missing(page, names):
    text = (REF / page).read_text(encoding="utf-8")
    return sorted(n for n in names if not documented(text, n))


def test_documented_is_strict():
    page = "Keys: `alpha, beta`.\n\n```yaml\ngamma: 1\n```\nThe delta key, epsilon: 2\n"
    assert documented(page, "alpha") and documented(page, "beta") and documented(page, "gamma")
    assert documented(page, "epsilon") and not documented(page, "delta")
    assert not documented(page, "alph")


def test_scene_reference_names_every_scene_key():
    names = accepted_names(sorted((ROOT / "src/model/scene").glob("*.[ch]pp")))
    assert {"bodies", "joints", "parent_point", "spring", "revolute", "rolling", "coupler"} <= names
    assert missing("scene.md", names) == []


def test_study_reference_names_every_study_key():
    # The solver's enum names are in the tables both the parser and the printer read.
    names = accepted_names(sorted((ROOT / "src/study").glob("parse_*.cpp")) + [ROOT / "src/sim/solve/solver_options.hpp"])
    assert {"time", "solver", "rtol", "saltelli", "truncnormal", "mu", "trajectories",
            "constraint_force", "poses", "max_count", "argmax", "kinetic", "rising", "stop"} <= names
    assert missing("study.md", names) == []


def help_text(*args):
    r = subprocess.run(args, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    return r.stdout


def options(help_out):
    return set(re.findall(r"(?<![\w-])(--[a-z][a-z0-9-]*)", help_out))


def subcommands(help_out):
    m = re.search(r"^Subcommands:\n(.*?)(?:\n\s*\n|\Z)", help_out, re.S | re.M | re.I)
    assert m, help_out
    return [l.split()[0] for l in m.group(1).splitlines() if l.strip()]


@pytest.mark.skipif(not KANESENS, reason="needs the kanesens executable (KANESENS)")
def test_cli_reference_names_every_subcommand_and_option():
    text = (REF / "cli.md").read_text(encoding="utf-8")
    top = help_text(KANESENS, "--help")
    subs = subcommands(top)
    assert {"check", "eom", "simulate", "run"} <= set(subs)
    bad = [f"option {o}" for o in options(top) if o != "--help" and o not in text]
    for sub in subs:
        if not re.search(rf"^#+ .*`{sub}\b", text, re.M) and f"kanesens {sub}" not in text:
            bad.append(f"subcommand {sub}")
        h = help_text(KANESENS, sub, "--help")
        nested = subcommands(h) if re.search(r"^Subcommands:", h, re.M | re.I) else []
        for nest in nested:
            if f"{sub} {nest}" not in text:
                bad.append(f"subcommand {sub} {nest}")
            h += help_text(KANESENS, sub, nest, "--help")
        bad += [f"{sub} {o}" for o in sorted(options(h)) if o != "--help" and o not in text]
    assert bad == [], "not in docs/reference/cli.md: " + ", ".join(bad)


def test_python_reference_names_every_kanesens_post_subcommand_and_option():
    text = (REF / "python.md").read_text(encoding="utf-8")
    post = [sys.executable, "-m", "kanesens_post"]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "python"))
    top = subprocess.run(post + ["--help"], capture_output=True, text=True, env=env, timeout=60)
    assert top.returncode == 0, top.stderr
    subs = re.search(r"\{([a-z,-]+)\}", top.stdout).group(1).split(",")
    assert {"summary", "sobol", "draw", "animate"} <= set(subs)
    bad = []
    for sub in subs:
        if f"kanesens-post {sub}" not in text:
            bad.append(f"subcommand {sub}")
        h = subprocess.run(post + [sub, "--help"], capture_output=True, text=True, env=env, timeout=60)
        assert h.returncode == 0, h.stderr
        bad += [f"{sub} {o}" for o in sorted(options(h.stdout)) if o != "--help" and o not in text]
    assert bad == [], "not in docs/reference/python.md: " + ", ".join(bad)


def test_python_reference_names_every_public_function():
    """Every analysis entry point and io reader of the package appears in python.md."""
    import ast
    text = (REF / "python.md").read_text(encoding="utf-8")
    wanted = {"io": {"open_run", "response", "sensitivities", "output_names", "design"},
              "summary": {"summarize", "output_statistics"}, "sobol": {"analyze"}, "morris": {"analyze"},
              "dgsm": {"analyze"}, "linear_uq": {"analyze"}, "plot": {"plot"}, "geometry": {"scene_geometry"}}
    bad = []
    for module, functions in wanted.items():
        tree = ast.parse((ROOT / "python/kanesens_post" / f"{module}.py").read_text(encoding="utf-8"))
        defined = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
        for f in functions:
            if f not in defined:
                bad.append(f"{module}.{f} is no longer defined")
                continue
            if f"kanesens_post.{module}.{f}(" not in text:
                bad.append(f"kanesens_post.{module}.{f} not in python.md")
            # every parameter named in the signature is the one documented
            args = [a.arg for a in defined[f].args.args]
            m = re.search(rf"`kanesens_post\.{module}\.{f}\(([^`]*)\)`", text)
            if m:
                # the documented signature, read as Python: its names exist, its defaults are the code's
                shown = ast.parse(f"def f({m.group(1)}): pass").body[0].args
                bad += [f"{module}.{f}: no parameter '{a.arg}'" for a in shown.args if a.arg not in args]
                fa = defined[f].args
                code = dict(zip([a.arg for a in fa.args][len(fa.args) - len(fa.defaults):],
                                [ast.unparse(d) for d in fa.defaults]))
                doc = dict(zip([a.arg for a in shown.args][len(shown.args) - len(shown.defaults):],
                               [ast.unparse(d) for d in shown.defaults]))
                bad += [f"{module}.{f}: {a}={v} documented, {code.get(a)} in the code"
                        for a, v in doc.items() if a in args and code.get(a) != v]
    assert bad == []


STUDY = """\
kanesens: 1
scene: {scene}
time: {{end: 0.2, outputs: 5}}
solver: {{rtol: 1.0e-6, atol: 1.0e-8}}
sampling: {{method: saltelli, samples: 2, seed: 1}}
vary:
  c: {{dist: uniform, low: 0.65, high: 0.75}}
  m2: {{dist: normal, mean: 2.0, std: 0.01}}
sensitivities: [m2]
record: [states, sensitivities, multipliers, energy, constraint_residual, poses]
outputs:
  tip: {{type: position, body: coupler, point: [0, 0, 0]}}
  tip_end: {{of: tip.x, at: end}}
  f: {{type: constraint_force, constraint: {constraint}}}
events:
  - {{name: half, when: "crank.q - 2"}}
"""


def h5_names(path):
    import h5py
    datasets, groups, attributes = set(), set(), set()
    with h5py.File(path, "r") as f:
        attributes |= set(f.attrs)

        def visit(name, obj):
            (groups if isinstance(obj, h5py.Group) else datasets).add("/" + name)
            attributes.update(a for a in obj.attrs if not a.isupper() and not a.startswith("_")
                              and a not in {"CLASS", "NAME", "REFERENCE_LIST", "DIMENSION_LIST"})
        f.visititems(visit)
    return datasets, groups, attributes


@pytest.mark.skipif(not KANESENS, reason="needs the kanesens executable (KANESENS)")
def test_hdf5_reference_names_everything_a_run_writes(tmp_path):
    scene_text = (ROOT / "configs/four_bar.yaml").read_text(encoding="utf-8")
    for needed in ("m2:", "c:", "coupler"):
        assert needed in scene_text, f"configs/four_bar.yaml has no '{needed}'"
    constraint = re.search(r"constraints:\s*\n\s*-\s*\{?\s*name:\s*(\w+)", scene_text)
    assert constraint, "configs/four_bar.yaml: no named constraint"
    study = tmp_path / "study.yaml"
    study.write_text(STUDY.format(scene=ROOT / "configs/four_bar.yaml", constraint=constraint.group(1)))
    out = tmp_path / "run.h5"
    r = subprocess.run([KANESENS, "run", str(study), "-o", str(out)], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    datasets, groups, attributes = h5_names(out)
    text = (REF / "hdf5.md").read_text(encoding="utf-8")
    bad = []
    for d in sorted(datasets | groups):
        parts = d.strip("/").split("/")
        if parts[0] in {"outputs", "output_sensitivities", "vary"} and len(parts) > 1:
            # /outputs/<name>: the study's own names; the fixed ones must be listed
            if parts[1] in {"energy", "position_residual", "velocity_residual"} and parts[1] not in text:
                bad.append(d)
            if f"/{parts[0]}/" not in text:
                bad.append(d)
        elif parts[0] == "solver_stats" and len(parts) > 1:
            if parts[1] not in text:
                bad.append(d)
        elif f"/{parts[0]}" not in text:
            bad.append(d)
    bad += [f"attribute {a}" for a in sorted(attributes) if a not in text]
    assert {"/states", "/sensitivities", "/multipliers", "/poses", "/status"} <= datasets
    assert bad == [], "not in docs/reference/hdf5.md: " + ", ".join(bad)
    # and each dataset's dimensions are the documented ones
    documented_dims = hdf5_documented_dims(text)
    assert len(documented_dims) > 20, documented_dims
    wrong = []
    for d, dims in sorted(h5_dims(out).items()):
        if d.startswith("/solver_stats/"):
            if dims != ("sample",):
                wrong.append(f"{d} {dims}")
            continue
        if d.endswith("_name"):
            continue  # the plain copies of the names ("the same names as plain datasets")
        shapes = {s for pattern, s in documented_dims if re.fullmatch(pattern, d)}
        if dims not in shapes:
            wrong.append(f"{d} is {dims}, documented {sorted(shapes) or 'nowhere'}")
    assert wrong == [], "dimensions not as in docs/reference/hdf5.md:\n" + "\n".join(wrong)


def hdf5_documented_dims(text):
    """(path regex, dimension names) of every `/path (dim, dim)` entry of hdf5.md's listing
    (`<name>` stands for any name; several paths may share one entry)."""
    entries = []
    listing = re.search(r"^    dimension scales.*?(?=^\S)", text, re.S | re.M).group(0)
    for paths, dims in re.findall(r"((?:/[\w<>./]+,?[ \t]*)+)\(([a-z, ]+)\)", listing):
        for path in re.findall(r"/[\w<>./]+", paths):
            pattern = re.escape(path.rstrip(",")).replace(re.escape("<name>"), r"[^/]+")
            entries.append((pattern, tuple(x.strip() for x in dims.split(","))))
    return entries


def h5_dims(path):
    """Every dataset's dimension names: the names of the scales attached to its axes (a
    dimension scale's own dimension is itself)."""
    import h5py
    result = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                if h5py.h5ds.is_scale(obj.id):
                    result["/" + name] = (name.rsplit("/", 1)[-1],)
                else:
                    result["/" + name] = tuple(d[0].name.rsplit("/", 1)[-1] if len(d) else "?" for d in obj.dims)
        f.visititems(visit)
    return result


def table_codes(text, heading):
    section = text.split(heading, 1)[1].split("\n## ", 1)[0]
    codes = set()
    for row in re.findall(r"^\| ([^|]+) \|", section, re.M):
        for c in re.findall(r"[−-]?\d+", row):
            codes.add(int(c.replace("−", "-")))
    return codes


def test_exit_codes_reference_lists_every_code():
    text = (REF / "exit-codes.md").read_text(encoding="utf-8")
    exits = table_codes(text, "## Exit codes")
    returned = set()
    for src in (ROOT / "apps/kanesens").glob("*.cpp"):
        s = src.read_text(encoding="utf-8")
        returned |= {int(c) for c in re.findall(r"\breturn (\d+);", s)}
        returned |= {int(c) for c in re.findall(r"\? (\d+) : (?:\d+)", s)}
        if "128 + s.stop_signal" in s:
            returned |= {130, 143}  # SIGINT, SIGTERM
    assert {0, 1, 2, 4, 5} <= returned
    assert sorted(returned - exits) == []
    statuses = table_codes(text, "## `/status`")
    written = set()
    for src in (ROOT / "src").rglob("*.cpp"):
        written |= {int(c) for c in re.findall(r"constexpr int kStatus\w+ = (-?\d+);", src.read_text(encoding="utf-8"))}
    assert {-100, -101} <= written
    assert sorted(written - statuses) == []


# ---- the other direction: what the reference promises exists, with the defaults it states ----

def section(page_text, heading):
    """The text of the `## heading...` section of a page (up to the next `## `)."""
    m = re.search(rf"^## {re.escape(heading)}[^\n]*\n(.*?)(?=^## |\Z)", page_text, re.S | re.M)
    assert m, f"no section '## {heading}'"
    return m.group(1)


def all_help(*commands):
    return "".join(help_text(*c, "--help") for c in commands)


KANESENS_COMMANDS = [(), ("check",), ("eom",), ("linearize",), ("simulate",), ("run",), ("bench",), ("bench", "rhs")]
USER_PAGES = ["README.md", "docs/getting-started.md"] + [f"docs/tutorials/{p.name}" for p in
                                                         sorted((ROOT / "docs/tutorials").glob("*.md"))]


def documented_options(reference: str, command_line: str, exclude=frozenset()) -> dict:
    """Every --option the reference page names (but `exclude`), and every option on a command
    line matching `command_line` on the user pages, each with the page that names it."""
    named = {o: f"docs/reference/{reference}" for o in options((REF / reference).read_text(encoding="utf-8"))
             if o not in exclude}
    for page in USER_PAGES:
        text = (ROOT / page).read_text(encoding="utf-8").replace("\\\n", " ")
        for line in re.findall(command_line, text):
            named.update({o: page for o in options(line)})
    return named


@pytest.mark.skipif(not KANESENS, reason="needs the kanesens executable (KANESENS)")
def test_documented_kanesens_options_exist():
    """Every --option cli.md names, and every option of a `kanesens SUB ...` command line on the
    user pages, is one some `kanesens ... --help` lists."""
    existing = options(all_help(*[(KANESENS,) + c for c in KANESENS_COMMANDS]))
    assert {"--set", "--sens", "--chunk", "--batch-seconds"} <= existing
    named = documented_options("cli.md", r"(?<![\w-])kanesens (?:check|eom|linearize|simulate|run|bench)\b[^\n`]*")
    bad = sorted(f"{o} ({where})" for o, where in named.items() if o not in existing)
    assert bad == [], "documented but not an option of kanesens: " + ", ".join(bad)


def test_documented_kanesens_post_options_exist():
    post = [sys.executable, "-m", "kanesens_post"]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "python"))
    run = lambda *a: subprocess.run(post + list(a) + ["--help"], capture_output=True, text=True, env=env,
                                    timeout=60).stdout
    top = run()
    subs = re.search(r"\{([a-z,-]+)\}", top).group(1).split(",")
    existing = options(top + "".join(run(s) for s in subs))
    pip = {"--no-build-isolation", "--no-deps", "--no-index", "--system-site-packages", "--samples"}
    named = documented_options("python.md", r"kanesens-post [a-z-]+ [^\n`]*", exclude=pip)
    bad = sorted(f"{o} ({where})" for o, where in named.items() if o not in existing)
    assert bad == [], "documented but not an option of kanesens-post: " + ", ".join(bad)


def json_keys(value, prefix=""):
    """Every key of a JSON object and of the objects nested in it."""
    keys = set()
    if isinstance(value, dict):
        for k, v in value.items():
            keys.add(k)
            keys |= json_keys(v)
    return keys


@pytest.mark.skipif(not KANESENS, reason="needs the kanesens executable (KANESENS)")
def test_cli_reference_names_every_json_key(tmp_path):
    """The JSON of eom, linearize --json, simulate and run --json: each key is named in its
    command's section of cli.md (study outputs are the study's own names)."""
    import json
    cli = (REF / "cli.md").read_text(encoding="utf-8")
    scene = ROOT / "configs/four_bar.yaml"
    constraint = re.search(r"constraints:\s*\n\s*-\s*\{?\s*name:\s*(\w+)", scene.read_text(encoding="utf-8")).group(1)
    study = tmp_path / "study.yaml"
    study.write_text(STUDY.format(scene=scene, constraint=constraint))

    def run(*args):
        r = subprocess.run([KANESENS, *map(str, args)], capture_output=True, text=True, timeout=120)
        assert r.returncode == 0, r.stderr
        return json.loads(r.stdout)

    pend = ROOT / "configs/simple_pendulum.yaml"
    got = {"eom": json_keys(run("eom", pend, "--q=0.3", "--u=0.1")),
           "linearize": json_keys(run("linearize", pend, "--json")),
           "simulate": json_keys(run("simulate", study)),
           "run": json_keys(run("run", study, "-o", tmp_path / "r.h5", "--json"))}
    sim = run("simulate", study)
    study_names = set(sim["outputs"]) - {"energy"}
    assert {"stats", "output_sensitivities", "multiplier_sensitivities"} <= got["simulate"]
    assert {"repartitions", "sensitivity_method", "wall_seconds"} <= set(sim["stats"])
    bad = []
    for command, keys in got.items():
        text = section(cli, f"`{command}")
        bad += [f"{command}: {k}" for k in sorted(keys - study_names) if not documented(text, k)]
    assert bad == [], "JSON keys not in their section of docs/reference/cli.md: " + ", ".join(bad)


def header_default(path, pattern):
    m = re.search(pattern, (ROOT / path).read_text(encoding="utf-8"))
    assert m, f"{path}: no match for {pattern} (moved? update this test)"
    return m.group(1)


def test_study_reference_states_the_code_defaults():
    """The `default` column of study.md's solver table, and the sampling defaults in its prose,
    are the values the option structs start with."""
    solver, constraints = "src/sim/solve/solver_options.hpp", "src/sim/constraint_options.hpp"
    enum_word = {"automatic": "auto"}
    word = lambda s: enum_word.get(s, s)
    expected = {
        "method": word(header_default(solver, r"Method method = Method::(\w+);")),
        "iteration": word(header_default(solver, r"Iteration iteration = Iteration::(\w+);")),
        "rtol": header_default(solver, r"double rtol = ([\d.e+-]+);"),
        "atol": header_default(solver, r"double atol = ([\d.e+-]+);"),
        "max_steps": header_default(solver, r"long max_steps = (\d+);"),
        "max_order": header_default(solver, r"int max_order = (\d+);"),
        "jacobian": word(header_default(solver, r"JacobianKind jacobian = JacobianKind::(\w+);")),
        "linear_solver": word(header_default(solver, r"LinearSolver linear_solver = LinearSolver::(\w+);")),
        "sensitivity.method": word(header_default(solver, r"SensitivityMethod sensitivity_method = SensitivityMethod::(\w+);")),
        "sensitivity.error_control": header_default(solver, r"bool sens_error_control = (\w+);"),
        "sensitivity.rhs": word(header_default(solver, r"SensitivityRhs sens_rhs = SensitivityRhs::(\w+);")),
        "constraints.formulation": header_default(constraints, r"Formulation formulation = Formulation::(\w+);"),
        "constraints.stabilization": header_default(constraints, r"Stabilization stabilization = Stabilization::(\w+);"),
        "constraints.correct_initial": header_default(constraints, r"bool correct_initial = (\w+);"),
        "constraints.project_sensitivities": header_default(constraints, r"bool project_sensitivities = (\w+);"),
    }
    alpha, beta = (header_default(constraints, rf"{k} = ([\d.]+)") for k in (r"double alpha", r"beta"))
    text = (REF / "study.md").read_text(encoding="utf-8")
    rows = {}
    for key_cell, default in re.findall(r"^\| (`[^|]+`) \|[^\n]*\| ([^|\n]*) \|$", section(text, "`solver`"), re.M):
        for key in re.findall(r"`([a-z_.]+)`", key_cell):
            rows[key] = default.strip().strip("`")
    assert set(expected) <= set(rows), sorted(set(expected) - set(rows))
    same = lambda doc, code: doc == code or (re.fullmatch(r"[\d.e+-]+", code) and float(doc) == float(code))
    bad = [f"{k}: documented {rows[k]!r}, code {v!r}" for k, v in expected.items() if not same(rows[k], v)]
    ab = rows["constraints.alpha"].replace(" ", "").split(",")
    if [float(x) for x in ab] != [float(alpha), float(beta)]:
        bad.append(f"alpha, beta: documented {ab}, code {[alpha, beta]}")
    min_states = header_default(solver, r"kKrylovMinStates = (\d+);")
    max_rate = header_default(solver, r"kKrylovMaxRate = ([\d.e+-]+);")
    if not re.search(rf"krylov from {min_states} states unless the Jacobian's spectral radius exceeds {max_rate} /s", text):
        bad.append(f"linear_solver auto: not 'krylov from {min_states} states ... exceeds {max_rate} /s'")
    sampling = section(text, "`sampling`")
    spec = "src/study/sampling_spec.hpp"
    d = {name: header_default(spec, pattern) for name, pattern in (
        ("method", r"SamplingMethod method = SamplingMethod::(\w+);"), ("seed", r"std::uint64_t seed = (\d+);"),
        ("levels", r"morris_levels = (\d+);"), ("base", r"SamplingMethod base = SamplingMethod::(\w+);"),
        ("randomize", r"bool randomize = (\w+);"))}
    for claim, code in ((f"`method` \\(default `{d['method']}`\\)", "method"),
                        (f"`seed` \\(default {d['seed']}\\b", "seed"),
                        (f"default {d['levels']}\\)", "morris levels"),
                        (f"`base` \\(`{d['base']}` default", "base"),
                        (f"`randomize` \\(default {d['randomize']}", "randomize")):
        if not re.search(claim, sampling):
            bad.append(f"sampling {code}: the documented default is not the code's ({claim})")
    assert bad == [], "study.md defaults that are not the code's:\n" + "\n".join(bad)


def test_cmake_options_are_documented_and_exist():
    """Every option() of the top-level CMakeLists.txt (and KANESENS_PYTHON) is on the
    getting-started page, and every -DKANESENS_... the docs name exists."""
    cmake = (ROOT / "CMakeLists.txt").read_text(encoding="utf-8")
    defined = set(re.findall(r"option\((KANESENS_\w+)", cmake)) | set(re.findall(r"set\((KANESENS_\w+) [^)]*CACHE", cmake))
    assert {"KANESENS_WERROR", "KANESENS_BUILD_TESTS", "KANESENS_PYTHON"} <= defined
    getting_started = (ROOT / "docs/getting-started.md").read_text(encoding="utf-8")
    bad = [f"{o} not in docs/getting-started.md" for o in sorted(defined) if f"-D{o}" not in getting_started]
    for page in ["README.md"] + sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").rglob("*.md")):
        for o in set(re.findall(r"-D(KANESENS_\w+)", (ROOT / page).read_text(encoding="utf-8"))):
            if o not in defined:
                bad.append(f"{page}: -D{o} is not an option")
    assert bad == []


def test_scene_reference_names_every_expression_function():
    """The functions of scene.md's "Expressions" paragraph are the parser's, with their arity."""
    source = (ROOT / "src/model/expr/expression.cpp").read_text(encoding="utf-8")
    table = dict(re.findall(r'\{"([a-z0-9]+)",\s*\{Op::\w+,\s*(\d)\}\}', source))
    assert {"sin", "atan2", "max"} <= set(table), table
    text = (REF / "scene.md").read_text(encoding="utf-8")
    paragraph = re.search(r"^Expressions: .*?(?=\n\n)", text, re.S | re.M).group(0)
    listed = re.search(r"parentheses, `([^`]*)`", paragraph).group(1).split()
    shown = {re.sub(r"\(.*", "", f): f.count(",") + 1 if "(" in f else 1 for f in listed}
    assert shown == {name: int(arity) for name, arity in table.items()}
