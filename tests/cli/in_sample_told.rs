//! What `evaluate` (and `report`) say of logs whose truth the test knows, where the sample
//! sketch sees little or sees coarsely: a drone log and the CSV `convert` writes of it (the
//! same float32 numbers), the calibration log thinned to every 13th to 100th row (every sample
//! its own), written with fewer digits (every sample its own, coarser), and extracts of under
//! one percent of it. Nothing of these is called "not the calibration log", and no share is
//! written 0 %.

use crate::common::run::{ok, p, sample};

fn evaluate_json(cal: &str, log: &str) -> serde_json::Value {
    serde_json::from_str(&ok(&["evaluate", cal, log, "--json"])).unwrap()
}

fn first_line(cal: &str, log: &str) -> String {
    ok(&["evaluate", cal, log])
        .lines()
        .next()
        .unwrap()
        .to_string()
}

/// The calibration log's header and data rows.
fn rows_of(path: &str) -> (String, Vec<String>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().unwrap().to_string();
    (header, lines.map(String::from).collect())
}

/// A PX4 ULog of a chamber run (20 → 60 → 20 °C, float32 rad/s and °C with noise), as the
/// sixteenth attack crafted it.
fn chamber_ulog(n: usize) -> Vec<u8> {
    let mut s = 5u64;
    let mut noise = || {
        s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let time_s: Vec<f64> = (0..n).map(|k| k as f64).collect();
    let path = |k: usize| -> f64 {
        let x = k as f64 / n as f64;
        if x < 0.2 {
            20.0
        } else if x < 0.45 {
            20.0 + 40.0 * (x - 0.2) / 0.25
        } else if x < 0.6 {
            60.0
        } else if x < 0.85 {
            60.0 - 40.0 * (x - 0.6) / 0.25
        } else {
            20.0
        }
    };
    let temp: Vec<f32> = (0..n).map(|k| (path(k) + 0.02 * noise()) as f32).collect();
    let gyro: Vec<[f32; 3]> = temp
        .iter()
        .map(|&t| {
            let r = 1e-5 * (f64::from(t) - 20.0) / 40.0;
            [
                (r + 4e-6 * noise()) as f32,
                (0.5 * r + 1e-6 + 4e-6 * noise()) as f32,
                (-r + 4e-6 * noise()) as f32,
            ]
        })
        .collect();
    crate::common::drone::ulog(&time_s, &gyro, &temp, 2_424_842)
}

/// A calibration fitted on a ULog judges `driftlab convert`'s CSV of it in-sample, and the
/// other way round: the same float32 numbers, binary or written as their shortest decimals.
#[test]
fn a_drone_log_and_its_converted_csv_are_one_run() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let ulg = p(d, "good.ulg");
    std::fs::write(&ulg, chamber_ulog(8000)).unwrap();
    let csv = p(d, "good.csv");
    ok(&["convert", &ulg, "-o", &csv]);
    let (from_ulog, from_csv) = (p(d, "from_ulog.json"), p(d, "from_csv.json"));
    ok(&["calibrate", &ulg, "-o", &from_ulog]);
    ok(&["calibrate", &csv, "-o", &from_csv]);
    for (cal, log) in [(&from_ulog, &csv), (&from_csv, &ulg)] {
        let json = evaluate_json(cal, log);
        let axes = json["axes"].as_array().expect("a unit of three axes");
        assert_eq!(axes.len(), 3);
        for axis in axes {
            assert_eq!(axis["in_sample"], true, "{cal} on {log}: {axis}");
            assert_eq!(axis["shared"]["share_of_log"], 1.0, "{cal} on {log}");
        }
        let line = first_line(cal, log);
        assert!(
            line.ends_with("(in-sample: the calibration log):"),
            "{line}"
        );
    }
    // The sketch says what it hashed the drone's numbers at.
    let text = std::fs::read_to_string(&from_csv).unwrap();
    assert!(text.contains("2;f32@degC;f32@rad/s;"), "{}", &text[..400]);
}

/// The calibration log thinned to every k-th row: every sample the calibration log's. Where
/// the sketch compares enough of them it says in-sample; where too few, that it cannot tell,
/// with how many; never "held out". A unit's three axes on the same thinned rows agree.
#[test]
fn thinned_copies_are_in_sample_or_cannot_be_told_never_held_out() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let thin = |log: &str, every: usize, name: &str| {
        let (header, rows) = rows_of(log);
        let kept: Vec<&str> = rows.iter().step_by(every).map(String::as_str).collect();
        let path = p(d, name);
        std::fs::write(&path, format!("{header}\n{}\n", kept.join("\n"))).unwrap();
        path
    };
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    for (every, said) in [
        (
            13,
            "(in-sample: a part of the calibration log, about 8 % of it)",
        ),
        (
            16,
            "(in-sample: a part of the calibration log, about 6 % of it)",
        ),
        (
            20,
            "(cannot tell if it is the calibration log: only 4 of its samples could be \
             compared, all the calibration log's)",
        ),
    ] {
        let log = thin(
            &sample("calibration.csv"),
            every,
            &format!("every{every}.csv"),
        );
        let line = first_line(&cal, &log);
        assert!(line.contains(said), "every {every}th row: {line}");
        let json = evaluate_json(&cal, &log);
        assert_eq!(json["cannot_tell"].is_string(), every == 20, "{json}");
    }
    for every in [40, 100] {
        let log = thin(
            &sample("calibration.csv"),
            every,
            &format!("every{every}.csv"),
        );
        let line = first_line(&cal, &log);
        assert!(!line.contains("held out"), "every {every}th row: {line}");
    }
    // compare holds both logs, and a sketch 32 times a file's tells every one of them.
    let json: serde_json::Value = serde_json::from_str(&ok(&[
        "compare",
        "--train",
        &sample("calibration.csv"),
        "--test",
        &p(d, "every20.csv"),
        &p(d, "every100.csv"),
        &sample("validation.csv"),
        "--models",
        "poly-t",
        "--json",
    ]))
    .unwrap();
    let held: Vec<bool> = json["models"][0]["logs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["held_out"].as_bool().unwrap())
        .collect();
    assert_eq!(held, [false, false, false, true]);

    let unit = p(d, "unit.json");
    ok(&["calibrate", &sample("imu3-calibration.csv"), "-o", &unit]);
    let log = thin(&sample("imu3-calibration.csv"), 20, "imu3_every20.csv");
    let text = ok(&["evaluate", &unit, &log]);
    assert!(
        !text.contains("held out") && !text.contains("cannot tell"),
        "{text}"
    );
    for axis in ["gx", "gy", "gz"] {
        let line = text
            .lines()
            .find(|l| l.starts_with(&format!("=== Axis {axis} ")))
            .unwrap_or_else(|| panic!("{text}"));
        assert!(
            line.contains("in-sample: a part of the calibration log, about 5 % of it"),
            "{line}"
        );
    }
    // The report tags every axis's section alike.
    let out = p(d, "report");
    ok(&["report", &unit, &log, "--out", &out]);
    let html = std::fs::read_to_string(d.join("report/report.html")).unwrap();
    assert!(html.contains("class=\"tag in-sample\""));
    assert!(!html.contains("class=\"tag held-out\""));
    // Every 100th row: too few on every axis, pooled too, and each axis says so.
    let log = thin(&sample("imu3-calibration.csv"), 100, "imu3_every100.csv");
    let header = ok(&["evaluate", &unit, &log])
        .lines()
        .next()
        .unwrap()
        .to_string();
    assert!(header.contains("(cannot tell on gx, gy, gz)"), "{header}");
}

/// The calibration log written with fewer digits (its rate in 0.001 °/h, or its temperature in
/// 0.01 °C): all its samples, which the sketch (made at 0.0001 °/h and 0.001 °C) cannot find
/// at that resolution. Said so, with no share (a tenth of its rates happen to be multiples of
/// 0.001 °/h: that is no share of anything).
#[test]
fn the_calibration_log_written_coarser_cannot_be_told() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let (header, rows) = rows_of(&sample("calibration.csv"));
    for (name, column, decimals, said) in [
        (
            "rate3.csv",
            1,
            3,
            "its rates are written in steps of 0.001 °/h, the calibration log's in steps of \
             0.0001 °/h",
        ),
        (
            "temp2.csv",
            2,
            2,
            "its temperatures are written in steps of 0.01 °C, the calibration log's in \
             steps of 0.001 °C",
        ),
    ] {
        let body: Vec<String> = rows
            .iter()
            .map(|r| {
                let mut cells: Vec<String> = r.split(',').map(String::from).collect();
                let v: f64 = cells[column].parse().unwrap();
                cells[column] = format!("{v:.decimals$}");
                cells.join(",")
            })
            .collect();
        let path = p(d, name);
        std::fs::write(&path, format!("{header}\n{}\n", body.join("\n"))).unwrap();
        let json = evaluate_json(&cal, &path);
        assert_eq!(json["in_sample"], false, "{name}");
        assert!(json["shared"].is_null(), "{name}: {}", json["shared"]);
        assert_eq!(json["cannot_tell"], said, "{name}");
        let line = first_line(&cal, &path);
        assert!(
            line.contains(&format!(
                "(cannot tell if it is the calibration log: {said})"
            )),
            "{line}"
        );
    }
}

/// Two hundred rows of the calibration log (0.5 % of it) found in-sample, and a hand-edited
/// sketch whose largest hash takes every sample in: a share under one percent is said so,
/// never "about 0 %".
#[test]
fn a_share_under_one_percent_is_not_written_0() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let (header, rows) = rows_of(&sample("calibration.csv"));
    let window = p(d, "window.csv");
    std::fs::write(
        &window,
        format!("{header}\n{}\n", rows[15_400..15_600].join("\n")),
    )
    .unwrap();
    let line = first_line(&cal, &window);
    assert!(
        line.contains("(in-sample: a part of the calibration log, under 1 % of it)"),
        "{line}"
    );
    let json = evaluate_json(&cal, &window);
    let of_cal = json["shared"]["share_of_calibration_log"].as_f64().unwrap();
    assert!(
        (of_cal - 200.0 / rows.len() as f64).abs() < 1e-6,
        "{of_cal}"
    );

    let mut edited: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let sketch = edited
        .pointer_mut("/calibration/source/samples_sketch")
        .expect("a sketch");
    let text = sketch.as_str().unwrap().to_string();
    let fields: Vec<&str> = text.split(';').collect();
    let top = |part: &str| format!("{}fffffffffffffffe", &part[..part.len() - 16]);
    *sketch = format!(
        "{};{};{};{};{}",
        fields[0],
        fields[1],
        fields[2],
        top(fields[3]),
        top(fields[4])
    )
    .into();
    let crafted = p(d, "crafted.json");
    std::fs::write(&crafted, edited.to_string()).unwrap();
    let line = first_line(&crafted, &sample("validation.csv"));
    assert!(
        line.contains("(held out, though under 1 % of its samples are the calibration log's)"),
        "{line}"
    );
    let share = evaluate_json(&crafted, &sample("validation.csv"))["shared"]["share_of_log"]
        .as_f64()
        .unwrap();
    assert!(share > 0.0 && share < 0.005, "{share}");
}
