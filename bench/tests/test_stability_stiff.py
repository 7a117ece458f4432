"""Stability atlas (docs/explanation/stability.md), stiffness: the 4-link chain swinging about its free first
joint while springs k = 1e6 N m/rad, c = 10 hold the others (bench/configs/wp_chain4_stiff_swing.yaml,
started on the slow manifold), 0.5 s. The Jacobian's largest eigenvalue is -164 +/- 5718i 1/s,
so RK4 is stable only for h below about 2.8/5720 = 4.9e-4 s.

Pinned: RK4 with h = 2e-3 blows up (a non-finite state, or the mass matrix of a blown-up state
fails: a failed row, not a crash), with h = 4e-4 it is accurate; BDF at rtol 1e-4 takes a few
dozen steps with ~1e-3 error; both Adams variants, DOP853 and RK4 need orders of magnitude more
steps (their stability limits, not accuracy, set h: DOP853 takes ~550 steps at every
tolerance)."""
from workprecision_support import row, rows, run


def test_stiff_chain_rk4_blows_up_bdf_cruises():
    d = run("bench/configs/wp_chain4_stiff_swing.yaml", "--set", "time.end=0.5", "--set", "time.outputs=26",
            "--methods", "bdf-exact,bdf-dq,adams-newton,adams-functional,dop853,rk4", "--tolerances", "1e-4",
            "--rk4-steps", "250,1250", "--reference-rtol", "1e-10")
    by_h = {round(r["h"], 12): r for r in rows(d, "rk4")}
    blown, fine = by_h[2e-3], by_h[4e-4]
    assert not blown["ok"] and blown["status"] in (-1001, -1002), blown["message"]
    assert blown["final_rel_error"] is None and blown["t_fail"] < 0.1
    assert fine["ok"] and fine["final_rel_error"] < 1e-6 and fine["steps"] == 1250

    bdf = row(d, "bdf-exact", tol=1e-4)
    assert bdf["ok"] and bdf["steps"] < 100 and bdf["final_rel_error"] < 1e-2, bdf
    assert row(d, "bdf-dq", tol=1e-4)["steps"] < 100
    for m in ("adams-newton", "adams-functional", "dop853"):
        r = row(d, m, tol=1e-4)
        assert r["ok"] and r["steps"] > 20 * bdf["steps"], (m, r["steps"], bdf["steps"])
    assert fine["rhs_evals"] > 50 * bdf["rhs_evals"]
