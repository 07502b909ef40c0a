//! The workbench session file: a session reopens exactly as it was left (log, mapping,
//! plateaus, every choice, knots moved by hand), and a malformed file is refused with a
//! message that says where.

use driftlab::files::session::{self, Coefficient, KnotEdits, LogRef, Session, ViewState};
use driftlab::log::ingest::{ColumnRef, ReadOptions};
use driftlab::models::approx::{ApproxKind, ApproxSpec};
use driftlab::models::recipe::{PlateauChoice, Recipe};
use driftlab::refit::{Pipeline, Request};
use driftlab::signal::plateau::PlateauRange;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name)
}

fn a_session(log: PathBuf) -> Session {
    let mut recipe = Recipe {
        gyro_id: "FOG-0007".into(),
        filter_s: 120.0,
        plateaus: PlateauChoice::Manual {
            ranges: vec![
                PlateauRange {
                    start_s: 3700.0,
                    end_s: 7200.0,
                },
                PlateauRange {
                    start_s: 14400.0,
                    end_s: 16800.0,
                },
                PlateauRange {
                    start_s: 28200.0,
                    end_s: 30600.0,
                },
            ],
        },
        ..Recipe::default()
    };
    recipe.k1_plus = ApproxSpec {
        kind: ApproxKind::Spline,
        knots: 5,
        extrapolate: false,
        values: Some(vec![30.0, 35.0, 40.0, 45.0, 50.0]),
        ..Default::default()
    };
    Session {
        log: Some(LogRef {
            path: log,
            read: ReadOptions {
                delimiter: Some(b','),
                rate_col: Some(ColumnRef::Name("omega_dph".into())),
                ..ReadOptions::default()
            },
            // A campaign's further runs: kept through a save and a load (made relative to the
            // session's folder and back).
            more_runs: vec![sample("validation.csv")],
            ..LogRef::default()
        }),
        // Averaged into 2-s bins: kept through a save and a load.
        validation: Some(LogRef {
            path: sample("validation.csv"),
            read: ReadOptions::default(),
            bin_s: Some(2.0),
            // A drone log's gyro and temperature source: kept through a save and a load.
            instance: driftlab::log::read::InstanceChoice {
                gyro: Some(2),
                temp_from: Some(driftlab::log::read::TempFrom::Accel),
            },
            more_runs: Vec::new(),
            // The accelerometer columns and unit chosen in the import view: kept through a
            // save and a load.
            accelerometers: driftlab::log::accel_axes::AccelAsk {
                columns: vec![ColumnRef::Index(4), ColumnRef::Name("acc_b".into())],
                unit: Some(driftlab::log::accel_axes::AccelUnit::MilliG),
            },
        }),
        recipe,
        knots: KnotEdits::default(),
        // The workbench judges with the recipe's filter; 15-minute windows.
        merit: driftlab::judge::metrics::MeritOptions {
            filter_s: 120.0,
            window_s: 900.0,
        },
        view: ViewState {
            time_range_s: Some([1000.0, 20000.0]),
            show_validation: true,
            axis: None,
        },
        axes: Vec::new(),
        accelerometers_off: false,
    }
}

#[test]
fn a_unit_session_is_version_2_and_loads_back_equal() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = a_session(sample("imu3-calibration.csv"));
    let mut gy = s.recipe.clone();
    gy.k0.kind = ApproxKind::Spline;
    gy.k0.knots = 4;
    s.axes = ["gx", "gy", "gz"]
        .iter()
        .map(|n| session::AxisChoices {
            name: n.to_string(),
            recipe: if *n == "gy" {
                gy.clone()
            } else {
                s.recipe.clone()
            },
            knots: KnotEdits::default(),
        })
        .collect();
    s.view.axis = Some("gy".into());
    // Its accelerometer axes turned off: kept through a save and a load.
    s.accelerometers_off = true;
    let path = dir.path().join("imu3.session.json");
    session::save(&path, &s).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"version\": 2"), "{text}");
    assert!(text.contains("\"accelerometers_off\": true"), "{text}");
    assert_eq!(session::load(&path).unwrap(), s);
    // Axes need version 2: a version-1 file that holds them is refused, naming them.
    let v1 = text.replace("\"version\": 2", "\"version\": 1");
    let e = session::from_json(&path, &v1).unwrap_err().to_string();
    assert!(e.contains("version-1") && e.contains("axes"), "{e}");
}

#[test]
fn a_saved_session_loads_back_equal() {
    let dir = tempfile::tempdir().unwrap();
    let s = a_session(sample("calibration.csv"));
    let path = dir.path().join("run7.session.json");
    session::save(&path, &s).unwrap();
    let back = session::load(&path).unwrap();
    assert_eq!(back, s);
    // It says what it is.
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"format\": \"driftlab-session\""));
    assert!(text.contains("\"version\": 1"));
}

#[test]
fn logs_beside_the_session_are_stored_relative_to_it() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("logs").join("run7.csv");
    std::fs::create_dir_all(log.parent().unwrap()).unwrap();
    std::fs::copy(sample("calibration.csv"), &log).unwrap();
    let path = dir.path().join("s.json");
    session::save(&path, &a_session(log.clone())).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"path\": \"logs/run7.csv\""), "{text}");
    // The folder moves as a whole: the session still finds its log.
    let moved = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(moved.path().join("logs")).unwrap();
    std::fs::copy(&log, moved.path().join("logs/run7.csv")).unwrap();
    std::fs::copy(&path, moved.path().join("s.json")).unwrap();
    let back = session::load(&moved.path().join("s.json")).unwrap();
    assert_eq!(back.log.unwrap().path, moved.path().join("logs/run7.csv"));
    // A log elsewhere keeps its absolute path.
    assert!(text.contains(&sample("validation.csv").display().to_string()));
}

#[test]
fn a_reopened_session_gives_the_same_calibration() {
    let dir = tempfile::tempdir().unwrap();
    let s = a_session(sample("calibration.csv"));
    let path = dir.path().join("s.json");
    session::save(&path, &s).unwrap();
    let run = |s: &Session| {
        let l = s.log.as_ref().unwrap();
        let log = Arc::new(driftlab::log::ingest::read_path(&l.path, &l.read).unwrap());
        let mut p = Pipeline::new();
        p.run(&Request {
            log,
            recipe: s.recipe.clone(),
            merit: s.merit,
            validation: None,
        })
        .unwrap()
        .calibration
    };
    let before = run(&s);
    let after = run(&session::load(&path).unwrap());
    assert_eq!(after.k0, before.k0);
    assert_eq!(after.k1_plus, before.k1_plus);
    assert_eq!(after.k2_plus, before.k2_plus);
    assert_eq!(after.plateaus, before.plateaus);
    // The knots moved by hand are the curve's knots.
    assert_eq!(after.k1_plus.knots().1, &[30.0, 35.0, 40.0, 45.0, 50.0][..]);
}

fn refused(text: &str) -> String {
    match session::from_json(Path::new("bad.json"), text) {
        Ok(_) => panic!("accepted: {text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn malformed_sessions_are_refused_with_a_reason() {
    let good = session::to_json(&a_session(sample("calibration.csv")));
    assert!(refused("{}").contains("no \"format\""));
    assert!(
        refused(r#"{"format": "driftlab-calibration", "version": 1}"#)
            .contains("expected \"driftlab-session\"")
    );
    assert!(refused(&good.replace("\"version\": 1", "\"version\": 9")).contains("version 9"));
    let unknown = good.replacen("\"recipe\": {", "\"recipe\": { \"colour\": \"red\",", 1);
    assert!(
        refused(&unknown).contains("colour"),
        "{}",
        refused(&unknown)
    );
    let bad_filter = good.replace("\"filter_s\": 120.0", "\"filter_s\": -1.0");
    assert!(refused(&bad_filter).contains("filter_s"));
    let truncated = &good[..good.len() / 2];
    assert!(refused(truncated).contains("bad.json"));
}

#[test]
fn a_sessions_figures_of_merit_and_knots_are_checked() {
    let good = session::to_json(&a_session(sample("calibration.csv")));
    let loaded = session::from_json(Path::new("s.json"), &good).unwrap();
    assert_eq!(loaded.merit.window_s, 900.0, "the session's window is kept");
    let edited = |edit: &dyn Fn(&mut serde_json::Value)| {
        let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
        edit(&mut v["session"]);
        v.to_string()
    };
    // A filter of the figures other than the recipe's: not what the workbench does.
    let e = refused(&edited(&|s| s["merit"]["filter_s"] = 50.0.into()));
    assert!(
        e.contains("merit.filter_s") && e.contains("recipe's filter_s (120 s)"),
        "{e}"
    );
    for w in [1e-300, 1e300, 0.0, -5.0] {
        let e = refused(&edited(&|s| s["merit"]["window_s"] = w.into()));
        assert!(e.contains("merit.window_s"), "{w}: {e}");
    }
    // No merit at all: the recipe's filter and 10-minute windows.
    let none = edited(&|s| {
        s.as_object_mut().unwrap().remove("merit");
    });
    let none = session::from_json(Path::new("s.json"), &none).unwrap();
    assert_eq!((none.merit.filter_s, none.merit.window_s), (120.0, 600.0));
    // Knots set by hand: finite and plausible, as many as the curve has.
    let e = refused(&edited(&|s| {
        s["recipe"]["k1_plus"]["values"][0] = 1e308.into()
    }));
    assert!(
        e.contains("k1_plus.values[0]") && e.contains("1e308"),
        "{e}"
    );
    let e = refused(&edited(&|s| {
        s["recipe"]["k1_plus"]["values"]
            .as_array_mut()
            .unwrap()
            .pop();
    }));
    assert!(
        e.contains("k1_plus.values") && e.contains("4 knot values given for 5 knots"),
        "{e}"
    );
    let e = refused(&edited(&|s| {
        s["recipe"]["k0"]["values"] = serde_json::json!([1.0, 2.0])
    }));
    assert!(
        e.contains("k0.values") && e.contains("parabolic curve has no knots"),
        "{e}"
    );
    // Knots placed by hand: strictly increasing, one per knot.
    let e = refused(&edited(&|s| {
        s["recipe"]["k1_plus"]["at"] = serde_json::json!([-1.0, -0.5, 0.0, 0.0, 1.0])
    }));
    assert!(
        e.contains("k1_plus.at") && e.contains("strictly increasing"),
        "{e}"
    );
    let e = refused(&edited(&|s| {
        s["recipe"]["k1_plus"]["at"] = serde_json::json!([-1.0, 1.0])
    }));
    assert!(
        e.contains("k1_plus.at") && e.contains("2 knot positions given for 5"),
        "{e}"
    );

    // A session written before the recipe held the values kept them beside it, in `knots`:
    // they are checked as they always were, and read into the recipe.
    let old = edited(&|s| {
        let values = s["recipe"]["k1_plus"]
            .as_object_mut()
            .unwrap()
            .remove("values")
            .unwrap();
        s["knots"] = serde_json::json!({ "k1_plus": values });
    });
    let loaded = session::from_json(Path::new("s.json"), &old).unwrap();
    assert_eq!(
        loaded.recipe.k1_plus.values,
        Some(vec![30.0, 35.0, 40.0, 45.0, 50.0])
    );
    assert!(loaded.knots.is_empty());
    assert!(!session::to_json(&loaded).contains("\"knots\": {"));
    let mut bad: serde_json::Value = serde_json::from_str(&old).unwrap();
    bad["session"]["knots"]["k1_plus"][0] = 1e308.into();
    let e = refused(&bad.to_string());
    assert!(e.contains("knots.k1_plus[0]") && e.contains("1e308"), "{e}");
    bad["session"]["knots"]["k1_plus"] = serde_json::json!([1.0, 2.0]);
    let e = refused(&bad.to_string());
    assert!(e.contains("knots.k1_plus") && e.contains("2 values"), "{e}");
}

#[test]
fn knot_edits_are_dropped_when_the_curve_changes() {
    let mut recipe = Recipe {
        k1_plus: ApproxSpec {
            kind: ApproxKind::Pwl,
            knots: 4,
            extrapolate: false,
            ..Default::default()
        },
        ..Recipe::default()
    };
    let mut k = KnotEdits::default();
    k.set(Coefficient::K1Plus, Some(vec![1.0; 4]));
    k.set(Coefficient::K2Minus, Some(vec![1.0; 4]));
    k.retain_matching(&recipe);
    assert!(k.get(Coefficient::K1Plus).is_some());
    assert!(
        k.get(Coefficient::K2Minus).is_none(),
        "K2− is linear: no knots to set"
    );
    recipe.k1_plus.knots = 6;
    k.retain_matching(&recipe);
    assert!(k.is_empty());
}

/// A session giving a coefficient's knot values both in its recipe and where older sessions
/// kept them, differently, is refused naming both (the older list was dropped unsaid); the same
/// values in both places, or the older place alone, are taken.
#[test]
fn knot_values_given_twice_and_differently_are_refused() {
    let good = session::to_json(&a_session(sample("calibration.csv")));
    let edited = |edit: &dyn Fn(&mut serde_json::Value)| {
        let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
        edit(&mut v["session"]);
        v.to_string()
    };
    let recipe_values = |s: &serde_json::Value| s["recipe"]["k1_plus"]["values"].clone();
    let good_json: serde_json::Value = serde_json::from_str(&good).unwrap();
    let own = recipe_values(&good_json["session"]);
    assert!(
        own.is_array(),
        "the sample session sets K1+'s values: {own}"
    );
    let other: Vec<f64> = own
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap() + 1.0)
        .collect();
    let e = refused(&edited(&|s| {
        s["knots"]["k1_plus"] = serde_json::json!(other.clone());
    }));
    assert!(
        e.contains("knots.k1_plus: knot values set both here")
            && e.contains("recipe.k1_plus.values"),
        "{e}"
    );
    let same = edited(&|s| s["knots"]["k1_plus"] = own.clone());
    session::from_json(Path::new("s.json"), &same).expect("the same values twice");
    let older = edited(&|s| {
        s["knots"]["k1_plus"] = own.clone();
        s["recipe"]["k1_plus"]["values"] = serde_json::Value::Null;
    });
    let loaded = session::from_json(Path::new("s.json"), &older).expect("the older place");
    assert_eq!(
        serde_json::json!(loaded.recipe.k1_plus.values.unwrap()),
        own,
        "moved into the recipe"
    );
}
