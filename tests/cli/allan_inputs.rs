//! `driftlab allan` on the logs it used to refuse or misread: a log whose temperature column
//! is missing, holds no number, or stops half way (the Allan deviation reads the rate alone),
//! and accelerometers logged in g or mg (Kalibr's accelerometer pair is in m/s²).
//!
//! The truths are independent of the code under test: the same rate in the bundled log with
//! its temperatures (the curve must be the same, sample for sample), and the noise densities an
//! IMU log is simulated with (as `kalibr.rs` checks them for accelerometers in m/s²).

use serde_json::Value;
use std::path::Path;

use crate::common;
use common::run::{driftlab, ok, p, sample};

/// The bundled calibration log with each data row (0-based `k` of `n`, its fields) rewritten
/// by `edit`, and its header by `header`.
fn rewritten(
    path: &str,
    header: impl Fn(&str) -> String,
    edit: impl Fn(usize, usize, &[&str]) -> String,
) {
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let mut out = header(lines.next().unwrap());
    out.push('\n');
    let rows: Vec<&str> = lines.collect();
    for (k, row) in rows.iter().enumerate() {
        let fields: Vec<&str> = row.split(',').collect();
        out.push_str(&edit(k, rows.len(), &fields));
        out.push('\n');
    }
    std::fs::write(path, out).unwrap();
}

/// `allan --json` of `log`: the curve and read-outs, and what it said on standard error. What
/// the temperature did is left out: it is what the logs here differ in
/// (`tests/cli/allan_temperature.rs` holds it).
fn allan_json(log: &str) -> (Value, String) {
    let out = driftlab(&["allan", log, "--json"]);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "allan {log}: {err}");
    let mut v: Value = serde_json::from_slice(&out.stdout).unwrap();
    v.as_object_mut().unwrap().remove("source");
    v.as_object_mut().unwrap().remove("temperature");
    if let Some(k) = v["kalibr"].as_object_mut() {
        k.remove("temperature_moves");
    }
    (v, err)
}

/// A log made from the bundled one: its file, its header from the bundled header, its data row
/// from the bundled row (`k` of `n`, the fields), and what `allan` must say of its temperature.
type Case = (
    &'static str,
    fn(&str) -> String,
    fn(usize, usize, &[&str]) -> String,
    &'static str,
);

#[test]
fn allan_reads_the_rate_whatever_the_temperature_column_holds() {
    let dir = tempfile::tempdir().unwrap();
    let (truth, _) = allan_json(&sample("calibration.csv"));
    let n = truth["samples"].as_u64().unwrap();
    assert_eq!(n, 40_201);
    let cases: [Case; 4] = [
        (
            // A plain recording of a gyro at rest.
            "no-temperature.csv",
            |_| "time_s,omega_dph".into(),
            |_, _, f| format!("{},{}", f[0], f[1]),
            "no temperature column",
        ),
        (
            // As `driftlab convert --temp-from none` writes a log of a gyro with no thermometer.
            "temperature-nan.csv",
            |h| h.into(),
            |_, _, f| format!("{},{},nan,nan", f[0], f[1]),
            "no number",
        ),
        (
            // The temperature sensor died half way: the rate goes on.
            "sensor-died.csv",
            |h| h.into(),
            |k, n, f| {
                if k < n / 2 {
                    f.join(",")
                } else {
                    format!("{},{},nan,", f[0], f[1])
                }
            },
            "20101 rows",
        ),
        (
            // Blank temperature cells here and there.
            "blanks.csv",
            |h| h.into(),
            |k, _, f| {
                if k % 97 == 5 {
                    format!("{},{},,{}", f[0], f[1], f[3])
                } else {
                    f.join(",")
                }
            },
            "415 rows",
        ),
    ];
    for (name, header, edit, said) in cases {
        let log = p(dir.path(), name);
        rewritten(&log, header, edit);
        let (got, err) = allan_json(&log);
        assert_eq!(
            got, truth,
            "{name}: the same rate gives the same curve\n{err}"
        );
        assert!(
            err.contains("temperature") && err.contains(said),
            "{name}: allan says what it did with the temperature: {err}"
        );
        // The table says how many samples it analysed.
        let table = ok(&["allan", &log]);
        assert!(table.contains("of 40201 samples"), "{name}: {table}");
    }
}

use crate::common::imu::G_M_S2;

/// An IMU simulated for two hours at 20 Hz (`tests/common/imu.rs`), its accelerometer axes
/// written in `unit` under the names `pattern` gives; axis y is 1.5 times noisier.
fn imu_csv(gyro: (f64, f64), accel: (f64, f64), pattern: &str, unit: f64) -> String {
    crate::common::imu::imu_csv(7200.0, gyro, accel, [1.0, 1.5, 0.8], pattern, unit)
}

/// The numbers of `key: value` lines of a YAML file.
fn yaml_number(text: &str, key: &str) -> Option<f64> {
    text.lines()
        .find(|l| l.starts_with(&format!("{key}:")))
        .and_then(|l| l.split('#').next())
        .and_then(|l| l.split_once(':'))
        .and_then(|(_, v)| v.trim().parse().ok())
}

#[test]
fn kalibr_gets_the_accelerometer_pair_of_axes_logged_in_g_and_mg() {
    let dir = tempfile::tempdir().unwrap();
    let (gyro, accel) = ((2e-4, 2e-5), (2e-3, 2e-4));
    let kalibr = |log: &str, name: &str| {
        let path = dir.path().join(format!("{name}.csv"));
        std::fs::write(&path, log).unwrap();
        let yaml = dir.path().join(format!("{name}.yaml"));
        ok(&[
            "allan",
            &path.display().to_string(),
            "--kalibr",
            &yaml.display().to_string(),
        ]);
        std::fs::read_to_string(yaml).unwrap()
    };
    let si = kalibr(&imu_csv(gyro, accel, "accel_{}_m_s2", 1.0), "si");
    // The simulator's names (acc_x_g with --accel, ax_g in the bundled imu3 logs), and mg.
    for (pattern, unit) in [
        ("acc_{}_g", G_M_S2),
        ("a{}_g", G_M_S2),
        ("accel_{}_mg", G_M_S2 / 1000.0),
    ] {
        let text = kalibr(
            &imu_csv(gyro, accel, pattern, unit),
            &pattern.replace("{}", ""),
        );
        assert!(!text.contains("no accelerometer"), "{pattern}: {text}");
        for (key, truth, tol) in [
            ("accelerometer_noise_density", 1.5 * accel.0, 0.10),
            ("accelerometer_random_walk", 1.5 * accel.1, 0.35),
        ] {
            let v = yaml_number(&text, key).unwrap_or_else(|| panic!("{key} in\n{text}"));
            // The density the IMU was made with, in m/s²/√Hz...
            assert!(
                (v / truth - 1.0).abs() < tol,
                "{pattern} {key}: {v} for {truth}"
            );
            // ... and the figure of the same samples logged in m/s².
            let s = yaml_number(&si, key).unwrap();
            assert!(
                (v / s - 1.0).abs() < 1e-6,
                "{pattern} {key}: {v} against {s}"
            );
        }
        let axis = format!("{} axis", pattern.replace("{}", "y"));
        assert!(text.contains(&axis), "{axis}: {text}");
    }
}

#[test]
fn kalibr_names_accelerometers_whose_unit_it_cannot_tell() {
    // `acc_x` says nothing of its unit: the pair is left out, and the file says why rather than
    // that the log has no accelerometer.
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("imu.csv");
    std::fs::write(&log, imu_csv((2e-4, 2e-5), (2e-3, 2e-4), "acc_{}", 1.0)).unwrap();
    let yaml = dir.path().join("imu.yaml");
    ok(&[
        "allan",
        &log.display().to_string(),
        "--kalibr",
        &yaml.display().to_string(),
    ]);
    let text = std::fs::read_to_string(&yaml).unwrap();
    assert!(!text.contains("has no accelerometer"), "{text}");
    assert!(
        text.contains("acc_x, acc_y, acc_z") && text.contains("unit"),
        "{text}"
    );
    assert!(yaml_number(&text, "accelerometer_noise_density").is_none());
    assert!(Path::new(&yaml).exists());
}

#[test]
fn kalibr_calls_an_accelerometer_that_never_changes_an_accelerometer_not_a_rate() {
    // Accelerometer columns of zeros (noise and walk 0): no Allan curve, said of an
    // accelerometer's samples, not of a gyro's rate.
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("imu.csv");
    std::fs::write(
        &log,
        imu_csv((2e-4, 2e-5), (0.0, 0.0), "accel_{}_m_s2", 1.0),
    )
    .unwrap();
    let yaml = dir.path().join("imu.yaml");
    let out = driftlab(&[
        "allan",
        &log.display().to_string(),
        "--kalibr",
        &yaml.display().to_string(),
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("accelerometer axis accel_x_m_s2: every sample reads 0 m/s^2"),
        "{err}"
    );
    assert!(!err.contains("rate"), "{err}");
}

#[test]
fn kalibr_takes_an_accelerometer_with_a_hole_over_its_longest_run_of_readings() {
    let dir = tempfile::tempdir().unwrap();
    let (gyro, accel) = ((2e-4, 2e-5), (2e-3, 2e-4));
    let log = imu_csv(gyro, accel, "accel_{}_m_s2", 1.0);
    // One reading of accel_x that is no number, a tenth of the way in.
    let lines: Vec<&str> = log.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let x = header.iter().position(|h| *h == "accel_x_m_s2").unwrap();
    let hole = lines.len() / 10;
    let mut holed = String::new();
    for (k, line) in lines.iter().enumerate() {
        let mut cells: Vec<&str> = line.split(',').collect();
        if k == hole {
            cells[x] = "NaN";
        }
        holed.push_str(&cells.join(","));
        holed.push('\n');
    }
    let path = dir.path().join("holed.csv");
    std::fs::write(&path, holed).unwrap();
    let yaml = dir.path().join("holed.yaml");
    let out = crate::common::run::driftlab(&[
        "allan",
        &path.display().to_string(),
        "--kalibr",
        &yaml.display().to_string(),
    ]);
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("accelerometer axis accel_x_m_s2: 1 of its 144000 samples read no number")
            && stderr.contains("longest run of readings"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(yaml).unwrap();
    let v = yaml_number(&text, "accelerometer_noise_density").unwrap();
    assert!((v / (1.5 * accel.0) - 1.0).abs() < 0.10, "{v}");
}
