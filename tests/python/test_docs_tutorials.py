"""The getting-started page and every tutorial run as written, so their commands cannot rot.

Convention in docs/getting-started.md and docs/tutorials/*.md: a fenced block marked ```bash is
a command a reader runs from the repository root, and this test runs it; a ```python block is
a script, run with /usr/bin/python3; blocks marked ```sh (installing packages, building, a real
cluster) or ```text are shown only, except that a ```text block right after a ```bash block
(nothing but blank lines between) is that command's output: each of its lines must be a line the
command printed (stdout or stderr), numbers equal to 1e-3 relative (1e-9 absolute: round-off
digits differ between machines), and a line ending in `...` only needs to begin the same. Blocks
run in page order in one scratch directory that holds the repository's configs/, scripts/ and
python/ (links), with `kanesens` and `kanesens-post` on PATH. On the Slurm tutorial `sbatch` and `srun` are stand-ins that run the batch script and
`mpirun` on this machine, so the batch script itself is what runs.
"""
import os
import pathlib
import re
import stat
import subprocess
import sys

import pytest

ROOT = pathlib.Path(os.environ.get("KANESENS_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
KANESENS = os.environ.get("KANESENS")
PAGES = [ROOT / "docs/getting-started.md"] + sorted((ROOT / "docs/tutorials").glob("*.md"))
PAGES = [p for p in PAGES if p.name != "README.md"]

BLOCK = re.compile(r"^```(\w+)[^\n]*\n(.*?)^```\s*$", re.S | re.M)


def blocks(page):
    return [(lang, body) for lang, body, _ in blocks_with_output(page)]


def blocks_with_output(page):
    """(lang, body, expected output or None) of every ```bash and ```python block."""
    text = page.read_text(encoding="utf-8")
    found = list(BLOCK.finditer(text))
    out = []
    for m, after in zip(found, found[1:] + [None]):
        if m.group(1) not in ("bash", "python"):
            continue
        shown = None
        if (m.group(1) == "bash" and after is not None and after.group(1) == "text"
                and text[m.end():after.start()].strip() == ""):
            shown = after.group(2)
        out.append((m.group(1), m.group(2), shown))
    return out


def _same_token(want, got):
    if want == got:
        return True
    a, b = want.strip("[](),;"), got.strip("[](),;")
    if want.replace(a, "") != got.replace(b, ""):  # the same brackets and commas around
        return False
    try:
        x, y = float(a), float(b)
    except ValueError:
        return False
    return abs(x - y) <= max(1e-9, 1e-3 * abs(x))


def line_shown(want, printed):
    """`want` (a line of a ```text block) is one of the `printed` lines, as the module docstring says."""
    want = want.strip()
    prefix = want.endswith("...")
    w = want[:-3].split() if prefix else want.split()
    for line in printed:
        g = line.split()
        if prefix:
            if len(g) >= len(w) and all(_same_token(a, b) for a, b in zip(w[:-1], g)) and \
                    (not w or g[len(w) - 1].startswith(w[-1])):
                return True
        elif len(g) == len(w) and all(_same_token(a, b) for a, b in zip(w, g)):
            return True
    return False


def write_exe(path, text):
    path.write_text(text)
    path.chmod(path.stat().st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)


def scratch(tmp_path):
    for d in ("configs", "scripts", "python"):
        (tmp_path / d).symlink_to(ROOT / d)
    bin_dir = tmp_path / ".bin"
    bin_dir.mkdir()
    (bin_dir / "kanesens").symlink_to(KANESENS)
    write_exe(bin_dir / "kanesens-post",
              f'#!/bin/sh\nPYTHONPATH="{ROOT / "python"}" exec /usr/bin/python3 -m kanesens_post "$@"\n')
    # Slurm stand-ins: sbatch runs the script with SLURM_NTASKS from --ntasks; srun runs mpirun.
    write_exe(bin_dir / "sbatch", """#!/usr/bin/env bash
set -e
n=2; args=()
for a in "$@"; do case $a in --ntasks=*) n=${a#--ntasks=};; --*) ;; *) args+=("$a");; esac; done
SLURM_NTASKS=$n SLURM_JOB_ID=1 exec bash "${args[@]}"
""")
    write_exe(bin_dir / "srun", """#!/usr/bin/env bash
while [[ $1 == --* ]]; do shift; done
exec mpirun -np "${SLURM_NTASKS:-2}" --oversubscribe "$@"
""")
    env = dict(os.environ)
    env["PATH"] = f"{bin_dir}:{env['PATH']}"
    env["PYTHONPATH"] = str(ROOT / "python")
    env["MPLBACKEND"] = "Agg"
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    return env


def test_every_page_has_runnable_blocks():
    names = {p.name for p in PAGES}
    assert {"getting-started.md", "closed-loop.md", "uq-sobol.md", "sensitivities.md", "cluster.md"} <= names
    for page in PAGES:
        assert blocks(page), f"{page}: no ```bash or ```python block"


@pytest.mark.skipif(not KANESENS, reason="needs the kanesens executable (KANESENS)")
@pytest.mark.parametrize("page", PAGES, ids=[p.stem for p in PAGES])
def test_page_runs_as_written(page, tmp_path):
    env = scratch(tmp_path)
    for i, (lang, body, shown) in enumerate(blocks_with_output(page)):
        if lang == "bash":
            cmd = ["bash", "-euo", "pipefail", "-c", body]
        else:
            script = tmp_path / f".block{i}.py"
            script.write_text(body)
            cmd = ["/usr/bin/python3", str(script)]
        r = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=900)
        assert r.returncode == 0, (f"{page.relative_to(ROOT)}, block {i + 1} ({lang}) failed "
                                   f"with {r.returncode}:\n{body}\n--- stdout\n{r.stdout[-3000:]}\n"
                                   f"--- stderr\n{r.stderr[-3000:]}")
        if shown is not None:
            printed = (r.stdout + "\n" + r.stderr).splitlines()
            missing = [line for line in shown.splitlines() if line.strip() and not line_shown(line, printed)]
            assert not missing, (f"{page.relative_to(ROOT)}, block {i + 1}: the output shown after it is not "
                                 f"what it printed:\n" + "\n".join(missing) + "\n--- printed\n" + "\n".join(printed))


def test_line_shown_is_strict():
    printed = ["t [s]  mean  std", "    2  0.1493  0.0003572", "error: out/a.yaml:9:27: bad 'x'; types are: a, b, c"]
    assert line_shown("    2    0.1493  0.0003572", printed)
    assert line_shown("2 0.14931 0.0003572", printed)                # 1e-3 relative
    assert not line_shown("2 0.15 0.0003572", printed)
    assert not line_shown("2 0.1493", printed)                       # a column missing
    assert line_shown("error: out/a.yaml:9:27: bad 'x'; types are: a, ...", printed)
    assert not line_shown("error: out/a.yaml:9:28: bad 'x'; types are: a, ...", printed)
    assert line_shown("  m  -4.0e-12 [-1.0e-11,", ["  m  -4.7e-12 [-1.4e-11,"])  # round-off digits


def test_getting_started_lists_the_packages_install_deps_installs():
    """The apt lists on the getting-started page are tools/install-deps.sh's list (which CI uses),
    apart from git and libfmt-dev, which the build does not need."""
    script = (ROOT / "tools/install-deps.sh").read_text(encoding="utf-8")
    array = re.search(r"^packages=\((.*?)^\)", script, re.S | re.M).group(1)
    installed = set(re.findall(r"[a-z0-9][a-z0-9.+-]+", re.sub(r"#.*", "", array)))
    installed |= set(re.findall(r"packages\+=\(([^)]*)\)", script)[0].split())
    page = (ROOT / "docs/getting-started.md").read_text(encoding="utf-8")
    section = page.split("## 1. Install the dependencies", 1)[1].split("**Other systems**", 1)[0]
    shown = set()
    for block in re.findall(r"```sh\n(.*?)```", section, re.S):
        for line in re.sub(r"#.*", "", block).replace("\\\n", " ").splitlines():
            if "apt-get install" in line:
                shown |= set(line.split("apt-get install", 1)[1].split())
    shown |= set(re.findall(r"`((?:python3|lib|hdf5)[a-z0-9.+-]*(?: lib[a-z0-9.+-]+)*)`", section))
    shown = {w for item in shown for w in item.split()}
    assert sorted(shown - installed) == []
    assert sorted(installed - shown - {"git", "libfmt-dev"}) == []
