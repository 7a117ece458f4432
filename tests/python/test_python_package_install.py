"""The installed route of the post-processing package, exactly as docs/getting-started.md gives it: a venv
made with `/usr/bin/python3 -m venv --system-site-packages`, `pip install --no-build-isolation
--no-deps --no-index ./python` (offline), then the `kanesens-post` console script.

The package directory is copied first: setuptools builds in the source tree (python/build,
*.egg-info), which a test must not write into."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE_DIR = Path(__file__).resolve().parents[2] / "python"


def run(cmd, **kw):
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)
    assert p.returncode == 0, f"{' '.join(map(str, cmd))} exited {p.returncode}:\n{p.stdout}\n{p.stderr}"
    return p


@pytest.fixture(scope="module")
def venv(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("install")
    src = tmp / "python"
    shutil.copytree(PACKAGE_DIR, src, ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    env_dir = tmp / "venv"
    run([sys.executable, "-m", "venv", "--system-site-packages", env_dir])
    # No PYTHONPATH: the venv must find the installed copy, not the source tree.
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    run([env_dir / "bin" / "pip", "install", "--no-build-isolation", "--no-deps", "--no-index",
         "--disable-pip-version-check", "--quiet", src], env=env, cwd=tmp)
    return env_dir, env


def test_console_script_runs(venv):
    env_dir, env = venv
    p = run([env_dir / "bin" / "kanesens-post", "--help"], env=env)
    for command in ("summary", "plot", "sobol", "morris", "dgsm", "linear-uq"):
        assert command in p.stdout


def test_imports_the_installed_copy(venv, tmp_path):
    env_dir, env = venv
    p = run([env_dir / "bin" / "python", "-c", "import kanesens_post; print(kanesens_post.__file__)"],
            env=env, cwd=tmp_path)
    installed = Path(p.stdout.strip()).resolve()
    assert env_dir.resolve() in installed.parents, installed
