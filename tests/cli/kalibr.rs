//! Kalibr's IMU noise file from `driftlab allan --kalibr`, checked against an IMU simulated
//! with known noise: white rate noise of density N (the angle random walk) and a bias random
//! walk of K, in Kalibr's own definitions. A discrete sample of white noise of density N at
//! rate f is N·√f; a bias that random-walks with K steps by K·√Δt each sample.

use crate::common;

use common::run::{driftlab, fails, ok};
use std::collections::HashMap;
use std::path::PathBuf;

/// `seconds` of three gyro axes (rad/s) and three accelerometer axes (m/s²) at 20 Hz, each
/// axis `(N, K)` scaled by its factor (`tests/common/imu.rs`).
fn imu_csv(seconds: f64, gyro: (f64, f64), accel: (f64, f64), scale: [f64; 3]) -> String {
    crate::common::imu::imu_csv(seconds, gyro, accel, scale, "accel_{}_m_s2", 1.0)
}

/// `key: value  # comment` lines of a YAML file as numbers or text.
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

#[test]
fn kalibr_gets_the_noise_the_imu_was_made_with_from_its_noisiest_axis() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("imu.csv");
    // Gyro: N = 2e-4 rad/s/sqrt(Hz), K = 2e-5 rad/s^2/sqrt(Hz) (they cross near 17 s);
    // accelerometer: 2e-3 m/s^2/sqrt(Hz), 2e-4 m/s^3/sqrt(Hz). Axis y is 1.5 times noisier.
    let (gyro, accel) = ((2e-4, 2e-5), (2e-3, 2e-4));
    std::fs::write(&log, imu_csv(7200.0, gyro, accel, [1.0, 1.5, 0.8])).unwrap();
    let log = log.display().to_string();
    let out_path = dir.path().join("imu.yaml");
    let out = driftlab(&[
        "allan",
        &log,
        "--kalibr",
        &out_path.display().to_string(),
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let text = std::fs::read_to_string(&out_path).unwrap();
    let y = yaml(&text);
    let value = |k: &str| y[k].parse::<f64>().unwrap();
    // The white-noise line rests on many octaves of many terms; the random walk on the few
    // longest, whose σ scatters by tens of percent: the bounds are those spreads.
    for (key, truth, axis, tol) in [
        ("gyroscope_noise_density", 1.5 * gyro.0, "gyro_y", 0.10),
        ("gyroscope_random_walk", 1.5 * gyro.1, "gyro_y", 0.35),
        (
            "accelerometer_noise_density",
            1.5 * accel.0,
            "accel_y_m_s2",
            0.10,
        ),
        (
            "accelerometer_random_walk",
            1.5 * accel.1,
            "accel_y_m_s2",
            0.35,
        ),
    ] {
        let v = value(key);
        eprintln!(
            "{key}: {v:.4e} for {truth:.4e} ({:+.1}%)",
            100.0 * (v / truth - 1.0)
        );
        assert!((v / truth - 1.0).abs() < tol, "{key}: {v} for {truth}");
        // The same number in --json, and the axis and tau range named in the comment.
        let sensor = key.split('_').next().unwrap();
        let entry = if key.ends_with("noise_density") {
            &json["kalibr"][sensor]["noise_density"]["value"]
        } else {
            &json["kalibr"][sensor]["random_walk"]["value"]
        };
        assert_eq!(entry["value"].as_f64().unwrap(), v, "{key}");
        assert_eq!(entry["axis"], axis, "{key}");
        let lo = entry["region_tau_s"][0].as_f64().unwrap();
        let hi = entry["region_tau_s"][1].as_f64().unwrap();
        assert!(
            text.contains(&format!("{axis} axis")) && text.contains(&format!("tau {lo} .. {hi} s")),
            "{text}"
        );
    }
    assert_eq!(y["update_rate"], "20.0");
    // Every string scalar of the file is double-quoted.
    assert_eq!(y["rostopic"], "\"/imu0\"");
    assert_eq!(json["kalibr"]["update_rate_hz"], 20.0);
}

#[test]
fn a_log_too_short_for_the_random_walk_writes_no_kalibr_file_and_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("short.csv");
    std::fs::write(&log, imu_csv(60.0, (2e-4, 2e-5), (2e-3, 2e-4), [1.0; 3])).unwrap();
    let out_path = dir.path().join("imu.yaml");
    let e = fails(&[
        "allan",
        &log.display().to_string(),
        "--kalibr",
        &out_path.display().to_string(),
    ]);
    assert!(
        e.contains("gyroscope_random_walk") && e.contains("record longer"),
        "{e}"
    );
    assert!(!out_path.exists());
    // --json says the same with no number.
    let json: serde_json::Value =
        serde_json::from_str(&ok(&["allan", &log.display().to_string(), "--json"])).unwrap();
    let walk = &json["kalibr"]["gyroscope"]["random_walk"];
    assert!(walk["value"].is_null(), "{walk}");
    assert!(walk["note"].as_str().unwrap().contains("+1/2"), "{walk}");
    // --rostopic without a Kalibr file or --json is refused by name.
    let e = fails(&["allan", &log.display().to_string(), "--rostopic", "/imu"]);
    assert!(e.contains("--rostopic"), "{e}");
}

#[test]
fn a_ros_bag_gives_kalibr_its_topic() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/formats");
    if !dir.is_dir() {
        assert!(
            std::env::var_os("CI").is_none(),
            "the reference data {} is missing (CI is set, so this fails)",
            dir.display()
        );
        eprintln!("skipping: reference data {} is missing", dir.display());
        return;
    }
    for rel in [
        "ros1_bag/sparkfun_razor.bag",
        "ros2_mcap/sparkfun_razor_ros2.mcap",
    ] {
        let log = dir.join(rel).display().to_string();
        // The sample IMU has no thermometer: inspect lists its instances and says so.
        let out = driftlab(&["inspect", &log, "--json"]);
        let listing: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let topic = listing["instances"][0]["label"].clone();
        assert!(topic.as_str().unwrap().starts_with('/'), "{listing}");
        let json: serde_json::Value =
            serde_json::from_str(&ok(&["allan", &log, "--temp-from", "none", "--json"])).unwrap();
        assert_eq!(json["kalibr"]["rostopic"], topic, "{rel}");
        assert!(json["kalibr"]["accelerometer"].is_object(), "{rel}");
    }
}

#[test]
fn a_crafted_file_name_stays_inside_its_comment_and_a_crafted_topic_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    // A carriage return and a line feed in the log's name, as if to set a key of the file.
    let log = dir
        .path()
        .join("imu\r\naccelerometer_noise_density: 1.0e+9\r\n\u{1b}[2J\u{85}x.csv");
    std::fs::write(&log, imu_csv(7200.0, (2e-4, 2e-5), (2e-3, 2e-4), [1.0; 3])).unwrap();
    let out_path = dir.path().join("imu.yaml");
    // A topic no ROS graph can hold is refused by name, before anything is written.
    let crafted = "/imu\nupdate_rate: 1\r\"\\";
    let e = fails(&[
        "allan",
        &log.display().to_string(),
        "--kalibr",
        &out_path.display().to_string(),
        "--rostopic",
        crafted,
    ]);
    assert!(
        e.contains("a ROS topic holds letters, digits, _ and / alone"),
        "{e}"
    );
    assert!(!out_path.exists());
    let topic = "/imu0/data_raw";
    ok(&[
        "allan",
        &log.display().to_string(),
        "--kalibr",
        &out_path.display().to_string(),
        "--rostopic",
        topic,
    ]);
    let text = std::fs::read_to_string(&out_path).unwrap();
    let starting = |key: &str| text.lines().filter(|l| l.starts_with(key)).count();
    assert_eq!(starting("accelerometer_noise_density:"), 1, "{text}");
    assert_eq!(starting("update_rate:"), 1, "{text}");
    assert!(!text.contains(['\r', '\u{1b}', '\u{85}']), "{text:?}");
    // An independent YAML reader (libyaml's) reads the values the IMU was made with and the
    // topic as it was given.
    let yaml: serde_norway::Value = serde_norway::from_str(&text).unwrap();
    let density = yaml["accelerometer_noise_density"].as_f64().unwrap();
    assert!((density / 2e-3 - 1.0).abs() < 0.2, "{density}");
    assert_eq!(yaml["rostopic"].as_str(), Some(topic));
    assert_eq!(yaml["update_rate"].as_f64(), Some(20.0));
    let keys: Vec<&str> = yaml
        .as_mapping()
        .unwrap()
        .keys()
        .map(|k| k.as_str().unwrap())
        .collect();
    assert_eq!(
        keys,
        [
            "accelerometer_noise_density",
            "accelerometer_random_walk",
            "gyroscope_noise_density",
            "gyroscope_random_walk",
            "rostopic",
            "update_rate"
        ]
    );
}

/// Binned at 1 s, a log still shows its white noise where it dominates beyond a second:
/// Kalibr's noise density is read there, and its `update_rate` is the IMU's (the rate of
/// its messages, which Kalibr discretises at), not the bins'.
#[test]
fn a_binned_log_gives_kalibr_the_recorded_rate() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("imu.csv");
    let (gyro, accel) = ((2e-4, 2e-5), (2e-3, 2e-4));
    std::fs::write(&log, imu_csv(7200.0, gyro, accel, [1.0, 1.5, 0.8])).unwrap();
    let out_path = dir.path().join("imu.yaml");
    ok(&[
        "allan",
        &log.display().to_string(),
        "--bin",
        "1",
        "--kalibr",
        &out_path.display().to_string(),
    ]);
    let y = yaml(&std::fs::read_to_string(&out_path).unwrap());
    assert_eq!(y["update_rate"], "20.0");
    let v = y["gyroscope_noise_density"].parse::<f64>().unwrap();
    assert!((v / (1.5 * gyro.0) - 1.0).abs() < 0.15, "{v}");
}

/// A log whose rate random walk outgrows its white noise well below the bin: after 1-s bins
/// the noise identification finds a random walk at every τ, and two neighbouring octaves that
/// happen to fall on a −1/2 line are not an angle random walk (it was read from them,
/// extrapolated to τ = 1 s, two orders of magnitude too large).
#[test]
fn a_random_walk_binned_at_1_s_gives_no_noise_density() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("walk.csv");
    // White noise and random walk cross at √3·N/K ≈ 17 ms, below the 50-ms step.
    let (gyro, accel) = ((2e-4, 2e-2), (2e-3, 2e-1));
    std::fs::write(&log, imu_csv(1200.0, gyro, accel, [1.0; 3])).unwrap();
    let log = log.display().to_string();
    let out_path = dir.path().join("imu.yaml");
    let e = fails(&[
        "allan",
        &log,
        "--bin",
        "1",
        "--kalibr",
        &out_path.display().to_string(),
    ]);
    assert!(
        e.contains("gyroscope_noise_density") && e.contains("--bin 1"),
        "{e}"
    );
    assert!(!out_path.exists());
    let json: serde_json::Value =
        serde_json::from_str(&ok(&["allan", &log, "--bin", "1", "--json"])).unwrap();
    assert!(json["readouts"]["arw"].is_null(), "{}", json["readouts"]);
    // The curve itself: a random walk at every τ.
    let alphas = json["alpha"].as_array().unwrap();
    assert!(alphas.iter().all(|a| a == -2), "{alphas:?}");
}
