//! The nineteenth attack's findings about commands: `calibrate --save-recipe` wrote a
//! Vakhrameev recipe for a calibration of another model; `allan --axes gx --kalibr` wrote
//! Kalibr's values from the axes it was told to leave out; a calibration of a DataFlash log's
//! second IMU was exported to ArduPilot as the first.

use crate::common::drone::{DataFlashImu, data_dir, dataflash};
use crate::common::run::{driftlab, fails, ok, p, sample};
use std::collections::HashMap;

// ------------------------------------------------------------------ helpers

/// The JSON file at `path`.
fn json(path: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// `NAME VALUE` lines of an ArduPilot parameter file.
fn parm(text: &str) -> HashMap<String, f64> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty())
        .map(|l| {
            let (k, v) = l.split_once(' ').unwrap();
            (k.to_string(), v.parse::<f64>().unwrap())
        })
        .collect()
}

/// `key: value  # comment` lines of a YAML file, as text.
fn yaml(text: &str) -> HashMap<String, String> {
    text.lines()
        .filter(|l| !l.trim_start().starts_with('#') && l.contains(':'))
        .map(|l| {
            let body = l.split('#').next().unwrap();
            let (k, v) = body.split_once(':').unwrap();
            (k.trim().to_string(), v.trim().to_string())
        })
        .collect()
}

// ------------------------------------------------------------------ 1. --save-recipe of a model

/// `--save-recipe` with a model a recipe cannot hold is refused before anything is read or
/// written, naming the option and the model: `--model poly-t` (the recipe made a Vakhrameev
/// calibration again), `--model custom` with its terms and lag, and a unit's `--axis-model
/// gz=poly-t` (refused for `--axis-recipe` already, not for `--axis-model`). Neither the
/// calibration nor the recipe is written.
#[test]
fn save_recipe_is_refused_for_a_model_the_recipe_cannot_hold() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (cal, recipe) = (p(d, "cal.json"), p(d, "recipe.json"));
    let log = sample("calibration.csv");
    let unit_log = sample("imu3-calibration.csv");
    let cases: [(&str, Vec<&str>, &[&str]); 3] = [
        (
            log.as_str(),
            vec!["--model", "poly-t"],
            &["--save-recipe", "model poly-t (--model poly-t)"],
        ),
        (
            log.as_str(),
            vec!["--model", "custom", "--terms", "1,T,Tdot", "--lag", "300"],
            &[
                "--save-recipe",
                "model custom (--model custom --terms 1,T,Tdot with its --lag)",
            ],
        ),
        (
            unit_log.as_str(),
            vec!["--axis-model", "gz=poly-t"],
            &["--save-recipe", "model poly-t (--axis-model gz=poly-t)"],
        ),
    ];
    for (log, options, said) in cases {
        let mut args = vec!["calibrate", log, "-o", &cal, "--save-recipe", &recipe];
        args.extend(options.iter().copied());
        let err = fails(&args);
        for s in said {
            assert!(err.contains(s), "{options:?}: {err}");
        }
        assert!(err.contains("vakhrameev"), "{options:?}: {err}");
        assert!(!std::path::Path::new(&cal).exists(), "{options:?}");
        assert!(!std::path::Path::new(&recipe).exists(), "{options:?}");
    }
}

/// Vakhrameev's recipe is still saved, and `--recipe` of it makes Vakhrameev's calibration
/// with the option given at first (`--k0 linear`) in it.
#[test]
fn save_recipe_of_vakhrameevs_model_still_reruns_its_calibration() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (cal, recipe, again) = (p(d, "cal.json"), p(d, "recipe.json"), p(d, "again.json"));
    let log = sample("calibration.csv");
    ok(&[
        "calibrate",
        &log,
        "-o",
        &cal,
        "--k0",
        "linear",
        "--save-recipe",
        &recipe,
    ]);
    assert_eq!(json(&recipe)["k0"]["kind"], "linear");
    ok(&["calibrate", &log, "-o", &again, "--recipe", &recipe]);
    let again = json(&again);
    assert_eq!(again["model"], "vakhrameev");
    assert_eq!(again["calibration"]["k0"]["kind"], "linear");
}

// ------------------------------------------------------------------ 2. Kalibr of the axes chosen

/// A 20 Hz IMU at rest whose gyro y is 1.5 times as noisy as x, z 0.8 times
/// (`tests/common/imu.rs`): `allan --axes gyro_x --kalibr` (and `--rate-col gyro_x_rad_s`)
/// gives Kalibr x's noise density, the one the IMU was made with, read off gyro_x (it gave
/// y's, 1.5 times it); `--axes gyro_x,gyro_z` the noisier of those two, x.
#[test]
fn kalibr_takes_its_gyro_values_from_the_axes_analysed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = p(d, "imu.csv");
    let (gyro, accel) = ((2e-4, 2e-5), (2e-3, 2e-4));
    std::fs::write(
        &log,
        crate::common::imu::imu_csv(7200.0, gyro, accel, [1.0, 1.5, 0.8], "accel_{}_m_s2", 1.0),
    )
    .unwrap();
    let chosen: [&[&str]; 3] = [
        &["--axes", "gyro_x"],
        &["--rate-col", "gyro_x_rad_s"],
        &["--axes", "gyro_x,gyro_z"],
    ];
    for options in chosen {
        let out_path = p(d, "imu.yaml");
        let mut args = vec!["allan", &log, "--kalibr", &out_path, "--json"];
        args.extend_from_slice(options);
        let out = driftlab(&args);
        assert!(
            out.status.success(),
            "{options:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let text = std::fs::read_to_string(&out_path).unwrap();
        let density: f64 = yaml(&text)["gyroscope_noise_density"].parse().unwrap();
        // The white-noise line rests on many octaves: within 10 % of the truth, and y's
        // 1.5 times it is far outside.
        assert!(
            (density / gyro.0 - 1.0).abs() < 0.10,
            "{options:?}: {density} for {}",
            gyro.0
        );
        for key in ["noise_density", "random_walk"] {
            assert_eq!(
                j["kalibr"]["gyroscope"][key]["value"]["axis"], "gyro_x",
                "{options:?} {key}"
            );
        }
        assert!(
            !text.contains("gyro_y") && !text.contains("gyro_z"),
            "{text}"
        );
        std::fs::remove_file(&out_path).unwrap();
    }
}

// ------------------------------------------------------------------ 3. the IMU of a drone log

/// Gyro drift of IMU `instance` in the crafted log, rad/s: a line in T with each axis's slope.
fn slopes(instance: u8) -> [f64; 3] {
    match instance {
        0 => [5.0e-4, 6.0e-4, 7.0e-4],
        _ => [1.0e-4, -2.0e-4, 3.0e-4],
    }
}

/// Three hours at 1 Hz of a DataFlash log of IMUs I=0 and I=1 warmed from 10 to 60 °C and
/// cooled again, each gyro axis drifting `0.01 + slope·(T − 35)` rad/s ([`slopes`]), IMU 1 a
/// degree warmer.
fn two_imus() -> Vec<u8> {
    let mut messages = Vec::new();
    for k in 0..3 * 3600u64 {
        let t = 35.0 - 25.0 * (2.0 * std::f64::consts::PI * k as f64 / 10_800.0).cos();
        for instance in [0u8, 1] {
            let temp = t + f64::from(instance);
            let s = slopes(instance);
            messages.push(DataFlashImu {
                time_us: 100_000_000 + k * 1_000_000 + u64::from(instance),
                instance,
                gyro: [0, 1, 2].map(|a| (0.01 + s[a] * (temp - 35.0)) as f32),
                temp_c: temp as f32,
            });
        }
    }
    dataflash(&messages)
}

/// `INS_TCALn_GYR1_*` against the slopes the IMU was made with: ArduPilot's order-1
/// coefficient around 35 °C, scaled by 10⁶.
fn assert_slopes(p: &HashMap<String, f64>, n: usize, instance: u8) {
    for (a, axis) in ["X", "Y", "Z"].iter().enumerate() {
        let truth = slopes(instance)[a] * 1e6;
        let got = p[&format!("INS_TCAL{n}_GYR1_{axis}")];
        assert!(
            (got - truth).abs() < 1e-3 * truth.abs(),
            "INS_TCAL{n}_GYR1_{axis}: {got} for {truth}"
        );
    }
}

/// A calibration of a DataFlash log's gyro records the log's gyro and its `IMU` instance
/// (`source.instance`), and `export --format ardupilot-parm` writes it to that IMU's
/// `INS_TCALn` (n = I + 1) with a note: IMU I=1 (`--gyro 1`) as `INS_TCAL2` (it wrote
/// `INS_TCAL1` without a word), IMU I=0 as `INS_TCAL1`, each with its own drift. `--imu 1`
/// still writes `INS_TCAL1`, and says it was fitted on IMU 2.
#[test]
fn a_dataflash_calibration_is_exported_to_the_imu_it_was_fitted_on() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = p(d, "two_imus.bin");
    std::fs::write(&log, two_imus()).unwrap();
    for (gyro, instance) in [("1", 1u8), ("0", 0)] {
        let cal = p(d, &format!("cal{gyro}.json"));
        ok(&[
            "calibrate",
            &log,
            "--gyro",
            gyro,
            "--model",
            "poly-t",
            "-o",
            &cal,
        ]);
        let recorded = &json(&cal)["source"]["instance"];
        assert_eq!(recorded["index"], u64::from(instance), "{recorded}");
        assert_eq!(recorded["dataflash_imu"], u64::from(instance), "{recorded}");

        let out = driftlab(&["export", "--format", "ardupilot-parm", &cal]);
        assert!(out.status.success(), "{out:?}");
        let (text, err) = (
            String::from_utf8(out.stdout).unwrap(),
            String::from_utf8(out.stderr).unwrap(),
        );
        let n = usize::from(instance) + 1;
        let params = parm(&text);
        assert_eq!(params[&format!("INS_TCAL{n}_ENABLE")], 1.0, "{text}");
        assert_eq!(
            params.keys().filter(|k| k.starts_with("INS_TCAL")).count(),
            params
                .keys()
                .filter(|k| k.starts_with(&format!("INS_TCAL{n}_")))
                .count(),
            "one IMU's parameters: {text}"
        );
        assert_slopes(&params, n, instance);
        let said =
            format!("INS_TCAL{n}: the calibration was fitted on IMU {n} (DataFlash I={instance})");
        assert!(err.contains(&said), "{err}");
    }

    // --imu chooses, and the note names the IMU it was fitted on.
    let cal = p(d, "cal1.json");
    let out = driftlab(&["export", "--format", "ardupilot-parm", &cal, "--imu", "1"]);
    assert!(out.status.success(), "{out:?}");
    let params = parm(&String::from_utf8(out.stdout).unwrap());
    assert_slopes(&params, 1, 1);
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("written as IMU 1 (INS_TCAL1) as asked")
            && err.contains("fitted on IMU 2 (DataFlash I=1)"),
        "{err}"
    );
}

/// A calibration that records no DataFlash IMU (a file written before the record, or one of
/// a CSV) loads as before and is written as `INS_TCAL1` with a note that says so; an IMU
/// ArduPilot does not calibrate is refused naming `--imu`.
#[test]
fn a_calibration_without_an_imu_is_written_as_the_first_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = p(d, "two_imus.bin");
    std::fs::write(&log, two_imus()).unwrap();
    let cal = p(d, "cal.json");
    ok(&[
        "calibrate",
        &log,
        "--gyro",
        "1",
        "--model",
        "poly-t",
        "-o",
        &cal,
    ]);
    let mut old = json(&cal);
    assert!(
        old["source"]
            .as_object_mut()
            .unwrap()
            .remove("instance")
            .is_some()
    );
    let old_path = p(d, "old.json");
    std::fs::write(&old_path, serde_json::to_string_pretty(&old).unwrap()).unwrap();
    let out = driftlab(&["export", "--format", "ardupilot-parm", &old_path]);
    assert!(out.status.success(), "{out:?}");
    let text = String::from_utf8(out.stdout).unwrap();
    assert_slopes(&parm(&text), 1, 1);
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("INS_TCAL1, the first IMU: the calibration records no DataFlash log's IMU"),
        "{err}"
    );
    assert!(text.contains("# note: INS_TCAL1, the first IMU"), "{text}");

    let err = fails(&["export", "--format", "ardupilot-parm", &cal, "--imu", "4"]);
    assert!(err.contains("not 4") && err.contains("--imu N"), "{err}");
}

/// The real ArduPilot sample holds IMUs I=0 and I=1 (its README): the log of each gyro records
/// the instance whose samples it holds, checked against the reference CSV's rows of that
/// instance (pymavlink's reading of the same file).
#[test]
fn the_real_dataflash_samples_gyro_records_its_imu_instance() {
    use driftlab::log::ingest::ReadOptions;
    use driftlab::log::read::{FormatChoice, read_drone_log};
    let Some(dir) = data_dir() else { return };
    let bin = dir.join(crate::common::drone::DATAFLASH);
    let reference = std::fs::read_to_string(bin.with_extension("gyro.csv")).unwrap();
    let rows: Vec<Vec<&str>> = reference
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    for gyro in [0usize, 1] {
        let choice = FormatChoice {
            gyro: Some(gyro),
            temp_from: None,
            ..FormatChoice::default()
        };
        let any = read_drone_log(&bin, &ReadOptions::default(), &choice, true)
            .unwrap()
            .unwrap();
        let instance = any.log.info.instance.unwrap();
        assert_eq!(instance.index, gyro);
        let i = instance.dataflash_imu.unwrap();
        let first = rows.iter().find(|r| r[2] == i.to_string()).unwrap();
        let x: f32 = first[3].parse().unwrap();
        let temp: f32 = first[6].parse().unwrap();
        let to_dph = 180.0 / std::f64::consts::PI * 3600.0;
        assert_eq!((any.log.omega_dph[0] / to_dph) as f32, x, "gyro {gyro}");
        assert_eq!(any.log.temp_c[0] as f32, temp, "gyro {gyro}");
    }
}
