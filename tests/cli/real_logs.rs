//! Real logs, as test stands write them: a logger outage, bursts, host time stamps that
//! bunch, a raw register beside the temperature, the names and units of IMU columns, and
//! figures that cannot be computed. Each log is made by the simulator (or in the test) with a
//! known truth; the calibrations are judged on another run of the same gyro, against the
//! calibration of the continuous log, never against driftlab's own earlier output.

use serde_json::Value;
use std::path::{Path, PathBuf};

use crate::common;
use common::run::{driftlab, fails, ok, p};

/// `driftlab simulate --profile PROFILE --seed SEED ARGS --out DIR/NAME`.
fn simulate(dir: &Path, name: &str, profile: &str, seed: &str, args: &[&str]) -> String {
    let out = p(dir, name);
    let mut all = vec!["simulate", "--profile", profile, "--seed", seed];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", &out]);
    ok(&all);
    out
}

fn json(args: &[&str]) -> Value {
    serde_json::from_str(&ok(args)).unwrap()
}

/// Held-out peak-to-peak ratio of calibration `cal` on `log`.
fn held_out(cal: &str, log: &str) -> f64 {
    json(&["evaluate", cal, log, "--json"])["evaluation"]["comparison"]["p2p_ratio"]
        .as_f64()
        .unwrap()
}

struct Runs {
    _dir: tempfile::TempDir,
    dir: PathBuf,
    validation: String,
    continuous_ratio: f64,
}

/// The validation run and the held-out ratio of the continuous calibration run's calibration.
fn runs() -> Runs {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_path_buf();
    let validation = simulate(&d, "val.csv", "validation", "2", &[]);
    let cal = simulate(&d, "cal.csv", "calibration", "1", &[]);
    let cal_json = p(&d, "cal.json");
    ok(&["calibrate", &cal, "--out", &cal_json]);
    let continuous_ratio = held_out(&cal_json, &validation);
    assert!(continuous_ratio > 3.0, "{continuous_ratio}");
    Runs {
        _dir: dir,
        dir: d,
        validation,
        continuous_ratio,
    }
}

#[test]
fn a_logger_outage_splits_the_log_and_the_calibration_still_transfers() {
    // A one-hour outage in the middle of the calibration run, on a ramp.
    let r = runs();
    let gap = simulate(
        &r.dir,
        "gap.csv",
        "calibration",
        "1",
        &["--gap", "18000:3600"],
    );
    let cal = p(&r.dir, "gap.json");
    let out = json(&["calibrate", &gap, "--out", &cal, "--json"]);
    // Ṫ is never taken across the gap: the fitted K1 ranges stay within the program's
    // 1 °C/min (0.0167 °C/s), as in the continuous run.
    for a in out["approximations"].as_array().unwrap() {
        let name = a["name"].as_str().unwrap();
        if name.starts_with("K1") {
            let (lo, hi) = (a["x_min"].as_f64().unwrap(), a["x_max"].as_f64().unwrap());
            assert!(lo.abs().max(hi.abs()) < 0.0175, "{name}: {lo} .. {hi} °C/s");
        }
    }
    let in_sample = out["in_sample"]["comparison"]["p2p_ratio"]
        .as_f64()
        .unwrap();
    assert!(in_sample > 3.0, "in-sample {in_sample}");
    let ratio = held_out(&cal, &r.validation);
    eprintln!(
        "held-out p2p ratio: with the gap {ratio:.2}x, continuous {:.2}x",
        r.continuous_ratio
    );
    assert!(
        ratio > 0.9 * r.continuous_ratio,
        "with the gap {ratio}, continuous {}",
        r.continuous_ratio
    );
    let inspect = ok(&["inspect", &gap]);
    assert!(inspect.contains("2 segments between 1 gap"), "{inspect}");
}

#[test]
fn a_burst_log_is_reduced_to_its_bursts_and_transfers_like_the_continuous_one() {
    // The same run logged at 50 Hz, 10 s every 2 minutes.
    let r = runs();
    let bursts = simulate(
        &r.dir,
        "bursts.csv",
        "calibration",
        "1",
        &["--rate-hz", "50", "--bursts", "10:120"],
    );
    let run = driftlab(&["inspect", &bursts]);
    let (inspect, err) = (
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr),
    );
    assert!(
        run.status.success() && inspect.contains("bursts of 10.0 s every 120 s"),
        "{inspect}"
    );
    // The pauses are how the log was written, not gaps: no warning says the log is cut into
    // segments while the listing says "problems: none".
    assert!(inspect.contains("problems: none"), "{inspect}");
    assert!(!err.contains("gap"), "{err}");
    let cal = p(&r.dir, "bursts.json");
    let run = driftlab(&["calibrate", &bursts, "--out", &cal]);
    assert!(run.status.success());
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(err.contains("each burst reduced to its mean"), "{err}");
    assert!(!err.contains("gaps in time"), "{err}");
    // K1 in its own units: the calibration's rates of T are per second of real time.
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let dt = v["calibration"]["resolved"]["dt_s"].as_f64().unwrap();
    assert!((dt - 120.0).abs() < 1.0, "step of the burst means {dt}");
    let ratio = held_out(&cal, &r.validation);
    eprintln!(
        "held-out p2p ratio: from bursts {ratio:.2}x, continuous {:.2}x",
        r.continuous_ratio
    );
    assert!(
        ratio > 0.9 * r.continuous_ratio,
        "from bursts {ratio}, continuous {}",
        r.continuous_ratio
    );
}

/// White rate noise of `sigma_dph` per sample, `n` samples `dt_s` apart, stamped by a host
/// that reads them in batches: 2 ms between stamps of a batch, waits of 1–25 ms, one stall of
/// 0.1–0.5 s in a hundred, never earlier than the sample.
fn host_stamped(n: usize, dt_s: f64, sigma_dph: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut noise = common::Noise::new(17);
    let mut lcg = 0x2545_f491_4f6c_dd1du64;
    let mut uniform = || {
        lcg = lcg.wrapping_mul(6364136223846793005).wrapping_add(1);
        (lcg >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut stamps, mut regular, mut rate) = (Vec::new(), Vec::new(), Vec::new());
    let mut host = 0.0f64;
    let mut i = 0;
    while i < n {
        // The host wakes, reads every sample taken so far, stamps them 2 ms apart.
        let wait = if uniform() < 0.01 {
            0.1 + 0.4 * uniform()
        } else {
            0.001 + 0.024 * uniform()
        };
        host += wait;
        while i < n && i as f64 * dt_s <= host {
            host = host.max(i as f64 * dt_s) + 0.002;
            stamps.push((host * 1e6).round() / 1e6);
            regular.push(i as f64 * dt_s);
            rate.push(sigma_dph * noise.normal());
            i += 1;
        }
    }
    (stamps, regular, rate)
}

fn write_rate_log(path: &str, time: &[f64], rate: &[f64]) {
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    for (t, r) in time.iter().zip(rate) {
        text.push_str(&format!("{t},{r},25\n"));
    }
    std::fs::write(path, text).unwrap();
}

fn arw(path: &str) -> f64 {
    let v = json(&["allan", path, "--json"]);
    v["readouts"]["arw_deg_per_sqrt_h"]
        .as_f64()
        .or_else(|| v["readouts"]["arw"]["value"].as_f64())
        .unwrap_or_else(|| panic!("no ARW read-out in {v}"))
}

#[test]
fn host_time_stamps_give_the_true_step_no_gaps_and_the_true_allan_deviation() {
    // 100 Hz for 20 minutes; the same samples once stamped regularly, once by the host.
    let dir = tempfile::tempdir().unwrap();
    let (stamps, regular, rate) = host_stamped(120_000, 0.01, 30.0);
    let jittered = p(dir.path(), "host.csv");
    let even = p(dir.path(), "even.csv");
    write_rate_log(&jittered, &stamps, &rate);
    write_rate_log(&even, &regular, &rate);
    let steps: Vec<f64> = stamps.windows(2).map(|w| w[1] - w[0]).collect();
    let short = steps.iter().filter(|s| **s < 0.0025).count();
    assert!(
        short * 3 > steps.len(),
        "the stamps bunch: {short} of {}",
        steps.len()
    );
    let info = json(&["inspect", &jittered, "--json"]);
    let step = info["step_s"].as_f64().unwrap();
    assert!((step - 0.01).abs() < 2e-5, "nominal step {step}");
    let text = ok(&["inspect", &jittered]);
    assert!(
        text.contains("time stamps jitter") && !text.contains("gap"),
        "{text}"
    );
    // White noise of σ per sample at τ0: ARW = σ·√τ0 (°/h·√s), in °/√h divided by 60.
    let truth = 30.0 * 0.01f64.sqrt() / 60.0;
    let (a_jit, a_even) = (arw(&jittered), arw(&even));
    assert!(
        (a_jit - a_even).abs() < 1e-3 * a_even,
        "{a_jit} vs {a_even}"
    );
    assert!((a_even - truth).abs() < 0.05 * truth, "{a_even} vs {truth}");
}

#[test]
fn a_raw_register_is_not_taken_for_the_temperature() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(
        dir.path(),
        "raw.csv",
        "calibration",
        "1",
        &["--raw-temp-col"],
    );
    let info = json(&["inspect", &log, "--json"]);
    let temp = info["info"]["columns"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["role"] == "temperature")
        .unwrap()["name"]
        .clone();
    assert_eq!(temp, "temp_C_est");
    assert!((info["temp_min_c"].as_f64().unwrap() + 50.0).abs() < 0.1);
    // Forced onto the register: said, naming the better column and the option.
    let run = driftlab(&["inspect", &log, "--temp-col", "temp_raw_int16"]);
    let text =
        String::from_utf8_lossy(&run.stdout).to_string() + &String::from_utf8_lossy(&run.stderr);
    assert!(
        text.contains("temp_raw_int16") && text.contains("--temp-col \"temp_C_est\""),
        "{text}"
    );
}

#[test]
fn imu_column_names_and_units_are_read_as_they_say() {
    // Each rate column holds 1 °/s in its own unit; time in its own unit.
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, f64, &str, f64); 10] = [
        ("gx_dps", 1.0, "time_s", 1.0),
        ("wx_deg_s", 1.0, "t_ms", 1000.0),
        ("gyr_x [deg/s]", 1.0, "time_us", 1e6),
        ("gyro_x_rad_s", std::f64::consts::PI / 180.0, "time_s", 1.0),
        (
            "angular_velocity_x (rad/s)",
            std::f64::consts::PI / 180.0,
            "time_s",
            1.0,
        ),
        ("rate_x_mdps", 1000.0, "time_s", 1.0),
        ("omega_x_dph", 3600.0, "time_s", 1.0),
        ("gx [°/h]", 3600.0, "time_s", 1.0),
        ("Gx, deg/s", 1.0, "time_ns", 1e9),
        ("wz_rad/s", std::f64::consts::PI / 180.0, "time_s", 1.0),
    ];
    for (name, per_dps, time, per_s) in cases {
        let path = p(dir.path(), "imu.csv");
        let mut text = format!("{time};{name};temp_c\n");
        for i in 0..200 {
            text.push_str(&format!(
                "{};{};{}\n",
                i as f64 * per_s,
                per_dps,
                20.0 + i as f64 * 0.01
            ));
        }
        std::fs::write(&path, text).unwrap();
        let log = driftlab::read_path(Path::new(&path), &driftlab::ReadOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            (log.omega_dph[0] - 3600.0).abs() < 1e-9,
            "{name}: {} °/h",
            log.omega_dph[0]
        );
        assert!(
            (log.time_s[1] - 1.0).abs() < 1e-9,
            "{time}: {}",
            log.time_s[1]
        );
    }
    // A column mapped by the engineer keeps the unit its name states.
    let path = p(dir.path(), "mapped.csv");
    std::fs::write(&path, "t,sensorA_dps,temp\n0,1,20\n1,1,20.1\n2,1,20.2\n").unwrap();
    let opts = driftlab::ReadOptions {
        rate_col: Some("sensorA_dps".parse().unwrap()),
        ..Default::default()
    };
    let log = driftlab::read_path(Path::new(&path), &opts).unwrap();
    assert_eq!(log.omega_dph[0], 3600.0);
    // With no rate column the message names the option.
    std::fs::write(&path, "time,foo,temp\n0,1,20\n1,1,20\n").unwrap();
    let err = fails(&["inspect", &path]);
    assert!(err.contains("--rate-col"), "{err}");
}

#[test]
fn three_gyro_axes_and_accelerometers_are_found_without_mapping() {
    let log = driftlab::read_path(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/imu3-calibration.csv"),
        &driftlab::ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(log.axis_names(), ["gx", "gy", "gz"]);
    let accel: Vec<_> = log.extra.iter().filter(|c| c.unit == "g").collect();
    assert_eq!(accel.len(), 3, "{:?}", log.extra);
    // inspect lists the axes, in the text and in JSON.
    let sample = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/imu3-calibration.csv");
    let text = ok(&["inspect", sample.to_str().unwrap()]);
    assert!(
        text.contains(
            "gyro axes: gx [deg/s] (column gx_dps), gy [deg/s] (column gy_dps), gz [deg/s] \
             (column gz_dps)"
        ),
        "{text}"
    );
    let v = json(&["inspect", sample.to_str().unwrap(), "--json"]);
    assert_eq!(v["axis"], "gx");
    assert_eq!(v["other_axes"], serde_json::json!(["gy", "gz"]));
}

#[test]
fn a_satellite_imu_in_bursts_without_plateaus_gets_a_clear_answer() {
    // 25 bursts of 250 samples at 50 Hz, one every 300 s; the temperature falls 8 °C over the
    // two hours; a bias of 0.5 °/h per °C.
    let dir = tempfile::tempdir().unwrap();
    let path = p(dir.path(), "sat.csv");
    let mut noise = common::Noise::new(5);
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    for b in 0..25 {
        for i in 0..250 {
            let t = b as f64 * 300.0 + i as f64 * 0.02;
            let temp = 30.0 - 8.0 * t / 7200.0;
            let omega = 0.5 * (temp - 30.0) + 0.3 * noise.normal();
            text.push_str(&format!("{t},{omega},{temp}\n"));
        }
    }
    std::fs::write(&path, text).unwrap();
    let cal = p(dir.path(), "sat.json");
    // Vakhrameev's K0 needs plateaus: said, with what to do.
    let err = fails(&["calibrate", &path, "--out", &cal]);
    assert!(
        err.contains("no plateaus") && err.contains("--plateau"),
        "{err}"
    );
    // A model of T alone works on the bursts' means and recovers the slope.
    let out = json(&[
        "calibrate",
        &path,
        "--model",
        "poly-t",
        "--out",
        &cal,
        "--json",
    ]);
    let names = out["model"]["names"].as_array().unwrap();
    let slope = out["model"]["coefficients"][names.iter().position(|n| n == "T").unwrap()]
        .as_f64()
        .unwrap();
    assert!((slope - 0.5).abs() < 0.05, "slope {slope}");
    // No figure is printed as 0 or inf for what cannot be computed.
    let text = ok(&["evaluate", &cal, &path]);
    assert!(
        !text.contains("inf") && !text.contains(" 0.0000 "),
        "{text}"
    );
}

#[test]
fn figures_that_cannot_be_computed_are_na_with_a_reason() {
    // Five minutes of log: no 10-minute window fits.
    let dir = tempfile::tempdir().unwrap();
    let path = p(dir.path(), "short.csv");
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    for i in 0..300 {
        text.push_str(&format!(
            "{i},{},{}\n",
            (i % 7) as f64 * 0.1,
            20.0 + i as f64 * 0.05
        ));
    }
    std::fs::write(&path, text).unwrap();
    let cal = p(dir.path(), "c.json");
    // Rates of T over 20-s smoothing and 10-s steps: a minute of history, under half the log.
    ok(&[
        "calibrate",
        &path,
        "--model",
        "poly-t",
        "--smooth",
        "20",
        "--step-h",
        "10",
        "--out",
        &cal,
    ]);
    let text = ok(&["evaluate", &cal, &path]);
    assert!(text.contains("n/a"), "{text}");
    assert!(text.contains("whole window"), "{text}");
    let v = json(&["evaluate", &cal, &path, "--json"]);
    let c = &v["evaluation"]["comparison"];
    assert!(c["raw"]["win_rms_mean_dph"].is_null(), "{c}");
    assert_eq!(c["raw"]["windows_unavailable"], "no_whole_window");
    assert!(c["win_rms_ratio"].is_null());
}

#[test]
fn a_log_too_narrow_for_a_model_is_refused_before_the_fit() {
    let dir = tempfile::tempdir().unwrap();
    let path = p(dir.path(), "flat.csv");
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    for i in 0..4000 {
        // The rate moves (a gyro's does); the temperature spans 0.02 °C.
        text.push_str(&format!(
            "{i},{},{}\n",
            0.1 + (i % 5) as f64 * 0.01,
            25.0 + (i % 3) as f64 * 0.01
        ));
    }
    std::fs::write(&path, text).unwrap();
    let cal = p(dir.path(), "c.json");
    let err = fails(&["calibrate", &path, "--model", "poly-t", "--out", &cal]);
    assert!(
        err.contains("temperature spans") && err.contains("2 °C"),
        "{err}"
    );
    assert!(!Path::new(&cal).exists());
}
