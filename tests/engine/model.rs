//! The Vakhrameev calibration recovers the coefficients its data were built with.

use crate::common;

use common::{Program, Truth, log_from};
use driftlab::judge::metrics::{Evaluation, MeritOptions};
use driftlab::models::approx::{ApproxKind, ApproxSpec, Curve};
use driftlab::models::recipe::{PlateauChoice, Recipe};
use driftlab::models::vakhrameev::{self, Regime};
use driftlab::signal::plateau::PlateauRange;

const TRUTH: Truth = Truth {
    k0: [0.2, 0.004, -6e-5],
    k1_plus: 40.0,
    k1_minus: 25.0,
    k2_plus: 0.0,
    k2_minus: 0.0,
};

/// A recipe that differentiates with almost no lag, for noise-free data.
fn sharp_recipe() -> Recipe {
    Recipe {
        filter_s: 1.0,
        temp_smoothing_s: 1.0,
        step_h_s: 2.0,
        ..Recipe::default()
    }
}

#[test]
fn plateaus_found_at_the_holds_of_the_program() {
    let program = Program::paper_like();
    let log = log_from(&program, &TRUTH, 0.0, 0.001, 1);
    let fit = vakhrameev::fit(&log, &driftlab::models::CheckedRecipe::default()).unwrap();
    let temps: Vec<f64> = fit.calibration.plateaus.iter().map(|p| p.temp_c).collect();
    assert_eq!(temps.len(), 4, "holds at 20, 60, -50, 20: {temps:?}");
    for (got, want) in temps.iter().zip([20.0, 60.0, -50.0, 20.0]) {
        assert!((got - want).abs() < 0.01, "{got} vs {want}");
    }
    // The settled tail of each hold: the last half, ending where the hold ends. The program's
    // next ramp starts as a raised cosine, under 0.01 °C/min for its first ~190 s.
    let p = fit.calibration.plateaus[1].range;
    assert!(
        (p.end_s - (3600.0 + 3000.0 + 5400.0)).abs() < 250.0,
        "{p:?}"
    );
}

#[test]
fn k0_recovered_from_plateaus() {
    let log = log_from(&Program::paper_like(), &TRUTH, 0.0, 0.0, 1);
    // Inside the three holds at 20, 60 and −50 °C, where Ṫ = T̈ = 0 exactly.
    let ranges = vec![
        PlateauRange {
            start_s: 1000.0,
            end_s: 3500.0,
        },
        PlateauRange {
            start_s: 7000.0,
            end_s: 11900.0,
        },
        PlateauRange {
            start_s: 21000.0,
            end_s: 24000.0,
        },
    ];
    let recipe = Recipe {
        plateaus: PlateauChoice::Manual { ranges },
        ..sharp_recipe()
    };
    let fit = vakhrameev::fit(&log, &recipe.clone().checked().unwrap()).unwrap();
    let Curve::Polynomial { coeffs } = fit.calibration.k0.curve() else {
        panic!("parabolic K0")
    };
    for (got, want) in coeffs.iter().zip(TRUTH.k0) {
        assert!((got - want).abs() < 1e-9, "{coeffs:?}");
    }
}

#[test]
fn k1_recovered_from_synthetic_ramps() {
    let log = log_from(&Program::paper_like(), &TRUTH, 0.0, 0.0, 1);
    let fit = vakhrameev::fit(&log, &(sharp_recipe()).clone().checked().unwrap()).unwrap();
    let cal = &fit.calibration;
    assert!(fit.k1_plus_points.len() > 1000 && fit.k1_minus_points.len() > 1000);
    for (name, a, want) in [
        ("K1+", &cal.k1_plus, TRUTH.k1_plus),
        ("K1-", &cal.k1_minus, TRUTH.k1_minus),
    ] {
        for x in [a.x_min(), 0.5 * (a.x_min() + a.x_max()), a.x_max()] {
            assert!(
                (a.eval(x) - want).abs() < 0.01 * want,
                "{name}({x}) = {} vs {want}",
                a.eval(x)
            );
        }
    }
    // With K2 = 0 in the data, what K1 leaves is noise of the derivative scheme: K2 ≈ 0
    // against a scale of K1·Ṫ/T̈.
    for a in [&cal.k2_plus, &cal.k2_minus] {
        assert!(a.eval(a.x_max()).abs() < 0.01 * 40.0 * 0.02 / 1e-5);
    }
}

#[test]
fn model_with_k2_terms_predicts_its_own_data() {
    let truth = Truth {
        k2_plus: 3.0e4,
        k2_minus: -2.0e4,
        ..TRUTH
    };
    let log = log_from(&Program::paper_like(), &truth, 0.0, 0.0, 1);
    let recipe = Recipe {
        k1_plus: ApproxSpec::of(ApproxKind::Parabolic),
        k1_minus: ApproxSpec::of(ApproxKind::Parabolic),
        ..sharp_recipe()
    };
    let fit = vakhrameev::fit(&log, &recipe.clone().checked().unwrap()).unwrap();
    let eval = Evaluation::of(&fit.calibration, &log, &MeritOptions::default());
    let c = eval.comparison;
    assert!(
        c.raw.p2p_dph > 1.0,
        "the test data must have a real drift: {}",
        c.raw.p2p_dph
    );
    // Measured 9.2x: the pointwise K1 absorbs part of K2·T̈/Ṫ, which the refinement passes
    // only partly return to K2.
    assert!(
        c.p2p_ratio > 6.0,
        "raw {} corrected {}",
        c.raw.p2p_dph,
        c.corrected.p2p_dph
    );
}

#[test]
fn regimes_follow_the_signs_of_the_rates() {
    assert_eq!(Regime::of(0.01, 1e-5), Regime::Plus);
    assert_eq!(Regime::of(-0.01, -1e-5), Regime::Plus);
    assert_eq!(Regime::of(0.01, -1e-5), Regime::Minus);
    assert_eq!(Regime::of(0.0, 1e-5), Regime::Static);
}

#[test]
fn manual_plateaus_replace_detection() {
    let log = log_from(&Program::paper_like(), &TRUTH, 0.0, 0.0, 1);
    let ranges = vec![
        PlateauRange {
            start_s: 1000.0,
            end_s: 3000.0,
        },
        PlateauRange {
            start_s: 9000.0,
            end_s: 11000.0,
        },
    ];
    let recipe = Recipe {
        plateaus: PlateauChoice::Manual {
            ranges: ranges.clone(),
        },
        ..sharp_recipe()
    };
    let fit = vakhrameev::fit(&log, &recipe.clone().checked().unwrap()).unwrap();
    let got: Vec<PlateauRange> = fit.calibration.plateaus.iter().map(|p| p.range).collect();
    assert_eq!(got, ranges);
    // Two plateaus cannot carry a parabola: K0 falls back to a line, with a warning.
    assert!(
        fit.warnings.iter().any(|w| w.starts_with("K0")),
        "{:?}",
        fit.warnings
    );
    assert!((fit.calibration.k0.eval(60.0) - TRUTH.k0(60.0)).abs() < 1e-9);
}

#[test]
fn a_log_without_plateaus_cannot_define_k0() {
    let program = Program {
        start_c: 0.0,
        start_hold_s: 0.0,
        legs: vec![(40.0, 4000.0, 0.0), (0.0, 4000.0, 0.0)],
    };
    let log = log_from(&program, &TRUTH, 0.0, 0.0, 1);
    let err = vakhrameev::fit(&log, &driftlab::models::CheckedRecipe::default()).unwrap_err();
    assert!(err.to_string().contains("no plateaus"), "{err}");
}

#[test]
fn invalid_recipes_are_refused_with_the_setting_named() {
    let log = log_from(&Program::paper_like(), &TRUTH, 0.0, 0.0, 1);
    let bad = Recipe {
        step_h_s: -1.0,
        ..Recipe::default()
    };
    // Refused where it is checked, before any fit can take it.
    assert!(bad.checked().unwrap_err().to_string().contains("step_h_s"));
    let bad = Recipe {
        k1_plus: ApproxSpec {
            kind: ApproxKind::Spline,
            knots: 1,
            extrapolate: false,
            ..Default::default()
        },
        ..Recipe::default()
    };
    assert!(bad.checked().unwrap_err().to_string().contains("k1_plus"));
    // A checked recipe whose windows do not fit the log is refused by the fit, named.
    let long = Recipe {
        step_h_s: 9e5,
        ..Recipe::default()
    }
    .checked()
    .unwrap();
    assert!(
        vakhrameev::fit(&log, &long)
            .unwrap_err()
            .to_string()
            .contains("step_h_s")
    );
}

/// The method's pointwise K1 and K2 written as a plain walk over the samples, apart from the
/// engine: outside plateaus, in the set's regime, beyond the dead-band,
/// `K1 = (Ω_f − K0(T) − K2(T̈)·T̈) / Ṫ` and `K2 = (Ω_f − K0(T) − K1(Ṫ)·Ṫ) / T̈`.
#[allow(clippy::needless_range_loop)] // one index walks six parallel columns
fn walk_points(
    log: &driftlab::Log,
    fit: &vakhrameev::Fit,
    regime: Regime,
    second: bool,
) -> (Vec<f64>, Vec<f64>) {
    let cal = &fit.calibration;
    let ranges: Vec<PlateauRange> = cal.plateaus.iter().map(|p| p.range).collect();
    let mask = driftlab::signal::plateau::mask(&log.time_s, &ranges);
    let (k1, k2) = match regime {
        Regime::Minus => (&cal.k1_minus, &cal.k2_minus),
        _ => (&cal.k1_plus, &cal.k2_plus),
    };
    let d = &fit.prepared.deriv;
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for i in d.ready_from..log.len() {
        let (td, tdd) = (d.tdot[i], d.tddot[i]);
        let deadband = if second {
            cal.resolved.deadband_tddot
        } else {
            cal.resolved.deadband_tdot
        };
        let x = if second { tdd } else { td };
        if mask[i] || x.abs() <= deadband || Regime::of(td, tdd) != regime {
            continue;
        }
        let rest = fit.prepared.omega_filtered_dph[i] - cal.k0.eval(log.temp_c[i]);
        xs.push(x);
        ys.push(if second {
            (rest - k1.eval(td) * td) / tdd
        } else {
            (rest - k2.eval(tdd) * tdd) / td
        });
    }
    (xs, ys)
}

#[test]
fn pointwise_coefficients_are_the_methods_walk() {
    // The report's and the workbench's scatter points (Calibration::pointwise) and the points
    // the fit kept are the method's formula over the samples it names, in log order.
    let truth = Truth {
        k2_plus: 2e4,
        k2_minus: -1e4,
        ..TRUTH
    };
    let log = log_from(&Program::paper_like(), &truth, 0.3, 0.001, 3);
    let fit = vakhrameev::fit(&log, &driftlab::models::CheckedRecipe::default()).unwrap();
    let [k1p, k1m, k2p, k2m] = fit.calibration.pointwise(&log);
    for (got, regime, second) in [
        (&k1p, Regime::Plus, false),
        (&k1m, Regime::Minus, false),
        (&k2p, Regime::Plus, true),
        (&k2m, Regime::Minus, true),
    ] {
        let (xs, ys) = walk_points(&log, &fit, regime, second);
        assert!(xs.len() > 1000);
        assert_eq!(got.x, xs);
        assert_eq!(got.y, ys);
    }
    // The fit's last pass saw the same points (its K1 with the K2 that pass started from, so
    // only K2's points, made with the final K1, must match the walk exactly).
    assert_eq!(fit.k2_plus_points.x, k2p.x);
    assert_eq!(fit.k2_plus_points.y, k2p.y);
    assert_eq!(fit.k2_minus_points.y, k2m.y);
}

#[test]
fn streamed_k2_fit_is_the_weighted_fit_of_the_walked_points() {
    // The fit solves its passes from moments gathered over sample indices, without gathering
    // points; its K2 must be the plain least-squares fit, weighted by T̈², of the walked
    // points, to rounding (the two sum the same products in another order), with the same
    // statistics.
    let truth = Truth {
        k2_plus: 2e4,
        k2_minus: -1e4,
        ..TRUTH
    };
    let log = log_from(&Program::paper_like(), &truth, 0.3, 0.001, 3);
    let recipe = Recipe::default();
    let lean = vakhrameev::fit_lean(&log, &recipe.clone().checked().unwrap())
        .unwrap()
        .calibration;
    let fit = vakhrameev::fit(&log, &recipe.clone().checked().unwrap()).unwrap();
    for (regime, spec, got) in [
        (Regime::Plus, &recipe.k2_plus, &lean.k2_plus),
        (Regime::Minus, &recipe.k2_minus, &lean.k2_minus),
    ] {
        let (xs, ys) = walk_points(&log, &fit, regime, true);
        let w: Vec<f64> = xs.iter().map(|x| x * x).collect();
        let want = driftlab::models::approx::fit_weighted(spec, &xs, &ys, Some(&w)).unwrap();
        assert_eq!((got.x_min(), got.x_max()), (want.x_min(), want.x_max()));
        let scale = xs.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        for k in 0..=20 {
            let x = want.x_min() + (want.x_max() - want.x_min()) * k as f64 / 20.0;
            let (g, v) = (got.eval(x), want.eval(x));
            assert!(
                (g - v).abs() <= 1e-9 * (v.abs() + want.eval(scale).abs() + 1.0),
                "{regime:?} K2 at {x}: moments {g}, walked points {v}"
            );
        }
        let (gs, ws) = (got.stats(), want.stats());
        assert_eq!(gs.n, xs.len());
        assert_eq!(gs.n, ws.n);
        assert!(
            (gs.rmse - ws.rmse).abs() <= 1e-9 * ws.rmse,
            "{gs:?} against {ws:?}"
        );
        assert!((gs.r2 - ws.r2).abs() <= 1e-9, "{gs:?} against {ws:?}");
    }
}

#[test]
fn lean_calibration_is_the_full_fit() {
    let log = log_from(&Program::paper_like(), &TRUTH, 0.3, 0.001, 5);
    for recipe in [Recipe::default(), sharp_recipe()] {
        let fit = vakhrameev::fit(&log, &recipe.clone().checked().unwrap()).unwrap();
        let lean = vakhrameev::fit_lean(&log, &recipe.clone().checked().unwrap()).unwrap();
        let strip = |c: &vakhrameev::Calibration| vakhrameev::Calibration {
            created: String::new(),
            ..c.clone()
        };
        assert_eq!(strip(&lean.calibration), strip(&fit.calibration));
        assert_eq!(lean.warnings, fit.warnings);
        assert_eq!(lean.deriv.tdot, fit.prepared.deriv.tdot);
        assert_eq!(lean.deriv.tddot, fit.prepared.deriv.tddot);
    }
}
