//! Readings no sensor gives (a float register's 1e38) among hours of good ones: a glitch,
//! dropped as a blank cell is (a gyro's rate: its row or sample) or kept as NaN (an
//! accelerometer's, whose axis keeps its samples where the gyro has them), and told with its
//! line or sample; never a calibration refused after its fit, or an accelerometer's unit
//! blamed. A column most of whose readings are beyond is not glitching: it is left to the
//! plausibility check, which doubts its unit.

use crate::common::drone::ulog_imu;
use driftlab::log::accel_axes::{self, AccelAsk};
use driftlab::log::ingest::{ReadOptions, read_bytes};
use driftlab::log::read::{self, FormatChoice};

/// A three-axis stand log of `n` rows at 1 s (°/h), gravity on z in m/s², with `cell` put in
/// column `col` of data row `row` (0-based).
fn stand_log(n: usize, row: usize, col: usize, cell: &str) -> String {
    let mut s = String::from(
        "time_s,temp_c,omega_x_dph,omega_y_dph,omega_z_dph,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n",
    );
    for i in 0..n {
        let t = i as f64;
        let temp = 20.0 + 30.0 * (t / n as f64);
        let mut cells: Vec<String> = [
            t,
            temp,
            0.1 * temp,
            -0.2,
            0.3,
            0.01,
            -0.02,
            9.81 + 1e-4 * temp,
        ]
        .iter()
        .map(|v| v.to_string())
        .collect();
        if i == row {
            cells[col] = cell.to_string();
        }
        s.push_str(&cells.join(","));
        s.push('\n');
    }
    s
}

#[test]
fn a_gyro_reading_of_1e38_drops_its_row_and_says_which_line() {
    let text = stand_log(2000, 999, 4, "1e38");
    let log = read_bytes("stand.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    // The header is line 1: data row 999 is line 1001.
    assert_eq!(log.len(), 1999);
    assert!(log.time_s.iter().all(|&t| t != 999.0));
    let told: Vec<&str> = log
        .info
        .problems
        .iter()
        .filter(|p| p.message.contains("no gyro gives"))
        .map(|p| p.message.as_str())
        .collect();
    assert_eq!(told.len(), 1, "{:?}", log.info.problems);
    assert!(
        told[0].contains("\"omega_z_dph\"") && told[0].contains("1e38 at line 1001"),
        "{}",
        told[0]
    );
    for (name, axis) in log.axis_names().iter().zip(0..) {
        let values = log.axis_rate(name).unwrap();
        assert!(
            values.iter().all(|v| v.abs() < 1e3),
            "axis {axis} {name} keeps a glitch"
        );
    }
}

#[test]
fn a_column_beyond_throughout_is_no_glitch_and_keeps_its_rows() {
    // Every rate 1e9 °/h (a register's counts read as °/h): the unit is in doubt, not a few
    // readings, and no row goes.
    let text = stand_log(500, usize::MAX, 0, "");
    let text: String = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 0 {
                format!("{l}\n")
            } else {
                let mut c: Vec<&str> = l.split(',').collect();
                c[2] = "1e9";
                format!("{}\n", c.join(","))
            }
        })
        .collect();
    let log = read_bytes("counts.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    assert_eq!(log.len(), 500);
    assert!(
        log.info
            .problems
            .iter()
            .all(|p| !p.message.contains("no gyro gives")),
        "{:?}",
        log.info.problems
    );
}

#[test]
fn an_accelerometer_reading_of_1e38_is_kept_as_nan_and_gravity_is_still_read() {
    let text = stand_log(2000, 1500, 7, "-3.4e38");
    let mut log = read_bytes("imu.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    let names = accel_axes::take(&mut log, &AccelAsk::default()).unwrap();
    assert_eq!(names, ["acc_x", "acc_y", "acc_z"]);
    let z = log.axis_rate("acc_z").unwrap();
    assert_eq!(z.len(), 2000);
    assert!(z[1500].is_nan());
    assert_eq!(z.iter().filter(|v| v.is_nan()).count(), 1);
    let told: Vec<&str> = log
        .info
        .problems
        .iter()
        .map(|p| p.message.as_str())
        .filter(|m| m.contains("no accelerometer gives"))
        .collect();
    assert_eq!(told.len(), 1, "{:?}", log.info.problems);
    assert!(told[0].contains("-3.4e38 at sample 1501"), "{}", told[0]);
}

#[test]
fn a_ulog_gyro_sample_of_1e38_is_dropped_with_its_sample_number() {
    let n = 2000;
    let time: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let mut gyro: Vec<[f32; 3]> = vec![[1e-5, -2e-5, 3e-5]; n];
    gyro[700][1] = 1e38;
    let accel = vec![[0.0f32, 0.0, -9.81]; n];
    let temp: Vec<f32> = (0..n).map(|i| 20.0 + 0.01 * i as f32).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("imu.ulg");
    std::fs::write(&path, ulog_imu(&time, &gyro, &accel, &temp, 2424842)).unwrap();
    let read = read::read_any(&path, &ReadOptions::default(), &FormatChoice::default()).unwrap();
    let log = read.log;
    assert_eq!(log.len(), n - 1);
    assert!(log.time_s.iter().all(|&t| t != 700.0));
    let told: Vec<String> = log
        .info
        .problems
        .iter()
        .map(|p| p.message.clone())
        .chain(
            read.drone
                .iter()
                .flat_map(|d| d.problems.iter().map(|p| p.to_string())),
        )
        .filter(|m| m.contains("no gyro gives"))
        .collect();
    assert_eq!(told.len(), 1, "{told:?}");
    assert!(
        told[0].contains("\"gyro_y_rad_s\"") && told[0].contains("1e38 at sample 701"),
        "{}",
        told[0]
    );
}

/// `text` with `cell` put in column `col` of the data rows `rows` (0-based; the header is kept).
fn with_cells(text: &str, rows: std::ops::Range<usize>, col: usize, cell: &str) -> String {
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            if i >= 1 && rows.contains(&(i - 1)) {
                let mut c: Vec<&str> = l.split(',').collect();
                c[col] = cell;
                format!("{}\n", c.join(","))
            } else {
                format!("{l}\n")
            }
        })
        .collect()
}

/// The messages of `log`'s problems that contain `words`.
fn told<'a>(log: &'a driftlab::Log, words: &str) -> Vec<&'a str> {
    log.info
        .problems
        .iter()
        .map(|p| p.message.as_str())
        .filter(|m| m.contains(words))
        .collect()
}

#[test]
fn a_few_blank_nan_or_infinite_cells_of_any_gyro_axis_drop_their_rows_as_the_first_axis_does() {
    // omega_y and omega_z are the unit's other axes: a cell no reading can be, in either, once
    // went untold and reached every fit and figure of its axis as NaN.
    for (col, name) in [(3, "omega_y_dph"), (4, "omega_z_dph")] {
        for cell in ["", "nan", "inf", "n/a"] {
            let why = "blank, NaN, infinite or unreadable";
            let text = stand_log(2000, 1200, col, cell);
            let log = read_bytes("stand.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
            assert_eq!(log.len(), 1999, "{name} {cell:?}");
            assert!(log.time_s.iter().all(|&t| t != 1200.0));
            let m = told(&log, "1 row dropped");
            assert_eq!(m.len(), 1, "{name} {cell:?}: {:?}", log.info.problems);
            // Data row 1200 is line 1202.
            assert!(
                m[0].contains(why) && m[0].contains(&format!("\"{name}\"")),
                "{}",
                m[0]
            );
            let p = &log.info.problems[0];
            assert_eq!((p.line, p.column), (1202, Some(col + 1)), "{p:?}");
            for axis in log.axis_names() {
                let rate = log.axis_rate(&axis).unwrap();
                assert!(rate.iter().all(|v| v.is_finite()), "{axis} keeps a NaN");
            }
        }
    }
}

#[test]
fn more_readings_beyond_than_glitches_are_kept_and_told_with_their_lines_and_share() {
    // 30 of 2000 readings of omega_z (1.5 %): too many to drop as glitches, too few to doubt
    // the column's unit. Kept, and told with the first and last lines and the share.
    let text = with_cells(&stand_log(2000, usize::MAX, 0, ""), 500..530, 4, "1e38");
    let log = read_bytes("stand.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    assert_eq!(log.len(), 2000);
    let m = told(&log, "taken for glitches");
    assert_eq!(m.len(), 1, "{:?}", log.info.problems);
    assert!(
        m[0].starts_with(
            "30 readings of \"omega_z_dph\" beyond the 10⁴ °/s of any gyro (1e38 at line 502, \
             the first; the last at line 531), 1.5 % of its 2000 readings"
        ),
        "{}",
        m[0]
    );
    // No unit is doubted for them.
    assert!(
        told(&log, "check its unit").is_empty(),
        "{:?}",
        log.info.problems
    );
}

#[test]
fn another_axis_beyond_throughout_has_its_unit_doubted_by_name() {
    // Every omega_y reading 1e9 °/h: the unit (or the column) is in doubt, told of that
    // column as it is of the first axis.
    let text = with_cells(&stand_log(500, usize::MAX, 0, ""), 0..500, 3, "1e9");
    let log = read_bytes("counts.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    assert_eq!(log.len(), 500);
    let m = told(&log, "check its unit");
    assert_eq!(m.len(), 1, "{:?}", log.info.problems);
    assert!(
        m[0].starts_with(
            "the rate column \"omega_y_dph\" read as deg/h reaches 2.778e5 °/s, beyond the 10⁴ \
             °/s of any gyro on a stand, in 500 of its 500 readings (100 %, the first at line "
        ),
        "{}",
        m[0]
    );
}

#[test]
fn a_stretch_of_accelerometer_readings_beyond_is_told_as_such_not_as_a_unit() {
    // 30 of 2000 acc_z readings at 1e38 (1.5 %): too many for glitches. Gravity is still read
    // from the others, so the unit is not blamed; the stretch is told and kept.
    let text = with_cells(&stand_log(2000, usize::MAX, 0, ""), 700..730, 7, "1e38");
    let mut log = read_bytes("imu.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    let names = accel_axes::take(&mut log, &AccelAsk::default()).unwrap();
    assert_eq!(names, ["acc_x", "acc_y", "acc_z"]);
    let z = log.axis_rate("acc_z").unwrap();
    assert_eq!(z.iter().filter(|v| v.abs() > 1e37).count(), 30);
    let m = told(&log, "taken for glitches");
    assert_eq!(m.len(), 1, "{:?}", log.info.problems);
    assert!(
        m[0].starts_with(
            "30 readings of \"acc_z_m_s2\" beyond the 1000 g of any accelerometer (1e38 at \
             sample 701, the first; the last at sample 730), 1.5 % of its 2000 readings"
        ),
        "{}",
        m[0]
    );
    // What `inspect` shows: the same, without making the columns axes.
    let log = read_bytes("imu.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    let seen = accel_axes::check(&log, &AccelAsk::default()).unwrap();
    assert_eq!(seen.len(), 1);
    assert_eq!(seen[0].message, m[0]);
    assert!(log.axis_rate("acc_z").is_none());
}

#[test]
fn an_axis_mostly_blank_keeps_the_other_axes_rows_and_is_refused_alone() {
    // omega_y logged in one row of three: its blanks are the column's own. The other axes keep
    // every row (dropping them would leave omega_x a third of its log), and every fit of
    // omega_y is refused, naming it; omega_x alone is fitted on all its rows.
    let base = stand_log(3000, usize::MAX, 0, "");
    let text: String = base
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i >= 1 && (i - 1) % 3 != 0 {
                let mut c: Vec<&str> = l.split(',').collect();
                c[3] = "";
                format!("{}\n", c.join(","))
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let log = read_bytes("half.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    assert_eq!(log.len(), 3000);
    let m = told(&log, "kept as missing");
    assert_eq!(m.len(), 1, "{:?}", log.info.problems);
    assert!(
        m[0].starts_with(
            "2000 cells of column \"omega_y_dph\" (66.7 % of the file's 3000 rows) are blank, \
             NaN, infinite or unreadable (first at line 3)"
        ),
        "{}",
        m[0]
    );
    let mut y = log.clone();
    assert!(y.select_axis("omega_y"));
    let e = driftlab::models::check_axis_readings(&y)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("the rate of axis omega_y is missing at 2000 of its 3000 samples (66.7 %)"),
        "{e}"
    );
    let mut x = log.clone();
    assert!(x.select_axis("omega_x"));
    driftlab::models::check_axis_readings(&x).unwrap();
}
