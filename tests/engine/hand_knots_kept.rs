//! Knots placed or values set by hand are kept or refused, never dropped: where the points
//! carry only a simpler curve than asked for (fewer temperatures than K0's knots, a set the
//! dead-bands leave empty), the fit is refused naming the field to change, by the batch fit
//! and the workbench's refit alike; where they carry it, the hand knots stand.

use driftlab::models::approx::{ApproxKind, ApproxSpec};
use driftlab::models::recipe::Recipe;
use driftlab::models::vakhrameev;
use driftlab::refit::{Pipeline, Request};
use std::path::Path;
use std::sync::Arc;

/// calibration.csv: four plateaus at three temperatures (−50, 20, 60 °C).
fn sample_log() -> driftlab::Log {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    driftlab::log::ingest::read_path(&path, &Default::default()).unwrap()
}

/// The batch fit's refusal and the workbench refit's, which must be the same.
fn refused(log: &driftlab::Log, recipe: &Recipe) -> String {
    let batch = vakhrameev::fit(log, &recipe.clone().checked().unwrap())
        .err()
        .unwrap_or_else(|| panic!("fitted: {recipe:?}"))
        .to_string();
    let live = Pipeline::new()
        .run(&Request {
            log: Arc::new(log.clone()),
            recipe: recipe.clone(),
            merit: Default::default(),
            validation: None,
        })
        .expect_err("the refit fitted")
        .to_string();
    assert_eq!(batch, live);
    batch
}

fn k0(spec: ApproxSpec) -> Recipe {
    Recipe {
        k0: spec,
        ..Recipe::default()
    }
}

#[test]
fn hand_knots_the_points_cannot_carry_are_refused_by_name() {
    let log = sample_log();
    // Four K0 knots placed by hand over three temperatures.
    let e = refused(
        &log,
        &k0(ApproxSpec {
            knots: 4,
            at: Some(vec![-60.0, -10.0, 30.0, 70.0]),
            ..ApproxSpec::of(ApproxKind::Pwl)
        }),
    );
    assert!(
        e.contains("k0.at: 4 knots placed by hand") && e.contains("only 3 temperatures"),
        "{e}"
    );
    // Four values set by hand, K0's knots at the plateaus' three temperatures.
    let e = refused(
        &log,
        &k0(ApproxSpec {
            knots: 4,
            values: Some(vec![1.0, 2.0, 3.0, 4.0]),
            ..ApproxSpec::of(ApproxKind::Pwl)
        }),
    );
    assert!(e.contains("k0.values: 4 knot values set by hand"), "{e}");
    // K1+ with knots and values by hand, in a set the dead-band empties.
    let e = refused(
        &log,
        &Recipe {
            deadband_tdot: Some(0.1),
            k1_plus: ApproxSpec {
                knots: 2,
                at: Some(vec![-0.01, 0.01]),
                values: Some(vec![10.0, 20.0]),
                ..ApproxSpec::of(ApproxKind::Pwl)
            },
            ..Recipe::default()
        },
    );
    assert!(
        e.contains("k1_plus.at: 2 knots placed by hand")
            && e.contains("no usable points")
            && e.contains("narrow the dead-bands"),
        "{e}"
    );
}

#[test]
fn hand_knots_the_points_carry_stand() {
    let log = sample_log();
    // Three K0 knots by hand, values by hand, at the three temperatures.
    let (at, values) = (vec![-50.0, 20.0, 60.0], vec![0.2, -0.1, 0.3]);
    let recipe = k0(ApproxSpec {
        knots: 3,
        at: Some(at.clone()),
        values: Some(values.clone()),
        ..ApproxSpec::of(ApproxKind::Pwl)
    });
    let cal = vakhrameev::fit(&log, &recipe.checked().unwrap())
        .unwrap()
        .calibration;
    assert_eq!(cal.k0.knots(), (&at[..], &values[..]));
    // The curve through them, apart from the engine, between the first two knots.
    let t = -15.0;
    let want = values[0] + (values[1] - values[0]) * (t - at[0]) / (at[1] - at[0]);
    assert!((cal.k0.eval(t) - want).abs() < 1e-12);
}

#[test]
fn knots_placed_beyond_a_chambers_reach_are_refused_by_name() {
    // A K0 knot at 1e300 °C made a calibration `report` could not draw.
    let e = k0(ApproxSpec {
        knots: 2,
        at: Some(vec![-1e300, 1e300]),
        ..ApproxSpec::of(ApproxKind::Pwl)
    })
    .checked()
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("k0.at[0]") && e.contains("beyond what a chamber reaches (-100 … 200 °C)"),
        "{e}"
    );
    // Ṫ beyond 30 °C/min, T̈ beyond that rate reversed in a minute.
    for (recipe, field) in [
        (
            Recipe {
                k1_minus: ApproxSpec {
                    knots: 3,
                    at: Some(vec![-0.4, 0.0, 0.6]),
                    ..ApproxSpec::of(ApproxKind::Pwl)
                },
                ..Recipe::default()
            },
            "k1_minus.at[2]",
        ),
        (
            Recipe {
                k2_plus: ApproxSpec {
                    knots: 2,
                    at: Some(vec![-0.02, 0.01]),
                    ..ApproxSpec::of(ApproxKind::Spline)
                },
                ..Recipe::default()
            },
            "k2_plus.at[0]",
        ),
    ] {
        let e = recipe.checked().unwrap_err().to_string();
        assert!(e.contains(field), "{field}: {e}");
    }
    // Within reach: taken.
    k0(ApproxSpec {
        knots: 2,
        at: Some(vec![-100.0, 200.0]),
        ..ApproxSpec::of(ApproxKind::Pwl)
    })
    .checked()
    .unwrap();
}

/// A calibration file whose K0 lies beyond the temperatures a log may hold (hand-edited: no fit
/// makes one) is refused when read, naming the field; it was applied and exported, and made a
/// report that could not draw its temperature axis.
#[test]
fn a_calibration_whose_k0_lies_beyond_any_log_is_refused_when_read() {
    let log = sample_log();
    let cal = vakhrameev::fit(&log, &Recipe::default().checked().unwrap())
        .unwrap()
        .calibration;
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.json");
    driftlab::files::calibration::save(&good, &cal).unwrap();
    driftlab::files::calibration::load(&good).expect("a fitted K0 is read");
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&good).unwrap()).unwrap();
    json["calibration"]["k0"]["x_max"] = serde_json::json!(500.0);
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    let e = driftlab::files::calibration::load(&bad)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("k0.x_max") && e.contains("beyond the temperatures a log may hold"),
        "{e}"
    );
}
