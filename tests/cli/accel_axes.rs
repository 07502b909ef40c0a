//! `calibrate --accel`, `apply` and `evaluate` on a six-axis MEMS IMU's log, as a user runs
//! them: the accelerometer axes calibrated after the gyro axes; `apply` writing them in m/s²
//! after the gyro axes, each corrected reading its raw less its prediction, the prediction's
//! change with T the simulator's cubic; the axis along g named with its apparent scale-factor
//! change; and the options that cannot reach an accelerometer refused by name.

use crate::common::run::{fails, ok, p};

/// m/s² in one g, written out here.
const G: f64 = 9.80665;

/// x's accelerometer bias (g, g/°C, g/°C², g/°C³ about 20 °C), as the profile documents it.
const X_BIAS: [f64; 4] = [8.0e-3, 1.5e-4, -2.0e-6, 5.0e-8];

fn x_truth_m_s2(t: f64) -> f64 {
    let d = t - 20.0;
    let b = X_BIAS;
    G * (b[0] + d * (b[1] + d * (b[2] + d * b[3])))
}

/// The `mems-imu` run of `seed` in m/s², written into `dir`.
fn mems(dir: &std::path::Path, seed: u64) -> String {
    let path = p(dir, &format!("mems{seed}.csv"));
    ok(&[
        "simulate",
        "--profile",
        "mems-imu",
        "--seed",
        &seed.to_string(),
        "--accel-unit",
        "m/s2",
        "--out",
        &path,
    ]);
    path
}

#[test]
fn accelerometer_axes_are_calibrated_applied_and_judged_in_m_s2() {
    let dir = tempfile::tempdir().unwrap();
    let (train, test) = (mems(dir.path(), 1), mems(dir.path(), 2));
    let cal = p(dir.path(), "imu.json");
    let printed = ok(&["calibrate", &train, "--accel", "--out", &cal]);
    assert!(printed.contains("=== Axis acc_x (column acc_x_m_s2) — model poly-t3 ==="));
    assert!(printed.contains("figure (m/s^2)"), "{printed}");
    assert!(
        printed.contains("Gravity: axis acc_z carries it (mean 9.9"),
        "{printed}"
    );
    assert!(printed.contains(
        "Calibration of 6 axes (omega_x, omega_y, omega_z, acc_x, acc_y, acc_z) written to"
    ));
    let json = ok(&["calibrate", &train, "--accel", "--out", &cal, "--json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["gravity"]["axis"], "acc_z");
    assert_eq!(v["axes"][3]["kind"], "accelerometer");
    assert_eq!(v["axes"][0].get("kind"), None);

    let out = p(dir.path(), "corrected.csv");
    ok(&["apply", &cal, &test, "--out", &out]);
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(
        header[10..19],
        [
            "acc_x_raw_m_s2",
            "acc_x_pred_m_s2",
            "acc_x_cor_m_s2",
            "acc_y_raw_m_s2",
            "acc_y_pred_m_s2",
            "acc_y_cor_m_s2",
            "acc_z_raw_m_s2",
            "acc_z_pred_m_s2",
            "acc_z_cor_m_s2"
        ]
    );
    assert_eq!(header[..2], ["time_s", "omega_x_raw_dph"]);
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
        .collect();
    // The raw readings are the log's; each corrected reading is the raw less the prediction.
    let log = std::fs::read_to_string(&test).unwrap();
    let logged: Vec<f64> = log
        .lines()
        .skip(2)
        .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
        .collect();
    assert_eq!(rows.len(), logged.len());
    for (row, raw) in rows.iter().zip(&logged) {
        assert_eq!(row[10], *raw);
        assert_eq!(row[12], row[10] - row[11]);
        assert_eq!(row[18], row[16] - row[17]);
    }
    // The prediction's change with T is x's bias cubic, to 10 µg where it moves by 18 mg.
    let t_col = header.iter().position(|h| *h == "temp_c").unwrap();
    let at20 = rows
        .iter()
        .min_by(|a, b| (a[t_col] - 20.0).abs().total_cmp(&(b[t_col] - 20.0).abs()))
        .unwrap();
    for row in rows.iter().step_by(101) {
        let (t, t20) = (row[t_col], at20[t_col]);
        let fitted = row[11] - at20[11];
        let truth = x_truth_m_s2(t) - x_truth_m_s2(t20);
        assert!((fitted - truth).abs() < 1e-4, "at {t} °C: {fitted} {truth}");
    }
    // The axis along g keeps its mean: gravity stays on z.
    let z_mean = rows.iter().map(|r| r[18]).sum::<f64>() / rows.len() as f64;
    assert!((z_mean / G - 1.0).abs() < 0.02, "{z_mean}");

    // Judged on its own log and on another run, each axis in its unit.
    let own = ok(&["evaluate", &cal, &train]);
    assert!(own.contains("(in-sample: the calibration log)"), "{own}");
    let held = ok(&["evaluate", &cal, &test]);
    assert!(held.contains("held out"), "{held}");
    assert!(held.contains("=== Axis acc_z — model poly-t3"), "{held}");
    assert!(
        held.contains("deg/h, m/s^2 for the accelerometer axes"),
        "{held}"
    );
}

#[test]
fn what_cannot_reach_an_accelerometer_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let train = mems(dir.path(), 3);
    let cal = p(dir.path(), "imu.json");
    let e = fails(&[
        "calibrate",
        &train,
        "--accel",
        "--model",
        "vakhrameev",
        "--out",
        &cal,
    ]);
    assert!(
        e.contains("accelerometer axis acc_x: model vakhrameev reads more than T")
            && e.contains("--axis-model"),
        "{e}"
    );
    // A static model named for every axis reaches the accelerometers too.
    let printed = ok(&[
        "calibrate",
        &train,
        "--accel",
        "--model",
        "px4",
        "--out",
        &cal,
    ]);
    assert!(printed.contains("=== Axis acc_x (column acc_x_m_s2) — model px4 ==="));
    assert!(printed.contains("=== Axis omega_x (column omega_x_dph) — model px4 ==="));
    // A log without accelerometers, and the options of commands that read none.
    let fog = p(dir.path(), "fog.csv");
    ok(&["simulate", "--profile", "fast-ramps", "--out", &fog]);
    let e = fails(&["calibrate", &fog, "--accel", "--out", &cal]);
    assert!(e.contains("no accelerometer column"), "{e}");
    let e = fails(&["compare", "--train", &train, "--accel-col", "acc_x_m_s2"]);
    assert!(
        e.contains("--accel-col: compare reads no accelerometer axis"),
        "{e}"
    );
    let e = fails(&["calibrate", &train, &train, "--accel", "--out", &cal]);
    assert!(e.contains("--accel: a campaign of 2 runs"), "{e}");
    // A calibration of one gyro axis, given accelerometer options: the option given, and what
    // the calibration holds, named (it said "--accel-col, --accel-unit: … (its axes: )").
    let fog_cal = p(dir.path(), "fog.json");
    ok(&["calibrate", &fog, "--out", &fog_cal]);
    let e = fails(&["evaluate", &fog_cal, &fog, "--accel-unit", "mg"]);
    assert!(
        e.contains(
            "--accel-unit: the calibration has no accelerometer axis (it holds one gyro axis)"
        ),
        "{e}"
    );
    let e = fails(&[
        "report",
        &fog_cal,
        &fog,
        "--accel-col",
        "3",
        "--out",
        &p(dir.path(), "r"),
    ]);
    assert!(
        e.contains("--accel-col: the calibration has no accelerometer axis (it holds one"),
        "{e}"
    );
}

/// The `mems-imu` log of `path` rewritten by `edit` (of its header line and of each data
/// line's cells) into `to`.
fn rewritten(path: &str, to: &str, edit: impl Fn(usize, &mut Vec<String>)) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let mut out = String::new();
    for (k, line) in text.lines().enumerate() {
        let mut cells: Vec<String> = line.split(',').map(str::to_string).collect();
        edit(k, &mut cells);
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    std::fs::write(to, out).unwrap();
    to.to_string()
}

#[test]
fn a_unit_contradicted_or_no_gravity_is_refused_and_a_bad_cell_costs_only_its_sample() {
    let dir = tempfile::tempdir().unwrap();
    let train = mems(dir.path(), 4);
    let cal = p(dir.path(), "imu.json");
    let header = std::fs::read_to_string(&train).unwrap();
    // The simulator's first line is the command that made the log; the header is the next.
    let header: Vec<String> = header
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let acc: Vec<usize> = (0..header.len())
        .filter(|&k| header[k].starts_with("acc_"))
        .collect();
    assert_eq!(acc.len(), 3, "{header:?}");

    // m/s² written under names that say g: gravity then reads 9.9 g, refused, naming it.
    let as_g = rewritten(&train, &p(dir.path(), "as_g.csv"), |k, cells| {
        if k == 1 {
            for &c in &acc {
                cells[c] = cells[c].replace("_m_s2", "_g");
            }
        }
    });
    let e = fails(&["calibrate", &as_g, "--accel", "--out", &cal]);
    assert!(
        e.contains("IMU at rest reads 1 g") && e.contains("(9.9"),
        "{e}"
    );
    // And a unit given against the unit every column states.
    let e = fails(&[
        "calibrate",
        &as_g,
        "--accel",
        "--accel-unit",
        "m/s2",
        "--out",
        &cal,
    ]);
    assert!(
        e.contains("accelerometer unit given, m/s2, contradicts") && e.contains("acc_x_g in g"),
        "{e}"
    );

    // The column of another part of the log, named as an accelerometer.
    let e = fails(&["calibrate", &train, "--accel-col", "temp_c", "--out", &cal]);
    assert!(
        e.contains("column temp_c is the log's temperature column"),
        "{e}"
    );

    // One cell that reads inf and one in a hundred NaN: those samples left out, the axis
    // fitted, its kept mean finite.
    let holed = rewritten(&train, &p(dir.path(), "holed.csv"), |k, cells| {
        if k == 1000 {
            cells[acc[0]] = "inf".into();
        } else if k > 2 && k % 100 == 0 {
            cells[acc[0]] = "NaN".into();
        }
    });
    let json = ok(&["calibrate", &holed, "--accel", "--out", &cal, "--json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let mean = v["axes"][3]["kept_mean_m_s2"].as_f64().unwrap();
    assert!(mean.is_finite() && mean.abs() < 1.0, "{mean}");
}

#[test]
fn a_run_in_another_orientation_is_judged_about_its_own_mean_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let (train, test) = (mems(dir.path(), 5), mems(dir.path(), 6));
    let cal = p(dir.path(), "imu.json");
    ok(&["calibrate", &train, "--accel", "--out", &cal]);
    let header = std::fs::read_to_string(&test).unwrap();
    let z = header
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .position(|h| h == "acc_z_m_s2")
        .unwrap();
    // The unit flipped: gravity's share on z is −1 g where it was +1 g; its bias, in the
    // sensor's own frame, is what it was.
    let flipped = rewritten(&test, &p(dir.path(), "flipped.csv"), |k, cells| {
        if k > 1 {
            let v: f64 = cells[z].parse().unwrap();
            cells[z] = format!("{}", v - 2.0 * G);
        }
    });
    let out = crate::common::run::driftlab(&["evaluate", &cal, &flipped, "--json"]);
    assert!(out.status.success());
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.contains("accelerometer axis acc_z reads a mean of -9.6")
            && stderr.contains("another orientation"),
        "{stderr}"
    );
    // Judged about its own mean, its figures are its change with T (tens of mg), not 2 g.
    let same = crate::common::run::driftlab(&["evaluate", &cal, &test, "--json"]);
    let figure = |json: &[u8]| -> f64 {
        let v: serde_json::Value = serde_json::from_slice(json).unwrap();
        let axes = v["axes"].as_array().unwrap();
        let z = axes.iter().find(|a| a["name"] == "acc_z").unwrap();
        // The largest |10-min mean| of the corrected axis, named in its unit, m/s²; no field
        // of the axis is named in °/h.
        assert!(!z.to_string().contains("_dph\""), "{z}");
        z["evaluation"]["comparison"]["corrected"]["win_mean_max_abs_m_s2"]
            .as_f64()
            .unwrap()
    };
    let (upright, flipped) = (figure(&same.stdout), figure(&out.stdout));
    // Two g of gravity would read 19.9 m/s²; the flipped run's change with T is its own.
    assert!(flipped < 0.05, "{flipped}");
    assert!(upright < 0.05, "{upright}");
}

#[test]
fn an_accelerometer_with_no_reading_at_the_hottest_sample_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let train = mems(dir.path(), 7);
    let text = std::fs::read_to_string(&train).unwrap();
    let header: Vec<&str> = text.lines().nth(1).unwrap().split(',').collect();
    let (x, t) = (
        header.iter().position(|h| *h == "acc_x_m_s2").unwrap(),
        header.iter().position(|h| *h == "temp_c").unwrap(),
    );
    let hottest = text
        .lines()
        .enumerate()
        .skip(2)
        .max_by(|a, b| {
            let t_of = |l: &str| l.split(',').nth(t).unwrap().parse::<f64>().unwrap();
            t_of(a.1).total_cmp(&t_of(b.1))
        })
        .unwrap()
        .0;
    let holed = rewritten(&train, &p(dir.path(), "hot.csv"), |k, cells| {
        if k == hottest {
            cells[x] = "NaN".into();
        }
    });
    // Its fitted range is a little narrower than the log's: its Tref the middle of its own.
    let cal = p(dir.path(), "imu.json");
    ok(&["calibrate", &holed, "--accel", "--out", &cal]);
    ok(&["evaluate", &cal, &holed]);
}

#[test]
fn a_missing_accelerometer_reading_costs_its_sample_and_not_the_axiss_figures() {
    // One NaN cell (or a glitch kept as NaN) in acc_z at sample 1000 once cut the axis's
    // figures to the samples before it (peak-to-peak 0.0004 for 0.077 m/s², std n/a).
    let dir = tempfile::tempdir().unwrap();
    let log = mems(dir.path(), 1);
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &log, "--accel", "--out", &cal]);
    let acc_z = |log: &str| -> serde_json::Value {
        let v: serde_json::Value =
            serde_json::from_str(&ok(&["evaluate", &cal, log, "--json"])).unwrap();
        v["axes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|a| a["name"] == "acc_z")
            .unwrap()["evaluation"]["comparison"]
            .clone()
    };
    let clean = acc_z(&log);
    // The header is the first line that is no comment; sample 1000 is 1001 lines below it.
    let text = std::fs::read_to_string(&log).unwrap();
    let (h, header) = text
        .lines()
        .enumerate()
        .find(|(_, l)| !l.starts_with('#'))
        .unwrap();
    let z = header
        .split(',')
        .position(|c| c.starts_with("acc_z"))
        .unwrap();
    for cell in ["nan", "1e38"] {
        let holed = rewritten(&log, &p(dir.path(), &format!("{cell}.csv")), |k, cells| {
            if k == h + 1001 {
                cells[z] = cell.to_string();
            }
        });
        let one_less = acc_z(&holed);
        // Peak-to-peak and std over every sample but one are those over every sample, to
        // 2 %; the 10-min windows start again after the missing sample, which moves a
        // corrected window mean at the noise's level (1e-4 m/s²), so those are held to the
        // raw ones' 2 % and to being there.
        for which in ["raw", "corrected"] {
            for figure in ["p2p_m_s2", "std_m_s2", "win_mean_max_abs_m_s2"] {
                let (a, b) = (
                    clean[which][figure].as_f64().unwrap(),
                    one_less[which][figure]
                        .as_f64()
                        .unwrap_or_else(|| panic!("{cell}: {which} {figure} is null")),
                );
                let within = match (which, figure) {
                    ("corrected", "win_mean_max_abs_m_s2") => 0.5,
                    _ => 0.02,
                };
                assert!(
                    (a - b).abs() <= within * a,
                    "{cell}: {which} {figure} {b} against {a} with every sample"
                );
            }
        }
    }
}
