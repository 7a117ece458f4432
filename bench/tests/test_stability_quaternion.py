"""Stability atlas (docs/explanation/stability.md), quaternion norm drift: the fast heavy top
(bench/configs/wp_spinning_top.yaml: spherical joint, spin 100 rad/s). With the stabilisation term
kappa (1 - |q|^2) q in the kinematic equation, | |q| - 1 | stays within a small multiple of rtol
for BDF and Adams, and does not grow with time (40 s vs 160 s: the largest deviation, reached early,
is not exceeded later), while the energy error does."""
from workprecision_support import row, run


def drift(end, tols="1e-6,1e-8"):
    return run("bench/configs/wp_spinning_top.yaml", "--set", f"time.end={end}", "--set", f"time.outputs={10 * end + 1}",
               "--methods", "bdf-exact,adams-newton", "--tolerances", tols, "--reference-rtol", "1e-7")


def test_quaternion_norm_stays_near_one_and_bounded():
    short, long_ = drift(40), drift(160)
    for m in ("bdf-exact", "adams-newton"):
        for tol in (1e-6, 1e-8):
            a, b = row(short, m, tol=tol), row(long_, m, tol=tol)
            assert a["ok"] and b["ok"]
            assert a["quaternion_norm_drift"] < 20 * tol, (m, tol, a["quaternion_norm_drift"])
            assert b["quaternion_norm_drift"] < 20 * tol, (m, tol, b["quaternion_norm_drift"])
            # bounded: 4x the time, at most 2x the drift
            assert b["quaternion_norm_drift"] < 2 * a["quaternion_norm_drift"] + tol
    # ... whereas the energy error keeps growing for BDF
    assert row(long_, "bdf-exact", tol=1e-6)["energy_drift"] > 2 * row(short, "bdf-exact", tol=1e-6)["energy_drift"]
