"""Stability atlas (docs/explanation/stability.md), long-horizon energy drift: the regular double pendulum
(bench/configs/wp_double_pendulum_long.yaml: no spring, no damping, so T + V is conserved), 200 s
(~140 swings of the lower rod). Pinned: BDF loses energy steadily (its numerical damping: the
drift at the end is negative and is the largest deviation), Adams–Moulton's drift is several
times smaller at the same tolerance, and both shrink with the tolerance."""
from workprecision_support import row, run


def test_bdf_damps_energy_adams_conserves_better():
    d = run("bench/configs/wp_double_pendulum_long.yaml", "--set", "time.end=200", "--set", "time.outputs=401",
            "--methods", "bdf-exact,adams-newton", "--tolerances", "1e-6,1e-8", "--reference-rtol", "1e-9")
    for tol in (1e-6, 1e-8):
        bdf, adams = row(d, "bdf-exact", tol=tol), row(d, "adams-newton", tol=tol)
        assert bdf["ok"] and adams["ok"]
        # BDF: monotone loss, the final value is (within 5 %) the largest deviation.
        assert bdf["energy_drift_final"] < 0
        assert -bdf["energy_drift_final"] > 0.95 * bdf["energy_drift"]
        assert adams["energy_drift"] * 3 < bdf["energy_drift"], (tol, bdf["energy_drift"], adams["energy_drift"])
    assert row(d, "bdf-exact", tol=1e-8)["energy_drift"] < 0.1 * row(d, "bdf-exact", tol=1e-6)["energy_drift"]
    assert row(d, "adams-newton", tol=1e-8)["energy_drift"] < 0.1 * row(d, "adams-newton", tol=1e-6)["energy_drift"]
