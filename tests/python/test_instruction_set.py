"""The instruction set a build targets (CMake's KANESENS_ARCH; `auto`, the default, is the build
machine's) is named by `kanesens --version`, and a binary started on a processor that lacks one of
its extensions stops before it does anything, with one line naming them and exit code 1, instead
of dying of an illegal instruction (util/instruction_set.cpp). KANESENS_CPU_FEATURES_MASKED makes
the check treat the extensions it lists as absent, so the message is tested on any machine."""
import os
import re
import subprocess

import pytest

ROOT = os.environ.get("KANESENS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
STUDY = os.path.join(ROOT, "configs", "four_bar_study.yaml")


def kanesens(*args, masked=None):
    exe = os.environ.get("KANESENS")
    if not exe:
        pytest.skip("KANESENS is not set (path of the kanesens executable)")
    env = dict(os.environ)
    env.pop("KANESENS_CPU_FEATURES_MASKED", None)
    if masked is not None:
        env["KANESENS_CPU_FEATURES_MASKED"] = masked
    return subprocess.run([exe, *args], capture_output=True, text=True, env=env)


def compiled_features():
    out = kanesens("--version")
    assert out.returncode == 0, out.stderr
    line = [l for l in out.stdout.splitlines() if "instruction set" in l]
    assert len(line) == 1, out.stdout
    m = re.search(r"instruction set (the compiler's baseline|-march=(\S+)(?: \(([a-z0-9. ]+)\))?)$", line[0])
    assert m, line[0]
    return m.group(3).split() if m.group(3) else []


def test_a_missing_extension_stops_the_program_with_one_line(tmp_path):
    features = compiled_features()
    if not features:
        # A baseline build requires nothing beyond the architecture: masking changes nothing.
        assert kanesens("--version", masked="sse3 avx2 avx512f").returncode == 0
        return
    out_file = tmp_path / "run.h5"
    for masked, missing in ((features[-1], [features[-1]]),
                            (f"x {features[0]}  {features[-1]} y", [features[0], features[-1]])):
        r = kanesens("run", STUDY, "-o", str(out_file), masked=masked)
        assert r.returncode == 1, (masked, r.returncode, r.stderr)
        assert r.stdout == ""
        lines = r.stderr.splitlines()
        assert len(lines) == 1 and lines[0].startswith("kanesens: error: this processor lacks "), r.stderr
        assert lines[0].split("lacks ")[1].split(",")[0].split() == missing
        assert "KANESENS_ARCH" in lines[0]
        assert not out_file.exists()


def test_every_program_on_the_engine_has_the_check():
    # The check comes with the util library (a link option names it), not with main().
    features = compiled_features()
    if not features:
        pytest.skip("a baseline build: nothing to check")
    build = os.path.dirname(os.environ["KANESENS"])
    programs = [os.path.join(build, p) for p in ("examples/embed/kanesens-embed", "bench/kanesens-workprecision")]
    programs = [p for p in programs if os.path.exists(p)]
    if not programs:
        pytest.skip("kanesens-embed and kanesens-workprecision are not built")
    env = dict(os.environ, KANESENS_CPU_FEATURES_MASKED=features[0])
    for program in programs:
        r = subprocess.run([program, "--help"], capture_output=True, text=True, env=env)
        assert r.returncode == 1 and r.stderr.startswith("kanesens: error: this processor lacks " + features[0] + ","), \
            (program, r.returncode, r.stderr)


def test_only_whole_names_are_masked():
    features = compiled_features()
    if not features:
        pytest.skip("a baseline build: nothing to mask")
    # Prefixes and extensions of a name are other names (of a name whose prefix is not itself
    # one of the build's: bmi2's is bmi).
    name = next(f for f in reversed(features) if len(f) > 1 and f[:-1] not in features)
    for masked in (name[:-1], name + "x", ""):
        r = kanesens("--version", masked=masked)
        assert r.returncode == 0, (masked, r.stderr)
