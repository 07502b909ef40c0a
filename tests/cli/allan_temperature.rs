//! `allan` on a log whose temperature moves: the long-τ end of the curve holds the thermal
//! drift, so the rate random walk read there is the drift's. The truth is the simulator's run
//! with its drift left out (`--noise-only`: the same seed, the same noise samples), whose curve
//! shows no +½ region at all; and a log of known white noise and random walk whose temperature
//! is steady, or moves, as the test writes it.

use serde_json::Value;
use std::path::Path;

use crate::common;
use common::run::{driftlab, fails, ok, p};

fn simulate(dir: &Path, name: &str, extra: &[&str]) -> String {
    let out = p(dir, name);
    ok(&[
        &[
            "simulate",
            "--profile",
            "calibration",
            "--seed",
            "1",
            "--out",
            &out,
        ][..],
        extra,
    ]
    .concat());
    out
}

#[test]
fn a_chamber_runs_thermal_drift_is_not_written_as_kalibrs_random_walk() {
    let dir = tempfile::tempdir().unwrap();
    let chamber = simulate(dir.path(), "chamber.csv", &[]);
    let noise = simulate(dir.path(), "noise.csv", &["--noise-only"]);
    // The gyro's noise alone has no rate random walk: the +½ slope of the chamber run is the
    // drift's.
    let alone: Value = serde_json::from_str(&ok(&["allan", &noise, "--json"])).unwrap();
    assert!(alone["readouts"]["rrw"].is_null(), "{}", alone["readouts"]);
    let run = driftlab(&["allan", &chamber, "--json"]);
    assert!(run.status.success());
    let v: Value = serde_json::from_slice(&run.stdout).unwrap();
    assert!(v["readouts"]["rrw"]["value"].as_f64().is_some());
    // ... and allan says why it is no noise, on the terminal and in the JSON.
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(
        err.contains("warning: ")
            && err.contains("the temperature moves by 109.998 °C")
            && err.contains("rate random walk (+½ line)"),
        "{err}"
    );
    let t = &v["temperature"];
    assert_eq!(t["moves"], true);
    assert!((t["span_c"].as_f64().unwrap() - 110.0).abs() < 0.01, "{t}");
    assert_eq!(v["kalibr"]["temperature_moves"]["moves"], true);
    // Kalibr's file is refused, naming the temperature and the option that writes it anyway.
    let yaml = dir.path().join("imu.yaml");
    let y = yaml.display().to_string();
    let e = fails(&["allan", &chamber, "--kalibr", &y]);
    assert!(
        e.contains("the temperature moves by 109.998 °C (-49.999 … 59.999 °C)")
            && e.contains("gyroscope_random_walk (τ 1024 … 8192 s) would be read off +½ lines")
            && e.contains("--allow-moving-temperature")
            && e.contains("not written"),
        "{e}"
    );
    assert!(!yaml.exists());
    // Asked for, it is written, and the file says what its random walk is.
    ok(&[
        "allan",
        &chamber,
        "--kalibr",
        &y,
        "--allow-moving-temperature",
    ]);
    let text = std::fs::read_to_string(&yaml).unwrap();
    assert!(
        text.contains("# WARNING: the temperature of the log moves by 109.998 degC")
            && text.contains("gyroscope_random_walk on tau 1024 .. 8192 s"),
        "{text}"
    );
    assert!(text.contains("\ngyroscope_random_walk: "), "{text}");
    // The permission names what it is for.
    let e = fails(&["allan", &chamber, "--allow-moving-temperature"]);
    assert!(e.contains("give --kalibr OUT.yaml"), "{e}");
}

/// The 20 Hz IMU of known noise (`tests/common/imu.rs`, written at 25 °C), its temperature
/// rewritten as `temp(t)`.
fn imu_at(path: &Path, temp: impl Fn(f64) -> f64) {
    let text = common::imu::imu_csv(
        7200.0,
        (2e-4, 2e-5),
        (2e-3, 2e-4),
        [1.0, 1.0, 1.0],
        "accel_{}_m_s2",
        1.0,
    );
    let mut out = String::new();
    for (i, line) in text.lines().enumerate() {
        if i == 0 {
            out.push_str(line);
        } else {
            let mut f: Vec<String> = line.split(',').map(str::to_string).collect();
            assert_eq!(f[4], "25.0");
            f[4] = format!("{:.3}", temp(f[0].parse().unwrap()));
            out.push_str(&f.join(","));
        }
        out.push('\n');
    }
    std::fs::write(path, out).unwrap();
}

#[test]
fn a_lab_within_its_two_degrees_is_steady_and_a_warm_up_past_them_is_not() {
    let dir = tempfile::tempdir().unwrap();
    let yaml = p(dir.path(), "imu.yaml");
    // Air conditioning cycling ±0.9 °C every 20 min, and one bad read of 85 °C: steady.
    let lab = dir.path().join("lab.csv");
    imu_at(&lab, |t| {
        if (t - 3000.0).abs() < 0.01 {
            85.0
        } else {
            22.0 + 0.9 * (t / 1200.0 * std::f64::consts::TAU).sin()
        }
    });
    let lab = lab.display().to_string();
    let run = driftlab(&["allan", &lab, "--kalibr", &yaml, "--json"]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(
        !String::from_utf8(run.stderr)
            .unwrap()
            .contains("temperature moves")
    );
    let v: Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(v["temperature"]["moves"], false, "{}", v["temperature"]);
    assert!(!std::fs::read_to_string(&yaml).unwrap().contains("WARNING"));
    // The same noise while the IMU warms up by 3 °C: the random walks are refused.
    let warm = dir.path().join("warm.csv");
    imu_at(&warm, |t| 25.0 + 3.0 * (1.0 - (-t / 900.0).exp()));
    let warm = warm.display().to_string();
    let refused = p(dir.path(), "warm.yaml");
    let e = fails(&["allan", &warm, "--kalibr", &refused]);
    assert!(
        e.contains("the temperature moves by")
            && e.contains("accelerometer_random_walk (τ ")
            && e.contains("gyroscope_random_walk (τ ")
            && e.contains("--allow-moving-temperature"),
        "{e}"
    );
    assert!(!Path::new(&refused).exists());
}
