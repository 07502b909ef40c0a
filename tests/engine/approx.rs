//! Approximations recover the curves their data were made from.
#![allow(clippy::needless_range_loop)] // tests index several columns by sample number

use driftlab::models::approx::{self, Approx, ApproxKind, ApproxSpec, Curve};
use splines::{Interpolation, Key, Spline};

fn grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

#[test]
fn linear_and_parabola_recovered_from_exact_data() {
    // Ṫ-like abscissa: small numbers far from 1, where an unscaled fit loses digits.
    let xs = grid(0.002, 0.03, 500);
    let ys: Vec<f64> = xs
        .iter()
        .map(|x| 41.0 - 900.0 * x + 12000.0 * x * x)
        .collect();
    let p = approx::fit(&ApproxSpec::of(ApproxKind::Parabolic), &xs, &ys).unwrap();
    let Curve::Polynomial { coeffs } = p.curve() else {
        panic!("parabola is a polynomial")
    };
    for (got, want) in coeffs.iter().zip([41.0, -900.0, 12000.0]) {
        assert!((got - want).abs() < 1e-6 * want.abs(), "{got} vs {want}");
    }
    assert!(p.stats().rmse < 1e-9 && p.stats().r2 > 1.0 - 1e-12 && p.stats().n == 500);

    let ys: Vec<f64> = xs.iter().map(|x| -0.4 + 25.0 * x).collect();
    let l = approx::fit(&ApproxSpec::of(ApproxKind::Linear), &xs, &ys).unwrap();
    let Curve::Polynomial { coeffs } = l.curve() else {
        panic!()
    };
    assert!((coeffs[0] + 0.4).abs() < 1e-12 && (coeffs[1] - 25.0).abs() < 1e-9);
}

#[test]
fn parabola_through_three_plateaus_is_exact() {
    // The paper's K0: a parabola through plateaus at 60, 20 and −50 °C.
    let t = [60.0, 20.0, -50.0];
    let w: Vec<f64> = t.iter().map(|t| 0.1 + 0.004 * t - 5e-5 * t * t).collect();
    let k0 = approx::fit(&ApproxSpec::of(ApproxKind::Parabolic), &t, &w).unwrap();
    for (ti, wi) in t.iter().zip(&w) {
        assert!((k0.eval(*ti) - wi).abs() < 1e-12);
    }
}

#[test]
fn pwl_recovered_from_data_of_its_own_knots() {
    let knots_y = [1.0, -2.0, 0.5, 3.0];
    let knots_x = grid(-1.0, 2.0, 4);
    let truth = |x: f64| {
        let j = (((x + 1.0) / 1.0).floor() as usize).min(2);
        let u = x - knots_x[j];
        knots_y[j] + (knots_y[j + 1] - knots_y[j]) * u
    };
    let xs = grid(-1.0, 2.0, 301);
    let ys: Vec<f64> = xs.iter().map(|&x| truth(x)).collect();
    let a = approx::fit(
        &ApproxSpec {
            kind: ApproxKind::Pwl,
            knots: 4,
            extrapolate: false,
            ..Default::default()
        },
        &xs,
        &ys,
    )
    .unwrap();
    let (kx, ky) = a.knots();
    for j in 0..4 {
        assert!((kx[j] - knots_x[j]).abs() < 1e-12);
        assert!(
            (ky[j] - knots_y[j]).abs() < 1e-6,
            "knot {j}: {} vs {}",
            ky[j],
            knots_y[j]
        );
    }
}

/// The reference curve, evaluated by the splines crate itself with the same phantom end keys.
fn crate_catmull_rom(kx: &[f64], ky: &[f64]) -> Spline<f64, f64> {
    let n = kx.len();
    let mut keys = vec![Key::new(
        2.0 * kx[0] - kx[1],
        2.0 * ky[0] - ky[1],
        Interpolation::CatmullRom,
    )];
    keys.extend(
        kx.iter()
            .zip(ky)
            .map(|(&x, &y)| Key::new(x, y, Interpolation::CatmullRom)),
    );
    keys.push(Key::new(
        2.0 * kx[n - 1] - kx[n - 2],
        2.0 * ky[n - 1] - ky[n - 2],
        Interpolation::CatmullRom,
    ));
    Spline::from_vec(keys)
}

#[test]
fn spline_basis_weights_reproduce_the_crate_evaluation() {
    let kx = [0.0, 0.4, 1.1, 1.5, 3.0];
    let ky = [2.0, -1.0, 0.3, 4.0, 1.0];
    let s = crate_catmull_rom(&kx, &ky);
    for x in grid(0.0, 2.999, 997) {
        let (first, w) = approx::knot_weights(ApproxKind::Spline, &kx, x);
        let ours: f64 = (0..4)
            .filter(|k| first + k < kx.len())
            .map(|k| w[k] * ky[first + k])
            .sum();
        let theirs = s.sample(x).unwrap();
        assert!((ours - theirs).abs() < 1e-12, "x {x}: {ours} vs {theirs}");
    }
}

#[test]
fn spline_recovered_from_data_of_its_own_knots() {
    let ky = [0.8, -0.3, 0.1, 0.9, 0.2, -0.5];
    let kx = grid(-0.02, 0.03, 6);
    let s = crate_catmull_rom(&kx, &ky);
    let xs = grid(-0.02, 0.03, 2000);
    // The crate has no segment starting at the last knot; the curve passes through it.
    let ys: Vec<f64> = xs.iter().map(|&x| s.sample(x).unwrap_or(ky[5])).collect();
    let a = approx::fit(
        &ApproxSpec {
            kind: ApproxKind::Spline,
            knots: 6,
            extrapolate: false,
            ..Default::default()
        },
        &xs,
        &ys,
    )
    .unwrap();
    for (j, want) in ky.iter().enumerate() {
        assert!(
            (a.knots().1[j] - want).abs() < 1e-6,
            "knot {j}: {} vs {want}",
            a.knots().1[j]
        );
    }
    for (&x, &y) in xs.iter().zip(&ys).step_by(37) {
        assert!((a.eval(x) - y).abs() < 1e-6);
    }
}

#[test]
fn outside_the_fitted_range_the_edge_value_is_held() {
    let xs = grid(1.0, 2.0, 50);
    let ys: Vec<f64> = xs.iter().map(|x| 3.0 * x).collect();
    for kind in ApproxKind::ALL {
        let a = approx::fit(&ApproxSpec::of(kind), &xs, &ys).unwrap();
        assert!((a.eval(10.0) - 6.0).abs() < 1e-6, "{kind} right edge");
        assert!((a.eval(-10.0) - 3.0).abs() < 1e-6, "{kind} left edge");
        let e = approx::fit(
            &ApproxSpec {
                extrapolate: true,
                ..ApproxSpec::of(kind)
            },
            &xs,
            &ys,
        )
        .unwrap();
        assert!(
            (e.eval(10.0) - 30.0).abs() < 1e-5,
            "{kind} extrapolated: {}",
            e.eval(10.0)
        );
    }
}

#[test]
fn an_empty_knot_interval_is_bridged_not_singular() {
    // Points only near both ends, as Ṫ points cluster at the ramp rates.
    let mut xs = grid(-1.0, -0.8, 50);
    xs.extend(grid(0.8, 1.0, 50));
    let ys: Vec<f64> = xs.iter().map(|x| 2.0 * x + 1.0).collect();
    for kind in [ApproxKind::Pwl, ApproxKind::Spline] {
        let a = approx::fit(
            &ApproxSpec {
                kind,
                knots: 7,
                extrapolate: false,
                ..Default::default()
            },
            &xs,
            &ys,
        )
        .unwrap();
        assert!(a.knots().1.iter().all(|v| v.is_finite()));
        assert!((a.eval(0.0) - 1.0).abs() < 1e-3, "{kind}: {}", a.eval(0.0));
    }
}

#[test]
fn too_few_points_is_an_error_not_a_panic() {
    let r = approx::fit(
        &ApproxSpec::of(ApproxKind::Parabolic),
        &[1.0, 2.0],
        &[1.0, f64::NAN],
    );
    assert!(matches!(
        r,
        Err(approx::FitError::TooFewPoints { got: 1, .. })
    ));
    assert!(
        approx::fit(
            &ApproxSpec {
                kind: ApproxKind::Spline,
                knots: 1,
                extrapolate: false,
                ..Default::default()
            },
            &[1.0; 5],
            &[1.0; 5]
        )
        .is_err()
    );
}

#[test]
fn stored_curves_are_validated_on_load() {
    let good = r#"{"kind":"pwl","x_min":0.0,"x_max":1.0,"extrapolate":false,
        "stats":{"n":3,"rmse":0.0,"r2":1.0},"curve":{"form":"pwl","knots_x":[0.0,1.0],"knots_y":[1.0,2.0]}}"#;
    let a: Approx = serde_json::from_str(good).unwrap();
    assert_eq!(a.eval(0.5), 1.5);
    let unordered = good.replace("[0.0,1.0]", "[1.0,0.0]");
    assert!(
        serde_json::from_str::<Approx>(&unordered)
            .unwrap_err()
            .to_string()
            .contains("increasing")
    );
    let nan = good.replace("[1.0,2.0]", "[1.0,null]");
    assert!(serde_json::from_str::<Approx>(&nan).is_err());
    let round: Approx = serde_json::from_str(&serde_json::to_string(&a).unwrap()).unwrap();
    assert_eq!(round, a);
}

#[test]
fn evaluation_equals_the_crate_on_equal_and_unequal_knots() {
    for kx in [
        vec![-0.02, -0.01, 0.0, 0.01, 0.02, 0.03],
        vec![0.0, 0.4, 1.1, 1.5, 3.0, 3.2],
    ] {
        let ky = [2.0, -1.0, 0.3, 4.0, 1.0, -0.5];
        let a = Approx::new(
            ApproxKind::Spline,
            Curve::CatmullRom {
                knots_x: kx.clone(),
                knots_y: ky.to_vec(),
            },
            kx[0],
            kx[5],
            false,
            Default::default(),
        )
        .unwrap();
        let s = crate_catmull_rom(&kx, &ky);
        let lin = Spline::from_vec(
            kx.iter()
                .zip(&ky)
                .map(|(&x, &y)| Key::new(x, y, Interpolation::Linear))
                .collect(),
        );
        let p = Approx::new(
            ApproxKind::Pwl,
            Curve::Pwl {
                knots_x: kx.clone(),
                knots_y: ky.to_vec(),
            },
            kx[0],
            kx[5],
            false,
            Default::default(),
        )
        .unwrap();
        for x in grid(kx[0], kx[5] - 1e-9, 1999) {
            let scale = 1.0 + s.sample(x).unwrap().abs();
            assert!(
                (a.eval(x) - s.sample(x).unwrap()).abs() < 1e-12 * scale,
                "spline at {x}"
            );
            assert!(
                (p.eval(x) - lin.sample(x).unwrap()).abs() < 1e-12 * scale,
                "pwl at {x}"
            );
        }
        assert_eq!(a.eval(kx[5]), ky[5]);
    }
}
