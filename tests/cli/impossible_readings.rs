//! Readings no sensor gives, past the few the readers drop as glitches, as a user meets them:
//! a stretch of a float register's 1e38 on any gyro axis or accelerometer is told with its
//! lines and share, and refused before any fit, naming the axis; never fitted and refused when
//! written, nor blamed on a unit. A cell no reading can be, on any gyro axis, drops its row.

use crate::common::drone::ulog_imu;
use crate::common::run::{driftlab, fails, ok, p};

/// The `mems-imu` run (18,301 rows at 1 s, gyro axes in °/h, accelerometers in m/s²) with
/// `cell` in column `col` (0-based) of the data rows `rows`, written as `name` into `dir`.
fn mems_with(
    dir: &std::path::Path,
    name: &str,
    col: usize,
    rows: std::ops::Range<usize>,
    cell: &str,
) -> String {
    mems_with_cells(dir, name, &[(col, rows, cell)])
}

/// [`mems_with`] with several columns' cells set, each `(col, rows, cell)`.
fn mems_with_cells(
    dir: &std::path::Path,
    name: &str,
    edits: &[(usize, std::ops::Range<usize>, &str)],
) -> String {
    let clean = p(dir, "clean.csv");
    if !std::path::Path::new(&clean).exists() {
        ok(&[
            "simulate",
            "--profile",
            "mems-imu",
            "--accel-unit",
            "m/s2",
            "--out",
            &clean,
        ]);
    }
    let text = std::fs::read_to_string(&clean).unwrap();
    let mut row = 0usize;
    let mut out = String::new();
    for line in text.lines() {
        if line.starts_with(|c: char| c.is_ascii_digit()) {
            let mut cells: Vec<&str> = line.split(',').collect();
            for (col, rows, cell) in edits {
                if rows.contains(&row) {
                    cells[*col] = cell;
                }
            }
            out.push_str(&cells.join(","));
            row += 1;
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    assert_eq!(row, 18301, "the profile's length");
    let path = p(dir, name);
    std::fs::write(&path, out).unwrap();
    path
}

#[test]
fn a_stretch_beyond_any_gyro_on_the_third_axis_is_refused_before_any_fit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 300 of 18,301 omega_z readings (1.64 %): more than the 1 % read as glitches. The file
    // has a comment line and a header: data row 1000 is line 1003.
    let log = mems_with(d, "z300.csv", 3, 1000..1300, "1e38");
    let out = p(d, "kept.json");
    std::fs::write(&out, "last week's calibration\n").unwrap();
    let err = fails(&["calibrate", &log, "--out", &out]);
    assert!(
        err.contains(
            "300 readings of \"omega_z_dph\" beyond the 10⁴ °/s of any gyro (1e38 at line \
             1003, the first; the last at line 1302), 1.64 % of its 18301 readings"
        ),
        "{err}"
    );
    let last = err.lines().last().unwrap();
    assert!(
        last.starts_with(&format!(
            "error: {log}: the rate of axis omega_z holds 300 readings beyond the 10⁴ °/s of \
             any gyro (1e38 °/h; from 1000 s to 1299 s), 1.64 % of its 18301: more than the 1 % taken for glitches"
        )),
        "{err}"
    );
    // Refused before the fit, not by the writer after it.
    assert!(!err.contains("not written"), "{err}");
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        "last week's calibration\n"
    );
    // `inspect` tells the same stretch, naming its lines.
    let seen = ok(&["inspect", &log]);
    assert!(
        seen.contains("line 1003: 300 readings of \"omega_z_dph\""),
        "{seen}"
    );
}

#[test]
fn a_nan_on_the_third_axis_drops_its_row_for_calibrate_and_allan_alike() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = mems_with(d, "znan.csv", 3, 5000..5001, "nan");
    let seen = ok(&["inspect", &log]);
    assert!(
        seen.contains(
            "line 5003: 1 row dropped: blank, NaN, infinite or unreadable in column \"omega_z_dph\""
        ),
        "{seen}"
    );
    // `allan` once refused every axis for that one cell.
    let o = driftlab(&["allan", &log]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = driftlab(&["calibrate", &log, "--out", &p(d, "c.json")]);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("1 row dropped: blank, NaN, infinite or unreadable in column \"omega_z_dph\""),
        "{err}"
    );
}

#[test]
fn each_axis_is_judged_against_the_file_s_rows_whatever_the_other_axes_drop() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 183 of the file's 18,301 rows (1.000 %) on omega_x and as many, in other rows, on
    // omega_y: each alone is dropped, so together both are (the second once was judged
    // against the 18,118 rows the first left, 1.01 %, and refused).
    for (name, y_cell) in [("blank_blank.csv", ""), ("blank_glitch.csv", "1e38")] {
        let log = mems_with_cells(d, name, &[(1, 0..183, ""), (2, 5000..5183, y_cell)]);
        let err = ok(&["calibrate", &log, "--out", &p(d, "c.json")]);
        assert!(err.contains("written"), "{name}: {err}");
        let seen = ok(&["inspect", &log]);
        assert!(seen.contains("183 rows dropped: blank or NaN in column \"omega_x_dph\""));
        assert!(seen.contains("\"omega_y_dph\""), "{name}: {seen}");
        assert!(
            !seen.contains("neither fitted nor judged"),
            "{name}: {seen}"
        );
    }
    // One cell more on omega_y is more than 1 % of the file's rows, whatever omega_x drops.
    let log = mems_with_cells(d, "over.csv", &[(1, 0..183, ""), (2, 5000..5184, "")]);
    let seen = ok(&["inspect", &log]);
    assert!(
        seen.contains("184 cells of column \"omega_y_dph\" (1.01 % of the file's 18301 rows)"),
        "{seen}"
    );
}

#[test]
fn a_stretch_beyond_any_accelerometer_is_refused_naming_the_axis_not_the_unit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // acc_z is column 6; 300 readings of 1e38 (1.64 %).
    let log = mems_with(d, "a300.csv", 6, 1000..1300, "1e38");
    let seen = ok(&["inspect", &log]);
    assert!(
        seen.contains(
            "accelerometers: 300 readings of \"acc_z_m_s2\" beyond the 1000 g of any \
             accelerometer (1e38 at sample 1001, the first; the last at sample 1300), 1.64 %"
        ),
        "{seen}"
    );
    let err = fails(&["calibrate", &log, "--accel", "--out", &p(d, "c.json")]);
    assert!(!err.contains("is their unit right"), "{err}");
    assert!(
        err.lines().last().unwrap().starts_with(&format!(
            "error: {log}: accelerometer axis acc_z holds 300 readings beyond the 1000 g of \
             any accelerometer (1e38 m/s²; from 1000 s to 1299 s), 1.64 % of its 18301: more than the 1 % taken for glitches"
        )),
        "{err}"
    );
    // A few are glitches, kept as NaN, and the calibration is made.
    let few = mems_with(d, "a100.csv", 6, 1000..1100, "1e38");
    let seen = ok(&["inspect", &few]);
    assert!(
        seen.contains("accelerometers: 100 readings of \"acc_z_m_s2\"")
            && seen.contains("kept as NaN"),
        "{seen}"
    );
    ok(&["calibrate", &few, "--accel", "--out", &p(d, "c100.json")]);
}

#[test]
fn convert_tells_a_stretch_of_gyro_readings_beyond_any_gyro() {
    // 37 of 3600 gyro_x samples of a ULog at 1e38 rad/s: one past the 1 % dropped as glitches.
    let n = 3600;
    let time: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let mut gyro: Vec<[f32; 3]> = (0..n)
        .map(|i| [1e-5 + 1e-9 * i as f32, -2e-5, 3e-5])
        .collect();
    for g in &mut gyro[1000..1037] {
        g[0] = 1e38;
    }
    let accel = vec![[0.0f32, 0.0, -9.81]; n];
    let temp: Vec<f32> = (0..n).map(|i| 20.0 + 0.01 * i as f32).collect();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = p(d, "imu.ulg");
    std::fs::write(&log, ulog_imu(&time, &gyro, &accel, &temp, 2424842)).unwrap();
    let o = driftlab(&["convert", &log, "-o", &p(d, "imu.csv")]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(
            "37 readings of \"gyro_x_rad_s\" beyond the 10⁴ °/s of any gyro (1e38 at sample \
             1001, the first; the last at sample 1037), 1.03 % of its 3600 readings"
        ),
        "{err}"
    );
    let err = fails(&["calibrate", &log, "--out", &p(d, "c.json")]);
    assert!(
        err.contains("the rate of axis gyro_x holds 37 readings beyond"),
        "{err}"
    );
    assert!(!err.contains("not written"), "{err}");
}

#[test]
fn report_and_allan_leave_out_an_axis_holding_readings_beyond_any_sensor() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let z300 = mems_with(d, "z300.csv", 3, 1000..1300, "1e38");
    let a300 = mems_with(d, "a300.csv", 6, 1000..1300, "1e38");
    let clean = p(d, "clean.csv");
    let cal = p(d, "cal.json");
    ok(&["calibrate", &clean, "--accel", "--out", &cal]);
    // The report judges the other axes of each log, and leaves out the one whose readings no
    // figure can take, with the words `evaluate` refuses it with.
    let rep = p(d, "rep");
    let said = ok(&["report", &cal, &clean, &z300, &a300, "--out", &rep]);
    assert!(
        said.contains(&format!(
            "z300.csv (left out), axis omega_z: {z300}: the rate of axis omega_z holds 300 \
             readings beyond the 10⁴ °/s of any gyro (1e38 °/h; from 1000 s to 1299 s), 1.64 %"
        )),
        "{said}"
    );
    assert!(
        said.contains(&format!(
            "a300.csv (left out), axis acc_z: {a300}: accelerometer axis acc_z holds 300 \
             readings beyond the 1000 g of any accelerometer"
        )),
        "{said}"
    );
    // No figure of 10³⁸ anywhere: not printed, not in the page.
    assert!(!said.contains("1e38 ->"), "{said}");
    let page = std::fs::read_to_string(format!("{rep}/report.html")).unwrap();
    assert!(
        !page.contains("100000000000000"),
        "a figure of 1e38 in the page"
    );
    assert!(
        page.contains(&format!(
            "left out: {z300}: the rate of axis omega_z holds 300 readings"
        )),
        "the page does not say why omega_z of z300.csv is left out"
    );
    // The log's other axes are judged: a row of omega_x in z300.csv's table.
    let z_table = page.split("data-log=\"z300.csv\"").nth(1).unwrap();
    let z_table = z_table.split("</table>").next().unwrap();
    assert!(
        z_table.contains("<tr data-axis=\"omega_x\"><td>omega_x</td>"),
        "{z_table}"
    );
    // `allan` refuses the axis as `evaluate` does, and writes no Kalibr file through it.
    let err = fails(&["allan", &z300]);
    assert!(
        err.contains(&format!(
            "{z300}: the rate of axis omega_z holds 300 readings beyond"
        )),
        "{err}"
    );
    ok(&["allan", &z300, "--axes", "omega_x"]);
    let yaml = p(d, "imu.yaml");
    let err = fails(&[
        "allan",
        &a300,
        "--kalibr",
        &yaml,
        "--allow-moving-temperature",
    ]);
    assert!(
        err.contains(&format!(
            "{a300}: accelerometer axis acc_z_m_s2 holds 300 readings beyond"
        )),
        "{err}"
    );
    assert!(!std::path::Path::new(&yaml).exists());
}

#[test]
fn at_half_the_column_the_two_sides_read_apart_and_both_keep_the_count_and_lines() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // omega_x is column 1. 9150 of 18,301 readings are 49.99727 %, a stretch; 9151 are
    // 50.00273 %, most of the column, whose unit is doubted. Data row 0 is line 3.
    let below = mems_with(d, "x9150.csv", 1, 0..9150, "1e38");
    let above = mems_with(d, "x9151.csv", 1, 0..9151, "1e38");
    let seen = ok(&["inspect", &below]);
    assert!(
        seen.contains(
            "9150 readings of \"omega_x_dph\" beyond the 10⁴ °/s of any gyro (1e38 at line 3, \
             the first; the last at line 9152), 49.997 % of its 18301 readings"
        ),
        "{seen}"
    );
    let seen = ok(&["inspect", &above]);
    assert!(
        seen.contains(
            "line 3: the rate column \"omega_x_dph\" read as deg/h reaches 2.778e34 °/s, beyond \
             the 10⁴ °/s of any gyro on a stand, in 9151 of its 18301 readings (50.003 %, the \
             first at line 3, the last at line 9153): more than half of the column"
        ),
        "{seen}"
    );
    // Told once, by the reader, not again by the plausibility check.
    assert_eq!(
        seen.matches("check its unit (--rate-unit)").count(),
        1,
        "{seen}"
    );
}
