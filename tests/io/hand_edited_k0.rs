//! K0 edited by hand in a calibration file: its range against the plateaus it was fitted
//! through, and its curve against them and the statistics the file states. Each file starts as
//! one the code fitted and wrote, which loads; each edit is refused naming the field.

use super::hand_edited_calibrations::{body, edited, refused, vakhrameev_file};
use driftlab::files::calibration;
use driftlab::models;
use driftlab::models::approx::{ApproxKind, ApproxSpec};
use driftlab::models::recipe::{PlateauChoice, Recipe};
use driftlab::signal::plateau::PlateauRange;
use serde_json::{Value, json};

/// The indices of the lowest and the highest of `temps`.
fn lowest_and_highest(temps: &[f64]) -> (usize, usize) {
    let by = |a: &usize, b: &usize| temps[*a].total_cmp(&temps[*b]);
    let lo = (0..temps.len()).min_by(by).unwrap();
    let hi = (0..temps.len()).max_by(by).unwrap();
    (lo, hi)
}

/// K0 is fitted through the plateaus, so a fitted parabola spans exactly the lowest and the
/// highest plateau temperature. A hand-edited `k0.x_min`/`x_max` wider than the plateaus
/// claimed (and exported) K0 where nothing was measured; narrower, or a plateau's `temp_c`
/// moved outside it, contradicted the points it was fitted through (the twenty-first attack).
/// Each is refused naming the field and both values; the file as written loads.
#[test]
fn k0s_range_is_the_span_of_the_plateaus_it_was_fitted_through() {
    let dir = tempfile::tempdir().unwrap();
    let (cal, c) = vakhrameev_file(dir.path(), "cal.json", &Recipe::default());
    let temps: Vec<f64> = c.plateaus.iter().map(|p| p.temp_c).collect();
    let (lo_j, hi_j) = lowest_and_highest(&temps);
    // The sample log's set points: -50, 20 and 60 °C, two plateaus at 20.
    assert!(
        temps[lo_j] < -45.0
            && temps[hi_j] > 55.0
            && temps.iter().filter(|t| t.abs() < 45.0).count() >= 2,
        "{temps:?}"
    );
    assert_eq!((c.k0.x_min(), c.k0.x_max()), (temps[lo_j], temps[hi_j]));
    let set = |pointer: String, value: f64| {
        move |v: &mut Value| *body(v).pointer_mut(&pointer).unwrap() = json!(value)
    };
    let cases: Vec<(&str, String, f64, String, String)> = vec![
        // Wider than every plateau.
        (
            "wide_hi.json",
            "/k0/x_max".into(),
            100.0,
            "k0.x_max".into(),
            "is 100 °C, but the plateaus K0 was fitted through span".into(),
        ),
        (
            "wide_lo.json",
            "/k0/x_min".into(),
            -80.0,
            "k0.x_min".into(),
            "is -80 °C, but the plateaus K0 was fitted through span".into(),
        ),
        // Narrower: the plateaus at -50 and 20 °C are below it.
        (
            "narrow.json",
            "/k0/x_min".into(),
            30.0,
            "k0.x_min".into(),
            "3 of them outside k0's range 30 …".into(),
        ),
        // One plateau moved out of the range, above or below.
        (
            "plateau500.json",
            format!("/plateaus/{lo_j}/temp_c"),
            500.0,
            format!("plateaus[{lo_j}].temp_c"),
            "is 500 °C, outside k0's range".into(),
        ),
        (
            "plateau_below.json",
            format!("/plateaus/{hi_j}/temp_c"),
            -60.0,
            format!("plateaus[{hi_j}].temp_c"),
            "is -60 °C, outside k0's range".into(),
        ),
    ];
    for (name, pointer, value, field, why) in cases {
        refused(&edited(&cal, name, set(pointer, value)), &field, &why);
    }
}

/// A knot curve's K0 has its end knots at the plateaus' lowest and highest set points (the
/// mean of a set point's plateaus): that loads, and a range wider than the plateaus is
/// refused; knots placed by hand stand where the engineer put them, beyond the plateaus too,
/// and load.
#[test]
fn a_knot_k0_spans_its_plateaus_unless_its_knots_were_placed_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let pwl = |at: Option<Vec<f64>>| Recipe {
        k0: models::approx::ApproxSpec {
            knots: at.as_ref().map_or(3, Vec::len),
            at,
            ..models::approx::ApproxSpec::of(models::approx::ApproxKind::Pwl)
        },
        ..Recipe::default()
    };
    let (cal, c) = vakhrameev_file(dir.path(), "pwl.json", &pwl(None));
    let temps: Vec<f64> = c.plateaus.iter().map(|p| p.temp_c).collect();
    let (lo_j, hi_j) = lowest_and_highest(&temps);
    // Widened past the highest plateau, knot and range alike.
    let file = edited(&cal, "wide.json", |v| {
        let k0 = &mut body(v)["k0"];
        k0["x_max"] = json!(100.0);
        let last = k0["curve"]["knots_x"].as_array().unwrap().len() - 1;
        k0["curve"]["knots_x"][last] = json!(100.0);
    });
    refused(
        &file,
        "k0.x_max",
        "is 100 °C, but the plateaus K0 was fitted through span",
    );
    // Knots placed by hand 10 °C beyond the plateaus on either side.
    let at = vec![temps[lo_j] - 10.0, 0.0, temps[hi_j] + 10.0];
    let (_, c) = vakhrameev_file(dir.path(), "placed.json", &pwl(Some(at.clone())));
    assert_eq!((c.k0.x_min(), c.k0.x_max()), (at[0], at[2]));
}

/// The recipe with K0 of `kind` (`knots` of them for a knot curve).
fn k0_of(kind: ApproxKind, knots: usize) -> Recipe {
    Recipe {
        k0: ApproxSpec {
            knots,
            ..ApproxSpec::of(kind)
        },
        ..Recipe::default()
    }
}

/// K0's curve in a calibration file's JSON.
fn k0_curve(v: &mut Value) -> &mut Value {
    &mut body(v)["k0"]["curve"]
}

/// The root-mean-square of `miss`.
fn rms(miss: &[f64]) -> f64 {
    (miss.iter().map(|m| m * m).sum::<f64>() / miss.len() as f64).sqrt()
}

/// A K0 curve edited off the plateaus it was fitted through (a knot's value or place, a
/// polynomial's constant) still claimed the fit's rmse and R², in the file, the C header and
/// the report, and handed the firmware a bias error (the twenty-second attack: +5 °/h at 20 °C
/// under "rmse 0.0035"). Each is refused naming `k0`; the statistics alone edited are refused
/// too. The test makes the stated rmse again itself, from the plateaus in the file, before
/// any edit: it is the one a fit states.
#[test]
fn a_k0_curve_edited_off_its_plateaus_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (name, kind, knots) in [
        ("parabola.json", ApproxKind::Parabolic, 3),
        ("line.json", ApproxKind::Linear, 2),
        ("spline.json", ApproxKind::Spline, 3),
        ("pwl.json", ApproxKind::Pwl, 3),
    ] {
        let (cal, c) = vakhrameev_file(dir.path(), name, &k0_of(kind, knots));
        // The stated statistics are the curve's on the stored plateaus, made here.
        let miss: Vec<f64> = c
            .plateaus
            .iter()
            .map(|p| p.omega_dph - c.k0.eval(p.temp_c))
            .collect();
        let stats = c.k0.stats();
        assert_eq!(stats.n, c.plateaus.len(), "{name}");
        assert!(
            (stats.rmse - rms(&miss)).abs() <= 1e-12,
            "{name}: stated {} against {}",
            stats.rmse,
            rms(&miss)
        );
        // The curve 5 °/h off at a point: the constant, or the middle knot's value.
        let raised = edited(&cal, &format!("raised_{name}"), |v| {
            let c = k0_curve(v);
            let (field, at) = if c.get("coeffs").is_some() {
                ("coeffs", 0)
            } else {
                ("knots_y", 1)
            };
            let old = c[field][at].as_f64().unwrap();
            c[field][at] = json!(old + 5.0);
        });
        refused(
            &raised,
            "k0",
            "misses the plateaus it was fitted through by up to",
        );
        let e = calibration::load_unit(&raised).err().unwrap().to_string();
        assert!(e.contains("where the file states"), "{name}: {e}");
        // A knot moved in x, between its neighbours.
        if kind.has_knots() {
            let moved = edited(&cal, &format!("moved_{name}"), |v| {
                let c = k0_curve(v);
                let (a, b) = (
                    c["knots_x"][0].as_f64().unwrap(),
                    c["knots_x"][2].as_f64().unwrap(),
                );
                c["knots_x"][1] = json!(a + 0.9 * (b - a));
            });
            refused(&moved, "k0", "misses the plateaus it was fitted through");
        }
        // The statistics edited, not the curve: the rms, then R² alone.
        let better = edited(&cal, &format!("rmse_{name}"), |v| {
            body(v)["k0"]["stats"]["rmse"] = json!(stats.rmse / 10.0)
        });
        refused(&better, "k0", "misses the plateaus it was fitted through");
        if stats.computed_r2().is_some() {
            let r2 = edited(&cal, &format!("r2_{name}"), |v| {
                body(v)["k0"]["stats"]["r2"] = json!(0.5)
            });
            refused(&r2, "k0.stats.r2", "is 0.5, but K0's curve");
        }
    }
}

/// Knots whose values were set by hand (dragged in the workbench) state their statistics on
/// the plateaus too, so the file they are written in loads; and a K0 held constant (the
/// plateaus at one temperature) states the spread of its points, not 0.
#[test]
fn hand_set_knots_and_a_constant_k0_state_their_own_statistics() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = k0_of(ApproxKind::Pwl, 3);
    let (_, fitted) = vakhrameev_file(dir.path(), "fitted.json", &recipe);
    let knots_x = match fitted.k0.curve() {
        models::approx::Curve::Pwl { knots_x, .. } => knots_x.clone(),
        other => panic!("a pwl K0: {other:?}"),
    };
    let values: Vec<f64> = knots_x.iter().map(|_| 0.1).collect();
    let hand = Recipe {
        k0: ApproxSpec {
            at: Some(knots_x.clone()),
            values: Some(values),
            knots: knots_x.len(),
            ..ApproxSpec::of(ApproxKind::Pwl)
        },
        ..Recipe::default()
    };
    let (_, c) = vakhrameev_file(dir.path(), "hand.json", &hand);
    let miss: Vec<f64> = c.plateaus.iter().map(|p| p.omega_dph - 0.1).collect();
    assert!((c.k0.stats().rmse - rms(&miss)).abs() <= 1e-12);
    // The two plateaus at 20 °C alone: K0 is their mean, with their spread as its rms.
    let at20: Vec<PlateauRange> = fitted
        .plateaus
        .iter()
        .filter(|p| (p.temp_c - 20.0).abs() < 1.0)
        .map(|p| p.range)
        .collect();
    assert_eq!(at20.len(), 2, "the sample log holds two plateaus at 20 °C");
    let one_temperature = Recipe {
        plateaus: PlateauChoice::Manual { ranges: at20 },
        ..Recipe::default()
    };
    let (_, c) = vakhrameev_file(dir.path(), "constant.json", &one_temperature);
    let omegas: Vec<f64> = c.plateaus.iter().map(|p| p.omega_dph).collect();
    let mean = omegas.iter().sum::<f64>() / omegas.len() as f64;
    assert!(
        (c.k0.eval(20.0) - mean).abs() <= 1e-12,
        "K0 is the plateaus' mean"
    );
    let miss: Vec<f64> = omegas.iter().map(|w| w - mean).collect();
    assert!(rms(&miss) > 0.0, "the two plateaus differ: {omegas:?}");
    assert!(
        (c.k0.stats().rmse - rms(&miss)).abs() <= 1e-12,
        "stated {} against {}",
        c.k0.stats().rmse,
        rms(&miss)
    );
}
