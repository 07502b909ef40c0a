//! `driftlab allan` as a user runs it: on the bundled chamber log and on one-column rate files.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde_json::Value;
use std::path::Path;

use crate::common;
use common::run::{fails, ok};

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn chamber_log_prints_curve_and_readouts() {
    let log = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    let log = log.to_str().unwrap();
    let v: Value = serde_json::from_str(&ok(&["allan", log, "--json"])).unwrap();
    let tau = floats(&v["tau"]);
    let adev = floats(&v["adev"]);
    let (lo, hi) = (floats(&v["adev_min"]), floats(&v["adev_max"]));
    let n = v["samples"].as_u64().unwrap() as usize;
    assert_eq!(v["tau0_s"].as_f64(), Some(1.0));
    // Octave τ of a 1 s log: 1, 2, 4, … up to N/4.
    assert_eq!(tau[0], 1.0);
    assert!(tau.windows(2).all(|w| w[1] == 2.0 * w[0]));
    assert!(*tau.last().unwrap() <= (n / 4) as f64 && 2.0 * tau.last().unwrap() > (n / 4) as f64);
    for i in 0..tau.len() {
        assert!(lo[i] < adev[i] && adev[i] < hi[i]);
        // Overlapping terms: N + 1 phase points less 2m.
        assert_eq!(
            v["n"][i].as_u64().unwrap() as usize,
            n + 1 - 2 * (tau[i] as usize)
        );
    }
    // σ(τ0) directly from the file: half the mean square of successive rate differences.
    let text = std::fs::read_to_string(log).unwrap();
    let y: Vec<f64> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert_eq!(y.len(), n);
    let s1 =
        (y.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() / (2.0 * (n - 1) as f64)).sqrt();
    assert!((adev[0] - s1).abs() < 1e-9 * s1, "{} vs {s1}", adev[0]);
    // ARW is σ(1 s)/60 on the −1/2 line: near adev[0]/60 for this white-noise-led log.
    let arw = v["readouts"]["arw"]["value"].as_f64().unwrap();
    assert!((arw / (s1 / 60.0) - 1.0).abs() < 0.05, "ARW {arw}");
    assert_eq!(v["readouts"]["arw"]["unit"], "deg/sqrt(h)");

    let table = ok(&["allan", log]);
    assert!(table.contains("sigma (deg/h)"));
    assert!(table.contains("angle random walk"));
    assert!(table.contains("bias instability"));
    assert!(table.contains("rate random walk"));
}

fn write_white(path: &Path, header: &str, n: usize, sigma: f64, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut s = String::from(header);
    for _ in 0..n {
        let z: f64 = StandardNormal.sample(&mut rng);
        s.push_str(&format!("{}\n", sigma * z));
    }
    std::fs::write(path, s).unwrap();
}

#[test]
fn one_column_log_is_a_rate_series_at_tau0() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("rate.txt");
    // ARW 0.2 °/√h at 10 Hz, written in °/s: per-sample σ = 60·ARW/√τ0 °/h.
    let (arw, tau0) = (0.2, 0.1_f64);
    let sigma_dph = 60.0 * arw / tau0.sqrt();
    write_white(&f, "rate [deg/s]\n", 200_000, sigma_dph / 3600.0, 5);
    let f = f.to_str().unwrap();
    let v: Value = serde_json::from_str(&ok(&["allan", f, "--tau0", "0.1", "--json"])).unwrap();
    assert_eq!(v["samples"].as_u64(), Some(200_000));
    let tau = floats(&v["tau"]);
    assert!((tau[0] - 0.1).abs() < 1e-12);
    let got = v["readouts"]["arw"]["value"].as_f64().unwrap();
    assert!((got / arw - 1.0).abs() < 0.02, "ARW {got} vs {arw}");
    // --sample-rate says the same as --tau0.
    let w: Value =
        serde_json::from_str(&ok(&["allan", f, "--sample-rate", "10", "--json"])).unwrap();
    assert_eq!(w["adev"], v["adev"]);
    // --all-tau: every factor up to N/4 would be 50 000 τ; a shorter file keeps this quick.
    let g = dir.path().join("short.txt");
    write_white(&g, "", 400, 1.0, 6);
    let g = g.to_str().unwrap();
    let a: Value =
        serde_json::from_str(&ok(&["allan", g, "--tau0", "1", "--all-tau", "--json"])).unwrap();
    assert_eq!(
        floats(&a["tau"]),
        (1..=100).map(|m| m as f64).collect::<Vec<_>>()
    );
}

#[test]
fn one_column_log_errors_are_clear() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str, text: &str| {
        let f = dir.path().join(name);
        std::fs::write(&f, text).unwrap();
        f.display().to_string()
    };
    let two = p("two.csv", "1.0\n2.0\n");
    assert!(fails(&["allan", &two]).contains("--tau0"));
    let one = p("one.csv", "1.0\n");
    assert!(fails(&["allan", &one, "--tau0", "1"]).contains("at least 2"));
    let hole = p("hole.csv", "1.0\n\nNaN\n2.0\n");
    assert!(fails(&["allan", &hole, "--tau0", "1"]).contains(":3:"));
    assert!(fails(&["allan", &two, "--tau0", "0"]).contains("--tau0"));
    let empty = p("empty.csv", "");
    fails(&["allan", &empty, "--tau0", "1"]);
}

/// A log stamped every second of white rate noise (ARW) and a rate random walk (RRW), with its
/// time column, so that the curve has a −½ line, a minimum and a +½ line.
fn write_white_and_walk(path: &Path, n: usize, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut walk = 0.0;
    let mut s = String::from("time_s,omega_dph\n");
    for i in 0..n {
        let (w, r): (f64, f64) = (
            StandardNormal.sample(&mut rng),
            StandardNormal.sample(&mut rng),
        );
        walk += 0.002 * r;
        s.push_str(&format!("{i},{}\n", 0.5 * w + walk));
    }
    std::fs::write(path, s).unwrap();
}

#[test]
fn a_tau0_k_times_the_step_moves_each_readout_by_its_own_power_of_k() {
    // σ of an m-sample average does not depend on τ0: only τ moves, by k. So the read-outs move
    // as the slope of the line each is read on: ARW (−½) by √k, bias instability (0) not at
    // all, RRW (+½) by 1/√k. Computed here from the two JSON curves, then held to the warning.
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("walk.csv");
    write_white_and_walk(&f, 100_000, 8);
    let f = f.to_str().unwrap();
    let json = |tau0: &str| -> Value {
        serde_json::from_str(&ok(&["allan", f, "--tau0", tau0, "--json"])).unwrap()
    };
    let (one, four) = (json("1"), json("4"));
    let value = |v: &Value, r: &str| v["readouts"][r]["value"].as_f64().unwrap();
    let ratio = |r: &str| value(&four, r) / value(&one, r);
    let tau = floats(&four["tau"])[3] / floats(&one["tau"])[3];
    assert!((tau - 4.0).abs() < 1e-12, "τ x{tau}");
    assert_eq!(four["adev"], one["adev"]);
    for (r, want) in [("arw", 2.0), ("bias_instability", 1.0), ("rrw", 0.5)] {
        assert!((ratio(r) / want - 1.0).abs() < 1e-9, "{r}: x{}", ratio(r));
    }
    // The warning states those factors, not one factor for every read-out.
    let run = common::run::driftlab(&["allan", f, "--tau0", "4"]);
    assert!(run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(
        err.contains("scales every τ by 4,")
            && err.contains("angle random walk (and Kalibr's noise density) by 2 (√4)")
            && err.contains("rate random walk (and Kalibr's random walk) by 0.5 (1/√4)")
            && err.contains("update_rate by 0.25")
            && err.contains("leaves the bias instability as it is")
            && !err.contains("every τ and read-out"),
        "{err}"
    );
}
