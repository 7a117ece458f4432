"""The getting-started page and every tutorial run as written, so their commands cannot rot.

Convention in docs/getting-started.md and docs/tutorials/*.md: a fenced block marked ```bash is
a command a reader runs from the repository root, and this test runs it; a ```python block is
a script, run with /usr/bin/python3; blocks marked ```sh (installing packages, building, a real
cluster) or ```text are shown only. Blocks run in page order in one scratch directory that holds
the repository's configs/, scripts/ and python/ (links), with `kanesens` and `kanesens-post` on
PATH. On the Slurm tutorial `sbatch` and `srun` are stand-ins that run the batch script and
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
    return [(lang, body) for lang, body in BLOCK.findall(page.read_text(encoding="utf-8"))
            if lang in ("bash", "python")]


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
    for i, (lang, body) in enumerate(blocks(page)):
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
