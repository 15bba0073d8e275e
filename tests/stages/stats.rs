//! The tests' own statistics (`tests/support/stats.rs`) and the chi-square tail they build on:
//! published critical values and quantiles, pooling, and outright failures.

use crate::support::stats::*;
use hemilab::stats::chi2_p_value;

#[test]
fn chi2_p_values_match_published_critical_values() {
    // Critical values of the chi-square distribution at p = 0.05 and 0.01.
    for (x, dof, p) in
        [(3.841_459, 1, 0.05), (18.307_04, 10, 0.05), (6.634_897, 1, 0.01), (124.342_1, 100, 0.05)]
    {
        let got = chi2_p_value(x, dof);
        assert!((got - p).abs() < 1e-5, "{x} {dof}: {got}");
    }
    // Below a + 1 (the series branch, where the warps' chi2 tests with thousands of dof land):
    // the lower 5 % critical values, and dof 2 in closed form, Q = exp(-x/2).
    for (x, dof) in [(77.929_46, 100), (3.940_299, 10)] {
        let got = chi2_p_value(x, dof);
        assert!((got - 0.95).abs() < 1e-5, "{x} {dof}: {got}");
    }
    assert!((chi2_p_value(0.103, 2) - (-0.0515f64).exp()).abs() < 1e-12);
    // P + Q = 1 on both branches.
    for (a, x) in [(0.5, 0.2), (3.0, 10.0), (2500.0, 2400.0)] {
        assert!((gamma_p(a, x) + gamma_q(a, x) - 1.0).abs() < 1e-12);
    }
}

#[test]
fn pooling_reaches_min_expected_and_keeps_totals() {
    let e = [0.5, 1.0, 2.0, 3.0, 10.0, 0.0, 4.0];
    let o = [1.0, 0.0, 2.0, 4.0, 9.0, 0.0, 5.0];
    let pools = pool_cells(&o, &e, 5.0);
    assert!(pools.iter().all(|p| p.1 >= 5.0));
    assert_eq!(pools.iter().map(|p| p.0).sum::<f64>(), 21.0);
    assert_eq!(pools.iter().map(|p| p.1).sum::<f64>(), 20.5);
}

#[test]
fn chi2_fails_outright_on_sample_in_empty_cell() {
    let r = chi2_test(&[1.0, 10.0, 10.0], &[0.0, 10.0, 11.0], 5.0);
    assert!(matches!(r, Err(Chi2Error::SampleWhereExpectedZero { cell: 0, .. })));
    assert!(matches!(chi2_test(&[1.0], &[5.0, 6.0], 5.0), Err(Chi2Error::LengthMismatch { .. })));
}

#[test]
fn two_sided_z_matches_normal_quantiles() {
    // Published two-sided quantiles of the standard normal.
    for (p, z) in [(0.05, 1.959_964), (0.01, 2.575_829), (0.002_699_796, 3.0), (1e-6, 4.891_638)] {
        assert!((two_sided_z(p) - z).abs() < 1e-5, "p = {p}: {}", two_sided_z(p));
    }
    assert_eq!(two_sided_z(1.0), 0.0);
}

#[test]
fn sidak_threshold_is_alpha_for_one_test() {
    assert!((sidak_threshold(0.01, 1) - 0.01).abs() < 1e-15);
    assert!(sidak_threshold(0.01, 4) < 0.01 / 4.0 + 1e-5);
}
