"""`kanesens-workprecision`: the rows it prints, errors that fall with the tolerance, a
reference read from a file (here `kanesens simulate` output) equivalent to the computed one,
skipped Adams rows for a projected constrained scene, and bad input as exit status 2."""
import json
import subprocess

from workprecision_support import ROOT, exe, row, rows, run

CHAIN = ["bench/configs/wp_chain4.yaml", "--set", "time.end=2", "--set", "time.outputs=21"]


def test_rows_and_errors_fall_with_tolerance():
    d = run(*CHAIN, "--tolerances", "1e-4,1e-6,1e-8", "--rk4-steps", "100,400", "--reference-rtol", "1e-12")
    assert d["reference"]["kind"] == "computed" and d["reference"]["row"]["ok"]
    assert {r["method"] for r in d["rows"]} == {"bdf-exact", "bdf-dq", "adams-newton", "adams-functional", "dop853", "rk4"}
    for m in ("bdf-exact", "bdf-dq", "adams-newton", "adams-functional", "dop853"):
        e = [row(d, m, tol=t)["final_rel_error"] for t in (1e-4, 1e-6, 1e-8)]
        assert e[2] < e[1] < e[0] < 1, (m, e)
        for r in rows(d, m):
            assert r["ok"] and r["steps"] > 0 and r["rhs_evals"] > 0 and r["wall_seconds"] > 0
            assert r["l2_error"] <= r["linf_error"]
    rk = {r["steps"]: r for r in rows(d, "rk4")}
    assert rk[400]["rhs_evals"] == 1600
    # fourth order: 4x the steps, error / 256 (loosely)
    assert rk[100]["final_rel_error"] / rk[400]["final_rel_error"] > 50


def test_reference_file_matches_computed_reference(tmp_path):
    ref = subprocess.run([exe(), "simulate", *CHAIN, "--set", "solver.rtol=1e-12", "--set", "solver.atol=1e-14"],
                         cwd=ROOT, capture_output=True, text=True, check=True).stdout
    (tmp_path / "ref.json").write_text(ref)
    a = run(*CHAIN, "--methods", "bdf-exact", "--tolerances", "1e-6", "--reference-rtol", "1e-12")
    b = run(*CHAIN, "--methods", "bdf-exact", "--tolerances", "1e-6", "--reference-file", tmp_path / "ref.json")
    assert b["reference"]["kind"] == "file"
    ea, eb = a["rows"][0]["final_rel_error"], b["rows"][0]["final_rel_error"]
    assert abs(ea - eb) < 1e-3 * ea, (ea, eb)


def test_sensitivity_methods_and_constrained_scene():
    d = run("bench/configs/wp_constrained_pendulum.yaml", "--set", "time.end=2", "--set", "time.outputs=21",
            "--tolerances", "1e-6", "--reference-rtol", "1e-11")
    assert row(d, "adams-newton", tol=1e-6)["skipped"]
    for m in ("bdf-exact", "sens-exact", "sens-dq"):
        r = row(d, m, tol=1e-6)
        assert r["ok"] and r["constraint_position_residual"] < 1e-6
    assert row(d, "sens-exact", tol=1e-6)["sens_final_rel_error"] < 1e-2
    assert row(d, "sens-dq", tol=1e-6)["rhs_evals_for_sens"] > 0
    assert row(d, "bdf-exact", tol=1e-6)["sens_final_rel_error"] is None  # states only
    # DOP853 projects after every accepted step: the position constraint holds to round-off
    dop = row(d, "dop853", tol=1e-6)
    assert dop["ok"] and dop["constraint_position_residual"] < 1e-12, dop
    # RK4 does not project: the constraint drifts, and the bench says by how much
    assert row(d, "rk4", tol=1e-6)["constraint_position_residual"] > 0


def test_dop853_reference_agrees_with_the_bdf_reference():
    """--reference-method dop853: the same study, the same errors to within the BDF reference's
    own error (~1e-9 relative here), so either reference measures errors above that floor."""
    a = run(*CHAIN, "--methods", "adams-newton", "--tolerances", "1e-6", "--reference-rtol", "1e-12")
    b = run(*CHAIN, "--methods", "adams-newton", "--tolerances", "1e-6", "--reference-method", "dop853")
    assert a["reference"]["row"]["method"] == "bdf-exact" and b["reference"]["row"]["method"] == "dop853"
    ea, eb = a["rows"][0]["final_rel_error"], b["rows"][0]["final_rel_error"]
    assert abs(ea - eb) < 1e-3 * ea, (ea, eb)


def test_bad_input_is_exit_2():
    p = run(*CHAIN, "--methods", "bdf-exact,magic", check=False)
    assert p.returncode == 2 and "unknown method 'magic'" in p.stderr
    p = run(*CHAIN, "--reference-method", "sens-exact", check=False)
    assert p.returncode == 2 and "--reference-method" in p.stderr
    p = run(*CHAIN, "--methods", "sens-dq", check=False)
    assert p.returncode == 2 and "sensitivities" in p.stderr
