//! Unit tests of the fast evaluator against `Approx::eval`, bit for bit.

use super::*;

#[test]
fn an_evaluator_gives_evals_bits() {
    let kx = vec![-2.0, -0.5, 0.25, 1.0, 3.0];
    let ky = vec![1.0, -3.0, 0.5, 2.0, -1.0];
    let u = knot_positions(-1.0, 2.0, 6);
    let uy: Vec<f64> = u.iter().map(|x| (x * 1.3).sin()).collect();
    let mut curves = Vec::new();
    for extrapolate in [false, true] {
        for (kind, curve) in [
            (
                ApproxKind::Pwl,
                Curve::Pwl {
                    knots_x: kx.clone(),
                    knots_y: ky.clone(),
                },
            ),
            (
                ApproxKind::Spline,
                Curve::CatmullRom {
                    knots_x: kx.clone(),
                    knots_y: ky.clone(),
                },
            ),
            (
                ApproxKind::Pwl,
                Curve::Pwl {
                    knots_x: u.clone(),
                    knots_y: uy.clone(),
                },
            ),
            (
                ApproxKind::Spline,
                Curve::CatmullRom {
                    knots_x: u.clone(),
                    knots_y: uy.clone(),
                },
            ),
            (
                ApproxKind::Parabolic,
                Curve::Polynomial {
                    coeffs: vec![0.5, -1.5, 2.0],
                },
            ),
            (
                ApproxKind::Parabolic,
                Curve::Polynomial {
                    coeffs: vec![0.5, -1.5, 2.0, 0.1, -0.01],
                },
            ),
        ] {
            let (lo, hi) = match &curve {
                Curve::Polynomial { .. } => (-1.5, 2.5),
                Curve::Pwl { knots_x, .. } | Curve::CatmullRom { knots_x, .. } => {
                    (knots_x[0], knots_x[knots_x.len() - 1])
                }
            };
            let a = Approx::new(kind, curve, lo, hi, extrapolate, FitStats::default())
                .expect("valid curve");
            curves.push(a.with_knot_value(1, 0.75));
            curves.push(a);
        }
    }
    curves.push(Approx::zero(ApproxKind::Linear));
    let mut xs: Vec<f64> = (0..4001).map(|i| -5.0 + i as f64 * 2.5e-3).collect();
    xs.extend(kx.iter().chain(&u).copied());
    xs.extend([
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        0.0,
        -0.0,
        1e300,
        -1e300,
    ]);
    for a in &curves {
        let e = a.evaluator();
        for &x in &xs {
            assert_eq!(e.eval(x).to_bits(), a.eval(x).to_bits(), "{a:?} at {x}");
        }
    }
}

#[test]
fn unusable_parts_are_refused_with_their_reason() {
    let stats = FitStats::default();
    let pwl = |knots_x: Vec<f64>| Curve::Pwl {
        knots_y: vec![0.0; knots_x.len()],
        knots_x,
    };
    let line = Curve::Polynomial {
        coeffs: vec![1.0, 2.0],
    };
    let e = Approx::new(ApproxKind::Linear, line.clone(), 2.0, 1.0, false, stats).unwrap_err();
    assert_eq!(
        e,
        CurveError::XRange {
            x_min: 2.0,
            x_max: 1.0
        }
    );
    assert_eq!(e.to_string(), "invalid x-range [2, 1]");
    let e = Approx::new(ApproxKind::Pwl, pwl(vec![0.0, 0.0]), 0.0, 1.0, false, stats);
    assert_eq!(
        e.unwrap_err().to_string(),
        "knot positions must be strictly increasing"
    );
    let a = Approx::new(
        ApproxKind::Spline,
        pwl(vec![0.0, 1.0]),
        0.0,
        1.0,
        false,
        stats,
    )
    .unwrap();
    assert_eq!(
        String::from(a.check().unwrap_err()),
        "the curve is of form pwl, which is not how a spline approximation is stored"
    );
    let close = pwl(vec![0.0, 1e-12, 1.0]);
    let a = Approx::new(ApproxKind::Pwl, close, 0.0, 1.0, false, stats).unwrap();
    assert!(matches!(a.check(), Err(CurveError::KnotsTooClose { .. })));
    let e = "cubic".parse::<ApproxKind>().unwrap_err();
    assert_eq!(
        e.to_string(),
        "unknown approximation \"cubic\": use linear, parabolic, pwl or spline"
    );
}

/// What a fit did not compute is written `null`, not a 0 that reads as a figure: the RMS
/// residual and R² of a curve over no point, the R² of one point; read back as 0 with the count
/// saying why, and a computed figure round-trips exactly.
#[test]
fn statistics_not_computed_are_written_null() {
    let none = FitStats::default();
    let one = FitStats {
        n: 1,
        rmse: 0.0,
        r2: 0.0,
    };
    let many = FitStats {
        n: 40,
        rmse: 0.125,
        r2: 0.731_234_567_890_123_4,
    };
    let text = |s: &FitStats| serde_json::to_string(s).unwrap();
    assert_eq!(text(&none), r#"{"n":0,"rmse":null,"r2":null}"#);
    assert_eq!(text(&one), r#"{"n":1,"rmse":0.0,"r2":null}"#);
    for s in [none, one, many] {
        let back: FitStats = serde_json::from_str(&text(&s)).unwrap();
        assert_eq!(back, s);
    }
    // An emptied set (a dead-band wider than every rate) is written so in a calibration.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    let log = crate::log::ingest::read_path(&path, &Default::default()).unwrap();
    let recipe = crate::models::recipe::Recipe {
        deadband_tdot: Some(0.1),
        ..Default::default()
    };
    let cal = crate::models::vakhrameev::fit(&log, &recipe.checked().unwrap())
        .unwrap()
        .calibration;
    let json = serde_json::to_value(&cal.k1_plus).unwrap();
    assert_eq!(
        json["stats"],
        serde_json::json!({"n": 0, "rmse": null, "r2": null})
    );
}
