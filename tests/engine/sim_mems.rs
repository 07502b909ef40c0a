//! The six-axis MEMS IMU of the simulator (`mems-imu`) against its constants written out here:
//! each accelerometer reads gravity times a scale factor that moves with T, plus a cubic bias
//! in T; the CSV in m/s² holds those readings by the standard gravity; the command line the
//! file names makes it again, byte for byte.

use driftlab::sim::{AccelUnit, CsvDialect, SimOptions, profile, simulate, write_simulated_csv};

/// The standard gravity, m/s² in one g, written out here.
const G: f64 = 9.80665;

/// The accelerometers' constants as the profile documents them (g, g/°C, g/°C², g/°C³ about
/// 20 °C; gravity in g; scale factor per °C).
const ACCEL: [(&str, f64, [f64; 4], f64); 3] = [
    ("x", 0.0, [8.0e-3, 1.5e-4, -2.0e-6, 5.0e-8], 0.0),
    ("y", 0.0, [-5.0e-3, -1.0e-4, 3.0e-6, -4.0e-8], 0.0),
    ("z", 1.0, [15.0e-3, 2.0e-4, -1.5e-6, 3.0e-8], -1.5e-4),
];

/// The noise-free reading of accelerometer `k` at housing temperature `t`, g.
fn reading_g(k: usize, t: f64) -> f64 {
    let (_, gravity, b, s) = ACCEL[k];
    let d = t - 20.0;
    gravity * (1.0 + s * d) + b[0] + b[1] * d + b[2] * d * d + b[3] * d * d * d
}

#[test]
fn the_mems_accelerometers_read_gravity_and_their_cubic_biases() {
    let p = profile("mems-imu").unwrap();
    assert_eq!(p.axes.len(), 3);
    assert_eq!(p.accelerometers.len(), 3);
    let run = simulate(&p, 3);
    for (k, a) in run.accelerometers.iter().enumerate() {
        assert_eq!(a.name, ACCEL[k].0);
        for i in (0..run.len()).step_by(97) {
            let truth = reading_g(k, run.housing_c[i]);
            assert!(
                (a.true_g[i] - truth).abs() < 1e-12,
                "{} at sample {i}: {} against {truth}",
                a.name,
                a.true_g[i]
            );
        }
        // The logged reading is the truth with white noise of 150 µg/√Hz (106 µg a 1-Hz
        // sample) to 1 µg.
        let d: Vec<f64> = a
            .values_g
            .iter()
            .zip(&a.true_g)
            .map(|(v, t)| v - t)
            .collect();
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        let sd = (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / d.len() as f64).sqrt();
        assert!(mean.abs() < 5e-6, "{}: mean noise {mean}", a.name);
        assert!(
            (sd / (150e-6 * 0.5f64.sqrt()) - 1.0).abs() < 0.03,
            "{}: {sd}",
            a.name
        );
    }
    // Over the run each bias moves by 10 mg or more.
    let span = |k: usize| {
        let v: Vec<f64> = run
            .housing_c
            .iter()
            .map(|&t| reading_g(k, t) - ACCEL[k].1 * (1.0 + ACCEL[k].3 * (t - 20.0)))
            .collect();
        v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
    };
    for k in 0..3 {
        assert!(span(k) > 0.01, "axis {k}: {}", span(k));
    }
    // A MEMS gyro has no fibre: its drift is its bias curve alone, at the die's temperature.
    for a in &run.axes {
        assert!(a.shupe_dph.iter().chain(&a.stress_dph).all(|&v| v == 0.0));
        assert_eq!(a.thermal_dph, a.static_dph);
    }
}

#[test]
fn the_mems_imu_is_written_in_m_s2_and_made_again_by_its_command() {
    let dir = tempfile::tempdir().unwrap();
    let p = profile("mems-imu").unwrap();
    let options = SimOptions {
        dialect: CsvDialect {
            accel_unit: AccelUnit::MetersPerSecond2,
            ..CsvDialect::driftlab()
        },
        ..SimOptions::default()
    };
    let path = dir.path().join("mems.csv");
    write_simulated_csv(&p, 4, &options, &path, &|_| {}).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    let command = lines.next().unwrap();
    assert_eq!(
        command,
        "# driftlab simulate --profile mems-imu --seed 4 --accel-unit m/s2"
    );
    assert_eq!(
        lines.next().unwrap(),
        "time_s,omega_x_dph,omega_y_dph,omega_z_dph,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,temp_c,\
         temp_chamber_c"
    );
    // Each cell is the reading in g times the standard gravity, to 10⁻⁶ m/s².
    let run = simulate(&p, 4);
    for (i, line) in lines.enumerate().step_by(331) {
        let cells: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        for k in 0..3 {
            let g = run.accelerometers[k].values_g[i];
            assert!(
                (cells[4 + k] - g * G).abs() <= 0.5e-6 + 1e-12,
                "row {i} axis {k}: {} against {}",
                cells[4 + k],
                g * G
            );
        }
    }
    // The command on the file's first line makes the same bytes.
    let again = dir.path().join("again.csv");
    let words: Vec<&str> = command
        .trim_start_matches("# driftlab ")
        .split(' ')
        .chain(["--out", again.to_str().unwrap()])
        .collect();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(&words)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(std::fs::read(&again).unwrap(), text.as_bytes());
}

#[test]
fn the_mems_imu_refuses_the_options_of_another_unit() {
    let p = profile("mems-imu").unwrap();
    let e = p.clone().with_axes(3).unwrap_err();
    assert_eq!(e.field, "--axes");
    assert!(e.reason.contains("of its own"), "{e}");
    let e = p.with_accelerometers().unwrap_err();
    assert_eq!(e.field, "--accel");
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args([
            "simulate",
            "--profile",
            "calibration",
            "--accel-unit",
            "m/s2",
            "--out",
        ])
        .arg(dir.path().join("x.csv"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--accel-unit m/s2: profile calibration has no accelerometers"),
        "{err}"
    );
}
