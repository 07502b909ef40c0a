//! Knots placed by hand (issue 22, item 1): a curve fitted at given knot positions recovers the
//! curve its data were made from, the positions and hand-set values travel in the recipe and
//! the calibration file, bad positions are refused with their reason, and the knot edits the
//! workbench makes (drag, place, value, insert, remove) keep to their rules.

use driftlab::files::calibration;
use driftlab::models::approx::{
    self, Approx, ApproxKind, ApproxSpec, FitError, KnotEdit, KnotEditError, KnotsError,
};
use driftlab::models::recipe::Recipe;
use driftlab::models::vakhrameev;
use splines::{Interpolation, Key, Spline};
use std::path::Path;

fn grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

/// A piecewise-linear curve through `(kx, ky)`, written out apart from the engine.
fn pwl_truth(kx: &[f64], ky: &[f64], x: f64) -> f64 {
    let j = (1..kx.len() - 1).filter(|&j| kx[j] <= x).count();
    ky[j] + (ky[j + 1] - ky[j]) * (x - kx[j]) / (kx[j + 1] - kx[j])
}

/// The `splines` crate's Catmull-Rom curve through the knots, with the straight phantom end
/// keys the method describes.
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

fn placed(kind: ApproxKind, at: &[f64]) -> ApproxSpec {
    ApproxSpec {
        kind,
        knots: at.len(),
        at: Some(at.to_vec()),
        ..ApproxSpec::default()
    }
}

#[test]
fn a_pwl_fitted_at_given_knots_recovers_the_pwl_its_data_came_from() {
    // Ṫ-like positions, unequally spaced: the bend at 0.004 is where no even knot falls.
    let kx = [-0.02, -0.012, 0.004, 0.009, 0.03];
    let ky = [3.0, -1.5, 2.25, 0.5, 4.0];
    let xs = grid(-0.02, 0.03, 1001);
    let ys: Vec<f64> = xs.iter().map(|&x| pwl_truth(&kx, &ky, x)).collect();
    let a = approx::fit(&placed(ApproxKind::Pwl, &kx), &xs, &ys).unwrap();
    assert_eq!(a.knots().0, &kx[..], "the knots are where they were placed");
    for (j, (&got, &want)) in a.knots().1.iter().zip(&ky).enumerate() {
        assert!((got - want).abs() < 1e-6, "knot {j}: {got} vs {want}");
    }
    assert!(a.stats().rmse < 1e-6, "rmse {}", a.stats().rmse);
    // The same count of evenly spread knots cannot follow the bends.
    let even = approx::fit(
        &ApproxSpec {
            at: None,
            ..placed(ApproxKind::Pwl, &kx)
        },
        &xs,
        &ys,
    )
    .unwrap();
    assert!(even.stats().rmse > 1e-3, "rmse {}", even.stats().rmse);
}

#[test]
fn a_spline_fitted_at_given_knots_recovers_the_spline_its_data_came_from() {
    let kx = [0.0, 0.4, 1.1, 1.5, 3.0];
    let ky = [2.0, -1.0, 0.3, 4.0, 1.0];
    let s = crate_catmull_rom(&kx, &ky);
    let xs = grid(0.0, 3.0, 2000);
    // The crate has no segment starting at the last knot; the curve passes through it.
    let ys: Vec<f64> = xs.iter().map(|&x| s.sample(x).unwrap_or(ky[4])).collect();
    let a = approx::fit(&placed(ApproxKind::Spline, &kx), &xs, &ys).unwrap();
    assert_eq!(a.knots().0, &kx[..]);
    for (j, (&got, &want)) in a.knots().1.iter().zip(&ky).enumerate() {
        assert!((got - want).abs() < 1e-6, "knot {j}: {got} vs {want}");
    }
    for (&x, &y) in xs.iter().zip(&ys).step_by(41) {
        assert!((a.eval(x) - y).abs() < 1e-6, "at {x}");
    }
}

#[test]
fn knots_beyond_the_points_are_allowed_and_the_curve_holds_its_ends() {
    // Points on 0..1 only; knots from −1 to 3. The curve spans the knots; beyond them it holds
    // its end values (no extrapolation asked for).
    let xs = grid(0.0, 1.0, 200);
    let ys: Vec<f64> = xs.iter().map(|x| 1.0 + 2.0 * x).collect();
    let at = [-1.0, 0.0, 1.0, 3.0];
    let a = approx::fit(&placed(ApproxKind::Pwl, &at), &xs, &ys).unwrap();
    assert_eq!((a.x_min(), a.x_max()), (-1.0, 3.0));
    for &x in &[0.0, 0.25, 1.0] {
        assert!((a.eval(x) - (1.0 + 2.0 * x)).abs() < 1e-6, "at {x}");
    }
    // A knot with no point beside it continues its neighbours' line (the fit's smoothness
    // term), and the curve is held beyond the last knot.
    assert!((a.eval(3.0) - 7.0).abs() < 1e-3, "{}", a.eval(3.0));
    assert_eq!(a.eval(10.0), a.eval(3.0));
    // Knots inside the points: points beyond them weigh on the end knot, held flat.
    let inner = approx::fit(&placed(ApproxKind::Pwl, &[0.2, 0.5, 0.8]), &xs, &ys).unwrap();
    assert_eq!((inner.x_min(), inner.x_max()), (0.2, 0.8));
    assert_eq!(inner.eval(0.0), inner.eval(0.2));
}

#[test]
fn bad_positions_are_refused_with_their_reason() {
    let xs = grid(0.0, 1.0, 50);
    let ys = xs.clone();
    let refused = |at: Vec<f64>, knots: usize| {
        let spec = ApproxSpec {
            kind: ApproxKind::Spline,
            knots,
            at: Some(at),
            ..ApproxSpec::default()
        };
        let e = spec.check_knots().unwrap_err();
        // The fit refuses them alike (compared as text: a NaN is not equal to itself).
        assert_eq!(
            approx::fit(&spec, &xs, &ys).unwrap_err().to_string(),
            FitError::Knots(e.clone()).to_string()
        );
        e
    };
    assert_eq!(
        refused(vec![0.0, 0.5, 0.5, 1.0], 4),
        KnotsError::NotIncreasing {
            index: 2,
            previous: 0.5,
            value: 0.5
        }
    );
    let e = refused(vec![0.0, 0.7, 0.5, 1.0], 4);
    assert_eq!(
        e.to_string(),
        "at[2] = 0.5 does not come after at[1] = 0.7: positions must be strictly increasing"
    );
    assert!(matches!(
        refused(vec![0.0, f64::NAN, 1.0], 3),
        KnotsError::PositionNotFinite { index: 1, .. }
    ));
    assert!(matches!(
        refused(vec![0.0, 1.0, f64::INFINITY], 3),
        KnotsError::PositionNotFinite { index: 2, .. }
    ));
    assert_eq!(
        refused(vec![0.0, 0.5, 1.0], 4),
        KnotsError::PositionCount { got: 3, knots: 4 }
    );
    assert_eq!(
        approx::check_positions(&[0.5]).unwrap_err(),
        KnotsError::TooFew { got: 1 }
    );
    assert!(matches!(
        refused(vec![0.0, 1e-12, 1.0], 3),
        KnotsError::TooClose { index: 1, .. }
    ));
    assert!(matches!(
        refused(vec![-1e308, 0.0, 1e308], 3),
        KnotsError::Span { .. }
    ));
    // On a curve without knots, and values of another count.
    let linear = ApproxSpec {
        at: Some(vec![0.0, 1.0]),
        ..ApproxSpec::of(ApproxKind::Linear)
    };
    assert_eq!(
        linear.check_knots().unwrap_err(),
        KnotsError::NoKnots {
            kind: ApproxKind::Linear,
            list: "at"
        }
    );
    let values = ApproxSpec {
        values: Some(vec![1.0; 3]),
        ..ApproxSpec::of(ApproxKind::Pwl)
    };
    assert_eq!(
        values.check_knots().unwrap_err(),
        KnotsError::ValueCount { got: 3, knots: 5 }
    );
    // A recipe names the field.
    let recipe = Recipe {
        k2_minus: ApproxSpec {
            knots: 3,
            at: Some(vec![0.0, -1e-5, 1e-5]),
            ..ApproxSpec::of(ApproxKind::Pwl)
        },
        ..Recipe::default()
    };
    let e = recipe.validate().unwrap_err().to_string();
    assert!(
        e.starts_with("k2_minus.at: at[1] = -1e-5 does not come after at[0] = 0"),
        "{e}"
    );
}

/// A spec with knots placed and set by hand.
fn hand_spec() -> ApproxSpec {
    ApproxSpec {
        kind: ApproxKind::Spline,
        knots: 4,
        extrapolate: true,
        at: Some(vec![-0.0125, -0.002, 0.004, 0.0175]),
        values: Some(vec![10.5, -3.25, 7.0, 1e-3]),
    }
}

#[test]
fn positions_and_values_survive_a_recipe_and_calibration_round_trip() {
    let recipe = Recipe {
        k1_plus: hand_spec(),
        k2_minus: ApproxSpec {
            at: Some(vec![-2e-5, 0.0, 3e-6]),
            knots: 3,
            ..ApproxSpec::of(ApproxKind::Pwl)
        },
        ..Recipe::default()
    };
    let text = serde_json::to_string_pretty(&recipe).unwrap();
    assert!(text.contains("\"at\": ["), "{text}");
    let back: Recipe = serde_json::from_str(&text).unwrap();
    assert_eq!(back, recipe);
    // A recipe without them reads as before and writes no `at` or `values`.
    let plain = serde_json::to_string(&Recipe::default()).unwrap();
    assert!(
        !plain.contains("\"at\"") && !plain.contains("\"values\""),
        "{plain}"
    );
    let old: Recipe = serde_json::from_str(
        r#"{"k1_plus": {"kind": "spline", "knots": 5, "extrapolate": false}}"#,
    )
    .unwrap();
    assert_eq!(old.k1_plus.at, None);
    assert_eq!(old.k1_plus.values, None);

    // The calibration file holds them in its recipe, and its curves have them.
    let log = sample_log();
    let recipe = Recipe {
        k1_plus: ApproxSpec {
            values: None,
            ..hand_spec()
        },
        ..Recipe::default()
    };
    let cal = vakhrameev::fit(&log, &recipe.clone().checked().unwrap())
        .unwrap()
        .calibration;
    assert_eq!(cal.k1_plus.knots().0, &hand_spec().at.unwrap()[..]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cal.json");
    calibration::save(&path, &cal).unwrap();
    let loaded = calibration::load(&path).unwrap();
    assert_eq!(loaded, cal);
    assert_eq!(loaded.recipe.k1_plus.at, hand_spec().at);
    assert_eq!(calibration::read_recipe(&path).unwrap(), recipe);
}

fn sample_log() -> driftlab::Log {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    driftlab::log::ingest::read_path(&path, &Default::default()).unwrap()
}

#[test]
fn a_calibration_fits_at_the_recipes_positions_and_takes_its_values() {
    let log = sample_log();
    let even = Recipe {
        k1_plus: ApproxSpec {
            knots: 4,
            ..ApproxSpec::of(ApproxKind::Pwl)
        },
        ..Recipe::default()
    };
    let first = vakhrameev::fit(&log, &even.clone().checked().unwrap())
        .unwrap()
        .calibration;
    // Knot 1 moved a quarter of the way to knot 2: the fit puts it there, the values follow,
    // and K2+ (fitted after K1+) follows too.
    let mut at = first.k1_plus.knots().0.to_vec();
    at[1] += 0.25 * (at[2] - at[1]);
    let mut moved = even.clone();
    moved.k1_plus.at = Some(at.clone());
    let second = vakhrameev::fit(&log, &moved.clone().checked().unwrap())
        .unwrap()
        .calibration;
    assert_eq!(second.k1_plus.knots().0, &at[..]);
    assert_ne!(second.k1_plus.knots().1, first.k1_plus.knots().1);
    assert_ne!(second.k2_plus, first.k2_plus);
    assert_eq!(second.k1_minus, first.k1_minus, "the − set is not touched");
    // Values set by hand on top: the curve has them, K2+ refitted on what they leave.
    let values = vec![100.0, 150.0, 120.0, 90.0];
    moved.k1_plus.values = Some(values.clone());
    let third = vakhrameev::fit(&log, &moved.checked().unwrap())
        .unwrap()
        .calibration;
    assert_eq!(third.k1_plus.knots(), (&at[..], &values[..]));
    assert_ne!(third.k2_plus, second.k2_plus);
}

/// A fitted spline of 5 knots at 0, 1, 2, 3, 4 with values 0, 1, 4, 9, 16.
fn shown() -> (ApproxSpec, Approx) {
    let xs = grid(0.0, 4.0, 401);
    let ys: Vec<f64> = xs.iter().map(|x| x * x).collect();
    let spec = ApproxSpec {
        knots: 5,
        ..ApproxSpec::of(ApproxKind::Pwl)
    };
    let a = approx::fit(&spec, &xs, &ys).unwrap();
    (spec, a)
}

#[test]
fn a_knot_dragged_sideways_stays_between_its_neighbours() {
    let (spec, a) = shown();
    let drag = |x: f64, j: usize| spec.edit_knot(&a, KnotEdit::Drag { index: j, x }).unwrap();
    let s = drag(1.3, 2);
    assert_eq!(s.at.as_deref(), Some(&[0.0, 1.0, 1.3, 3.0, 4.0][..]));
    assert_eq!(s.values, None, "the values are fitted at the new positions");
    // Past a neighbour: stopped short of it, strictly between.
    let s = drag(-5.0, 2);
    let at = s.at.unwrap();
    assert!(at[2] > 1.0 && at[2] < 1.1, "{at:?}");
    let s = drag(50.0, 2);
    let at = s.at.unwrap();
    assert!(at[2] < 3.0 && at[2] > 2.9, "{at:?}");
    // An end knot is free outwards, not past its neighbour.
    assert_eq!(drag(-2.0, 0).at.unwrap()[0], -2.0);
    let at = drag(3.0, 0).at.unwrap();
    assert!(at[0] < 1.0, "{at:?}");
    assert_eq!(drag(9.0, 4).at.unwrap()[4], 9.0);
    // With values set by hand, the knot keeps its value as it moves.
    let hand = spec
        .edit_knot(&a, KnotEdit::Value { index: 2, y: 5.0 })
        .unwrap();
    let moved = hand
        .edit_knot(&a, KnotEdit::Drag { index: 2, x: 2.5 })
        .unwrap();
    assert_eq!(moved.values.as_ref().unwrap()[2], 5.0);
    assert_eq!(moved.at.as_ref().unwrap()[2], 2.5);
}

#[test]
fn typed_positions_values_insertions_and_removals_keep_to_their_rules() {
    let (spec, a) = shown();
    let fitted = a.knots().1.to_vec();
    // A typed position outside the neighbours is refused, named.
    let e = spec
        .edit_knot(&a, KnotEdit::Place { index: 1, x: 2.5 })
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "knot 2 goes strictly between its neighbours, 0 and 2; 2.5 is not"
    );
    let s = spec
        .edit_knot(&a, KnotEdit::Place { index: 1, x: 0.5 })
        .unwrap();
    assert_eq!(s.at.as_deref(), Some(&[0.0, 0.5, 2.0, 3.0, 4.0][..]));
    // A value set by hand: every knot keeps the value it shows, this one takes the new one.
    let s = spec
        .edit_knot(&a, KnotEdit::Value { index: 3, y: -7.0 })
        .unwrap();
    let mut want = fitted.clone();
    want[3] = -7.0;
    assert_eq!(s.values, Some(want));
    assert_eq!(s.at, None, "a value set by hand moves no knot");
    // Added: the others stay; beyond the ends too.
    let s = spec.edit_knot(&a, KnotEdit::Insert { x: 2.5 }).unwrap();
    assert_eq!(s.knots, 6);
    assert_eq!(s.at.as_deref(), Some(&[0.0, 1.0, 2.0, 2.5, 3.0, 4.0][..]));
    let s = spec.edit_knot(&a, KnotEdit::Insert { x: 6.0 }).unwrap();
    assert_eq!(s.at.unwrap()[5], 6.0);
    assert_eq!(
        spec.edit_knot(&a, KnotEdit::Insert { x: 3.0 }).unwrap_err(),
        KnotEditError::AtKnot { index: 3, x: 3.0 }
    );
    // With values set by hand, the new knot takes the curve's value there.
    let hand = spec
        .edit_knot(&a, KnotEdit::Value { index: 0, y: 1.0 })
        .unwrap();
    let s = hand.edit_knot(&a, KnotEdit::Insert { x: 2.5 }).unwrap();
    assert_eq!(s.values.as_ref().unwrap().len(), 6);
    assert!((s.values.unwrap()[3] - a.eval(2.5)).abs() < 1e-12);
    // Removed: the others stay; never below two.
    let s = spec.edit_knot(&a, KnotEdit::Remove { index: 1 }).unwrap();
    assert_eq!(
        (s.knots, s.at.as_deref()),
        (4, Some(&[0.0, 2.0, 3.0, 4.0][..]))
    );
    let two = approx::fit(
        &ApproxSpec {
            knots: 2,
            ..ApproxSpec::of(ApproxKind::Pwl)
        },
        &[0.0, 1.0, 2.0],
        &[0.0, 1.0, 2.0],
    )
    .unwrap();
    let e = ApproxSpec {
        knots: 2,
        ..ApproxSpec::of(ApproxKind::Pwl)
    }
    .edit_knot(&two, KnotEdit::Remove { index: 0 })
    .unwrap_err();
    assert_eq!(e, KnotEditError::TooFew);
    // No knot there, no knots at all, a curve fitted with other knots than asked.
    assert_eq!(
        spec.edit_knot(&a, KnotEdit::Remove { index: 9 })
            .unwrap_err(),
        KnotEditError::NoSuchKnot { index: 9, count: 5 }
    );
    assert!(matches!(
        ApproxSpec::of(ApproxKind::Linear).edit_knot(&a, KnotEdit::Insert { x: 1.0 }),
        Err(KnotEditError::NoKnots { .. })
    ));
    // Fitted with fewer knots than asked (the count is a maximum): the five shown are edited,
    // and the count becomes theirs.
    let adopted = ApproxSpec {
        knots: 7,
        ..spec.clone()
    }
    .edit_knot(&a, KnotEdit::Insert { x: 1.5 })
    .unwrap();
    assert_eq!(adopted.knots, 6);
    assert_eq!(adopted.at.as_ref().map(Vec::len), Some(6));
    // A curve of another kind (a fallback line) has no knots to edit.
    let line = approx::fit(
        &ApproxSpec::of(ApproxKind::Linear),
        &[0.0, 1.0, 2.0],
        &[0.0, 1.0, 2.0],
    )
    .unwrap();
    assert!(matches!(
        spec.edit_knot(&line, KnotEdit::Insert { x: 1.5 }),
        Err(KnotEditError::NotAsFitted { knots: 5, .. })
    ));
    assert!(matches!(
        spec.edit_knot(
            &a,
            KnotEdit::Drag {
                index: 1,
                x: f64::NAN
            }
        ),
        Err(KnotEditError::NotFinite(_))
    ));
}

#[test]
fn a_new_kind_keeps_the_hand_knots_and_a_new_count_spreads_them_again() {
    let s = hand_spec();
    assert_eq!(s.with_kind(ApproxKind::Pwl).at, s.at);
    assert_eq!(s.with_kind(ApproxKind::Pwl).values, s.values);
    assert!(!s.with_kind(ApproxKind::Linear).hand_knots());
    assert_eq!(s.with_knot_count(4), s);
    assert!(!s.with_knot_count(6).hand_knots());
    assert!(!s.without_hand_knots().hand_knots());
    // Field by field, then made consistent: lists of another count are dropped.
    let mut edited = s.clone();
    edited.knots = 7;
    assert!(!edited.consistent().hand_knots());
    assert_eq!(
        s.knots_text(),
        "4 knots placed by hand at -0.0125, -0.002, 0.004, 0.0175; values set by hand: 10.5, \
         -3.25, 7, 0.001"
    );
}

/// `Σw(y − f(x))²` and `Σw(y − ȳ)²` of a curve on points, weighted by x² (the drift
/// weighting the default recipe fits with), written out here apart from the engine.
fn r2_by_hand(f: &Approx, xs: &[f64], ys: &[f64]) -> f64 {
    let w: Vec<f64> = xs.iter().map(|x| x * x).collect();
    let sw: f64 = w.iter().sum();
    let mean = xs
        .iter()
        .zip(ys)
        .zip(&w)
        .map(|((_, y), w)| w * y)
        .sum::<f64>()
        / sw;
    let (mut res, mut tot) = (0.0, 0.0);
    for ((&x, &y), &w) in xs.iter().zip(ys).zip(&w) {
        res += w * (y - f.eval(x)).powi(2);
        tot += w * (y - mean).powi(2);
    }
    1.0 - res / tot
}

/// Knot values set by hand change the curve, so its R² and RMSE are the new curve's on the
/// points the fit saw: they kept the fitted curve's (a K1+ knot dragged to 1000 °/h per °C/s
/// still said R² 0.78, in the window and in the file).
#[test]
fn hand_set_values_carry_the_statistics_of_the_curve_they_make() {
    let log = sample_log();
    let even = Recipe {
        k1_plus: ApproxSpec {
            knots: 4,
            ..ApproxSpec::of(ApproxKind::Pwl)
        },
        k2_plus: ApproxSpec {
            knots: 4,
            ..ApproxSpec::of(ApproxKind::Pwl)
        },
        ..Recipe::default()
    };
    let fitted = vakhrameev::fit(&log, &even.clone().checked().unwrap()).unwrap();
    let mut values = fitted.calibration.k1_plus.knots().1.to_vec();
    values[3] = 1000.0;
    let mut edited = even.clone();
    edited.k1_plus.values = Some(values);
    let hand = vakhrameev::fit(&log, &edited.clone().checked().unwrap()).unwrap();
    let (k1, k1_fit) = (&hand.calibration.k1_plus, &fitted.calibration.k1_plus);
    let p = &hand.k1_plus_points;
    // The K1 points are the fit's (the hand values change no K1 point).
    assert_eq!(p, &fitted.k1_plus_points);
    let want = r2_by_hand(k1, &p.x, &p.y);
    assert!(
        (k1.stats().r2 - want).abs() < 1e-9,
        "{:?} {want}",
        k1.stats()
    );
    assert!(k1.stats().r2 < k1_fit.stats().r2 - 0.01, "{:?}", k1.stats());
    assert_eq!(k1.stats().n, k1_fit.stats().n);
    // K2+ refitted on what the hand K1 leaves: its statistics are of its own fit there.
    let q = &hand.k2_plus_points;
    let want = r2_by_hand(&hand.calibration.k2_plus, &q.x, &q.y);
    assert!((hand.calibration.k2_plus.stats().r2 - want).abs() < 1e-9);
    // K2+ values set by hand as well: judged on the points the hand K1 leaves.
    let mut both = edited.clone();
    let mut v2 = hand.calibration.k2_plus.knots().1.to_vec();
    v2[0] *= -3.0;
    both.k2_plus.values = Some(v2);
    let two = vakhrameev::fit(&log, &both.checked().unwrap()).unwrap();
    let q = &two.k2_plus_points;
    let want = r2_by_hand(&two.calibration.k2_plus, &q.x, &q.y);
    assert!(
        (two.calibration.k2_plus.stats().r2 - want).abs() < 1e-9,
        "{:?} {want}",
        two.calibration.k2_plus.stats()
    );
    assert!(two.calibration.k2_plus.stats().r2 < hand.calibration.k2_plus.stats().r2);
}
