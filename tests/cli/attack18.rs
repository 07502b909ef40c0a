//! The eighteenth attack's findings about commands: `--recipe FILE --recipe-axis AXIS` told
//! every file it could not read that it held one recipe; a unit of one axis could be given
//! neither as `--recipe` nor with `--recipe-axis`.

use crate::common::drone::{DataFlashImu, dataflash};
use crate::common::run::{fails, ok, p, sample};

// ------------------------------------------------------------------ helpers

/// `imu3-calibration.csv`'s axis gy calibrated alone (`--axes gy`, a version-2 unit of one
/// axis) into `out`, with `more` options.
fn gy_unit(out: &str, more: &[&str]) {
    let log = sample("imu3-calibration.csv");
    let mut args = vec!["calibrate", &log, "--axes", "gy", "-o", out];
    args.extend_from_slice(more);
    ok(&args);
}

/// The JSON file at `path`.
fn json(path: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

// ------------------------------------------------------------------ 1. --recipe-axis's errors

/// `--recipe FILE --recipe-axis AXIS` says what is wrong with a file it cannot read (it said
/// of each that it was "no unit's calibration: it holds one recipe"): a missing file, a
/// unit's file cut short (with its line and column), a unit whose axis asks for a knot no
/// chamber reaches (with the field), a CSV log (line 1, column 1). Only a file that reads as
/// one recipe is told so.
#[test]
fn recipe_axis_names_what_is_wrong_with_a_file_it_cannot_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let unit = p(d, "gy.json");
    gy_unit(&unit, &[]);
    let log = sample("calibration.csv");
    let out = p(d, "cal.json");
    let refused = |file: &str| {
        fails(&[
            "calibrate",
            &log,
            "--recipe",
            file,
            "--recipe-axis",
            "gy",
            "-o",
            &out,
        ])
    };
    let one_recipe = "no unit's calibration";

    let missing = p(d, "missing.json");
    let err = refused(&missing);
    assert!(
        err.contains("missing.json") && !err.contains(one_recipe),
        "{err}"
    );

    // Cut short inside its first line after the header: serde's line and column of the end.
    let text = std::fs::read_to_string(&unit).unwrap();
    let cut = &text[..text.len() / 2];
    let (line, column) = (
        cut.lines().count(),
        cut.rsplit('\n').next().unwrap().chars().count(),
    );
    let short = p(d, "short.json");
    std::fs::write(&short, cut).unwrap();
    let err = refused(&short);
    assert!(
        err.contains("short.json")
            && err.contains(&format!("line {line} column {column}"))
            && !err.contains(one_recipe),
        "{err}"
    );

    let mut bad = json(&unit);
    bad["axes"][0]["calibration"]["recipe"]["k0"] =
        serde_json::json!({"kind": "pwl", "knots": 3, "at": [-300, 0, 50]});
    let bad_path = p(d, "bad.json");
    std::fs::write(&bad_path, bad.to_string()).unwrap();
    let err = refused(&bad_path);
    assert!(
        err.contains("bad.json")
            && err.contains("axes[gy].k0.at[0]")
            && err.contains("-300")
            && !err.contains(one_recipe),
        "{err}"
    );

    let err = refused(&sample("validation.csv"));
    assert!(
        err.contains("validation.csv")
            && err.contains("line 1 column 1")
            && !err.contains(one_recipe),
        "{err}"
    );

    let recipe = p(d, "recipe.json");
    std::fs::write(&recipe, r#"{"k0": {"kind": "linear"}}"#).unwrap();
    let err = refused(&recipe);
    assert!(
        err.contains(one_recipe) && err.contains("recipe.json"),
        "{err}"
    );
}

// ------------------------------------------------------------------ 2. a unit of one axis

/// The file `calibrate --axes gy` writes (a unit of one axis) is taken by `--recipe` as the
/// recipe of its one axis, and reproduces its calibration bit for bit: every coefficient,
/// statistic and the recipe of axis gy equal. `--recipe-axis gy` takes it too (it said the
/// file was a unit to the one, and no unit to the other).
#[test]
fn a_unit_of_one_axis_gives_its_recipe_back_to_recipe() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let first = p(d, "gyonly.json");
    // A recipe of its own (not the defaults), so that a recipe dropped on the way shows.
    let recipe = p(d, "r.json");
    std::fs::write(
        &recipe,
        r#"{"k0": {"kind": "spline", "knots": 5}, "k1_plus": {"kind": "parabolic"}}"#,
    )
    .unwrap();
    gy_unit(&first, &["--recipe", &recipe]);
    let again = p(d, "again.json");
    gy_unit(&again, &["--recipe", &first]);
    let calibration = |path: &str| json(path)["axes"][0]["calibration"].clone();
    let gy = calibration(&first);
    assert_eq!(gy["recipe"]["k0"]["kind"].as_str(), Some("spline"));
    assert_eq!(calibration(&again), gy);

    let by_axis = p(d, "by_axis.json");
    ok(&[
        "calibrate",
        &sample("calibration.csv"),
        "--recipe",
        &first,
        "--recipe-axis",
        "gy",
        "-o",
        &by_axis,
    ]);
    assert_eq!(
        json(&by_axis)["calibration"]["recipe"]["k0"],
        gy["recipe"]["k0"]
    );
}

// ------------------------------------------------------------------ 3. a recipe file's refusal

/// A recipe file's setting the engine refuses is refused naming the file (and, given by
/// `--axis-recipe`, the axis): it said only `k0.at[0]: -200 °C lies beyond …`. A setting is
/// named by its option (`filter_s (--filter)`) only when the option gave it, not when the file
/// did.
#[test]
fn a_recipe_files_refused_setting_names_the_file_or_the_option_that_gave_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = p(d, "cal.json");
    let log = sample("calibration.csv");
    let write = |name: &str, text: &str| {
        let path = p(d, name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let knot = write(
        "knot.json",
        r#"{"k0": {"kind": "pwl", "knots": 3, "at": [-200, 0, 50]}}"#,
    );
    let filter = write("filter.json", r#"{"filter_s": -5}"#);
    let plain = write("plain.json", "{}");

    let err = fails(&["calibrate", &log, "--recipe", &knot, "-o", &out]);
    assert!(err.contains(&format!("{knot}: k0.at[0]: -200 °C")), "{err}");
    let err = fails(&["calibrate", &log, "--recipe", &filter, "-o", &out]);
    assert!(
        err.contains(&format!("{filter}: filter_s: ")) && !err.contains("--filter"),
        "{err}"
    );
    let err = fails(&[
        "calibrate",
        &log,
        "--recipe",
        &plain,
        "--filter=-5",
        "-o",
        &out,
    ]);
    assert!(
        err.contains("filter_s (--filter): ") && !err.contains("plain.json"),
        "{err}"
    );

    // A value the file gives that only the fit refuses (a filter longer than the log) names
    // the file too, not the option.
    let long = write("long.json", r#"{"filter_s": 100000}"#);
    let err = fails(&["calibrate", &log, "--recipe", &long, "-o", &out]);
    assert!(
        err.contains(&format!(
            "{long}: filter_s: 100000 s is longer than the log"
        )) && !err.contains("--filter"),
        "{err}"
    );
    let err = fails(&["calibrate", &log, "--filter", "100000", "-o", &out]);
    assert!(err.contains("filter_s (--filter): 100000 s"), "{err}");

    let unit_log = sample("imu3-calibration.csv");
    let err = fails(&[
        "calibrate",
        &unit_log,
        "--axis-recipe",
        &format!("gy={knot}"),
        "-o",
        &out,
    ]);
    assert!(
        err.contains(&format!("--axis-recipe gy={knot}: k0.at[0]: -200 °C")),
        "{err}"
    );
}

// ------------------------------------------------------------------ 4. infinite temperatures

/// An ArduPilot DataFlash log of IMU 0 and IMU 1, 300 messages each one second apart; IMU 0's
/// temperature `t0(k)` at message k, IMU 1's rising 0.01 °C a message from 20 °C.
fn dataflash_two(t0: impl Fn(usize) -> f32) -> Vec<u8> {
    let messages: Vec<DataFlashImu> = (0..300usize)
        .flat_map(|k| {
            [(0u8, t0(k)), (1, 20.0 + 0.01 * k as f32)].map(|(instance, temp_c)| DataFlashImu {
                time_us: 100_000_000 + k as u64 * 1_000_000 + u64::from(instance),
                instance,
                gyro: [0.01, 0.0, 0.0],
                temp_c,
            })
        })
        .collect();
    dataflash(&messages)
}

/// A temperature of +inf is no reading: IMU 0 reading +inf throughout is listed without a
/// temperature (it read "temperature inf .. inf degC") and is not the default gyro, so
/// `convert` takes IMU 1 (it took IMU 0 and then dropped every sample); one reading +inf every
/// other sample is listed over its finite values (it read "20.00 .. inf degC").
#[test]
fn an_infinite_temperature_is_no_reading() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let all_inf = p(d, "inf.bin");
    std::fs::write(&all_inf, dataflash_two(|_| f32::INFINITY)).unwrap();
    let listing = ok(&["inspect", &all_inf]);
    assert!(!listing.contains("inf .."), "{listing}");
    let csv = p(d, "out.csv");
    ok(&["convert", &all_inf, "-o", &csv]);
    let temps: Vec<f64> = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
        .collect();
    assert_eq!(temps.len(), 300);
    // IMU 1's temperatures (column temp_c), as written into the log.
    assert!((temps[0] - 20.0).abs() < 1e-3 && (temps[299] - 22.99).abs() < 1e-3);

    let half = p(d, "half.bin");
    std::fs::write(
        &half,
        dataflash_two(|k| {
            if k % 2 == 1 {
                f32::INFINITY
            } else {
                30.0 + k as f32 / 100.0
            }
        }),
    )
    .unwrap();
    let listing = ok(&["inspect", &half]);
    assert!(
        listing.contains("temperature 30.00 .. 32.98 degC"),
        "{listing}"
    );
}

// ------------------------------------------------------------------ 5. bursts below a step

/// `simulate --bursts ON:EVERY` with a burst or a period shorter than the sampling step (1 s
/// for the calibration profile) is refused by name: 1e-9:1e-9 and 1e-300:1e-300 wrote a log
/// with samples lost at random-looking places. 1:1 (always logging) keeps every sample.
#[test]
fn bursts_shorter_than_a_sampling_step_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = p(d, "sim.csv");
    for bursts in ["1e-9:1e-9", "1e-300:1e-300", "0.5:10"] {
        let err = fails(&[
            "simulate",
            "--profile",
            "calibration",
            "--bursts",
            bursts,
            "-o",
            &out,
        ]);
        assert!(
            err.contains(&format!("--bursts {bursts}: a burst of "))
                && err.contains("sampling step of 1 s"),
            "{bursts}: {err}"
        );
        assert!(!std::path::Path::new(&out).exists());
    }
    let rows = |args: &[&str]| {
        ok(args);
        std::fs::read_to_string(&out).unwrap().lines().count()
    };
    let every = rows(&["simulate", "--profile", "calibration", "-o", &out]);
    let bursts = rows(&[
        "simulate",
        "--profile",
        "calibration",
        "--bursts",
        "1:1",
        "-o",
        &out,
    ]);
    assert_eq!(bursts, every);
}

// ------------------------------------------------------------------ 7. refinements stopped

/// Refinement passes that diverge are stopped (64-knot splines of the + set, 14 refinements
/// asked for: one runs); the calibration said 14 all the same, and so did its report. The
/// file now records the passes run on each set, a hand edit claiming more than the recipe's
/// is refused, and the report says both.
#[test]
fn refinements_stopped_short_are_recorded_in_the_calibration_and_its_report() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let recipe = p(d, "recipe.json");
    std::fs::write(
        &recipe,
        r#"{"k1_plus": {"kind": "spline", "knots": 64},
            "k2_plus": {"kind": "spline", "knots": 64}, "refinements": 14}"#,
    )
    .unwrap();
    let cal = p(d, "cal.json");
    let log = sample("calibration.csv");
    ok(&["calibrate", &log, "--recipe", &recipe, "-o", &cal]);
    let v = json(&cal);
    let c = &v["calibration"];
    assert_eq!(c["recipe"]["refinements"], 14);
    assert_eq!(c["resolved"]["refinements_run"], serde_json::json!([1, 14]));

    let out = p(d, "report");
    ok(&["report", &cal, &log, "--out", &out]);
    let html = std::fs::read_to_string(format!("{out}/report.html")).unwrap();
    assert!(
        html.contains("14 asked for; 1 run on the + set, 14 on the − set"),
        "{}",
        &html[html.find("refinement passes").unwrap_or(0)..][..300.min(html.len())]
    );

    // A file claiming more passes than its recipe asks for is refused, with the field.
    let edited = p(d, "edited.json");
    let mut claimed = v.clone();
    claimed["calibration"]["resolved"]["refinements_run"] = serde_json::json!([15, 14]);
    std::fs::write(&edited, serde_json::to_string_pretty(&claimed).unwrap()).unwrap();
    let err = fails(&["apply", &edited, &log, "-o", &p(d, "c.csv")]);
    assert!(err.contains("resolved.refinements_run"), "{err}");
}
