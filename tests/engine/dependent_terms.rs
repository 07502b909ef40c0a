//! Terms that are one effect between them are refused before or by the fit, never fitted
//! with standard errors that mean nothing (attack 23, finding 03): the polynomials in T by
//! name before the fit (`1,T,T-Tref` is one line in T for every Tref), and any other
//! dependence of the design's columns on the log by the fit's rank check. Independent
//! terms still recover the curve the log was made with.

use driftlab::log::Log;
use driftlab::models::regression::RegressionSpec;
use driftlab::models::regression::terms::parse_terms;
use driftlab::models::{self, CheckedRecipe, DriftModel, ModelChoice};

/// Six hours at 1 Hz between 10 and 60 °C, the rate `0.2 + 0.01·(T − 35) + 0.001·(T − 35)²`
/// °/h plus white noise.
fn parabola_log() -> Log {
    super::firmware_forms::log_of(&[0.2, 0.01, 0.001], 0.01, 1.0, 21_600.0, 7)
}

fn fit(log: &Log, terms: &str) -> driftlab::Result<DriftModel> {
    let spec = RegressionSpec::new("custom", parse_terms(terms).unwrap());
    models::fit(log, &ModelChoice::Custom(spec), &CheckedRecipe::default())
}

#[test]
fn terms_that_are_one_polynomial_in_t_are_refused_by_name() {
    let log = parabola_log();
    for (terms, named) in [
        (
            "1,T,T-Tref",
            "the terms 1, T and T-Tref are one polynomial in T",
        ),
        ("1,T,T^2,(T-Tref)^2", "(T-Tref)^2 = T^2 - 2·Tref·T + Tref^2"),
        ("T^2,1,(T-Tref)^2,T", "the terms T^2, 1, (T-Tref)^2 and T"),
    ] {
        let e = fit(&log, terms).expect_err(terms).to_string();
        assert!(e.contains(named), "{terms}: {e}");
    }
}

#[test]
fn a_design_dependent_on_the_log_is_refused_naming_its_columns() {
    // pwlT's hats add up to 1 at every T: with a constant they are one effect.
    let e = fit(&parabola_log(), "1,pwlT:3")
        .expect_err("refused")
        .to_string();
    assert!(
        e.contains("the terms 1, pwlT[0], pwlT[1], pwlT[2] are one effect between them"),
        "{e}"
    );
}

#[test]
fn independent_centred_terms_recover_the_curve() {
    let log = parabola_log();
    let DriftModel::Regression(r) = fit(&log, "1,(T-Tref)^1,(T-Tref)^2").unwrap() else {
        panic!("a regression");
    };
    let m = r.model;
    let t_ref = m.t_ref_c.unwrap();
    let [lo, hi] = m.ranges.temp.unwrap();
    assert_eq!(t_ref, 0.5 * (lo + hi));
    // The truth about 35 °C moved to Tref.
    let d = t_ref - 35.0;
    let want = [0.2 + 0.01 * d + 0.001 * d * d, 0.01 + 0.002 * d, 0.001];
    for (k, (got, want)) in m.coefficients.iter().zip(want).enumerate() {
        assert!(
            (got - want).abs() < 1e-3 * 25f64.powi(-(k as i32)) + 1e-6,
            "coefficient {k}: {got}, made with {want}"
        );
    }
}
