"""Stability atlas (docs/explanation/stability.md), chaos: the double pendulum released from shoulder = 2 rad
(bench/configs/wp_double_pendulum_lyapunov.yaml), sensitivities to both initial angles, 40 s. The norm
of the sensitivity matrix grows like exp(lambda t): ln ||S(t)||_F / t estimates the largest
Lyapunov exponent. Pinned: the growth rate is positive and about 1.3 1/s (0.8..2) for BDF,
Adams and RK4 alike, although their trajectories disagree completely by the end (final error
O(1)): the exponent is a property of the attractor, the trajectory is not."""
from workprecision_support import row, run


def test_sensitivity_growth_rate_is_a_positive_lyapunov_exponent():
    d = run("bench/configs/wp_double_pendulum_lyapunov.yaml", "--set", "time.end=40", "--set", "time.outputs=401",
            "--methods", "bdf-exact,adams-newton,rk4", "--with-sens", "--tolerances", "1e-8",
            "--reference-rtol", "1e-10")
    rates = [d["reference"]["row"]["sens_growth_rate"]]
    for m in ("bdf-exact", "adams-newton", "rk4"):
        r = row(d, m, tol=1e-8)
        assert r["ok"], r["message"]
        rates.append(r["sens_growth_rate"])
        assert r["sens_norm_final"] > 1e12  # e^(1.3 * 40) ~ 1e22: the growth is real
    for rate in rates:
        assert 0.8 < rate < 2.0, rates
    assert max(rates) - min(rates) < 0.5, rates
    # 40 s is far beyond the predictability horizon of rtol 1e-8: the states disagree at O(1).
    assert row(d, "bdf-exact", tol=1e-8)["final_rel_error"] > 1e-2
