//! One rule for in-sample: `evaluate`, `report` and `compare` call figures in-sample when the
//! log holds the calibration's own run, whatever its bytes (line endings, a comment removed, a
//! new name), or a part of it, and held out only on another run, even one that shares its
//! time and temperature columns.

use crate::common::run::{ok, p, sample};

/// The calibration log with CRLF line endings, without its comment line, under a new name.
fn copies(dir: &std::path::Path) -> Vec<String> {
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let crlf: String = text.lines().map(|l| format!("{l}\r\n")).collect();
    let bare: String = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    let mut out = Vec::new();
    for (name, body) in [
        ("crlf.csv", crlf),
        ("bare.csv", bare),
        ("renamed.csv", text),
    ] {
        std::fs::write(dir.join(name), body).unwrap();
        out.push(p(dir, name));
    }
    out
}

fn evaluate_in_sample(cal: &str, log: &str) -> bool {
    let json: serde_json::Value =
        serde_json::from_str(&ok(&["evaluate", cal, log, "--json"])).unwrap();
    json["in_sample"].as_bool().expect("in_sample")
}

#[test]
fn a_copy_of_the_calibration_log_with_other_bytes_is_in_sample() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let copies = copies(dir.path());
    for log in &copies {
        assert!(evaluate_in_sample(&cal, log), "{log} called held out");
    }
    assert!(!evaluate_in_sample(&cal, &sample("validation.csv")));

    // The report tags each log's section by the same rule.
    let out = p(dir.path(), "report");
    ok(&[
        "report",
        &cal,
        &copies[0],
        &sample("validation.csv"),
        "--out",
        &out,
    ]);
    let html = std::fs::read_to_string(dir.path().join("report/report.html")).unwrap();
    let crlf_at = html.find("crlf.csv").expect("the copy's section");
    let validation_at = html
        .find("validation.csv")
        .expect("the other run's section");
    let tag_after = |at: usize| {
        let rest = &html[at..];
        match (rest.find("in-sample"), rest.find("held out")) {
            (Some(i), Some(h)) => i < h,
            (Some(_), None) => true,
            _ => false,
        }
    };
    assert!(tag_after(crlf_at), "the copy is not tagged in-sample");
    assert!(
        !tag_after(validation_at),
        "the other run is not tagged held out"
    );

    // compare, which has both logs, says the same.
    let json: serde_json::Value = serde_json::from_str(&ok(&[
        "compare",
        "--train",
        &sample("calibration.csv"),
        "--test",
        &copies[1],
        "--test",
        &sample("validation.csv"),
        "--models",
        "poly-t",
        "--json",
    ]))
    .unwrap();
    let logs = json["models"][0]["logs"].as_array().expect("logs");
    let held: Vec<bool> = logs
        .iter()
        .map(|l| l["held_out"].as_bool().unwrap())
        .collect();
    assert_eq!(held, [false, false, true]);
}

#[test]
fn an_old_calibration_without_the_samples_sketch_is_judged_by_its_file_hash() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let source = json.pointer_mut("/calibration/source").expect("a source");
    assert!(source["samples_sketch"].is_string(), "{source}");
    source.as_object_mut().unwrap().remove("samples_sketch");
    let old = p(dir.path(), "old.json");
    std::fs::write(&old, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    assert!(evaluate_in_sample(&old, &sample("calibration.csv")));
    assert!(!evaluate_in_sample(&old, &sample("validation.csv")));
}

/// The calibration log's data rows (after its comment and header), and its header line.
fn rows_of(path: &str) -> (String, Vec<String>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().unwrap().to_string();
    (header, lines.map(String::from).collect())
}

fn evaluate_label(cal: &str, log: &str) -> String {
    ok(&["evaluate", cal, log])
        .lines()
        .next()
        .unwrap()
        .to_string()
}

#[test]
fn a_part_of_the_run_is_in_sample_and_another_gyro_on_its_columns_is_held_out() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    let log = sample("calibration.csv");
    ok(&["calibrate", &log, "-o", &cal]);
    let (header, rows) = rows_of(&log);
    let write = |name: &str, rows: &[String]| {
        let path = p(d, name);
        std::fs::write(&path, format!("{header}\n{}\n", rows.join("\n"))).unwrap();
        path
    };
    // Less its first row, and its first three quarters (30,000 of 40,201 rows).
    let trimmed = write("trimmed.csv", &rows[1..]);
    let first = write("first.csv", &rows[..30_000]);
    // Another run's rate beside this run's time and temperature columns.
    let other_run = p(d, "other.csv");
    ok(&["simulate", "--seed", "2", "--out", &other_run]);
    let (_, other_rows) = rows_of(&other_run);
    let mixed: Vec<String> = rows
        .iter()
        .zip(&other_rows)
        .map(|(mine, theirs)| {
            let mut cells: Vec<&str> = mine.split(',').collect();
            cells[1] = theirs.split(',').nth(1).unwrap();
            cells.join(",")
        })
        .collect();
    let gyro_b = write("gyro_b.csv", &mixed);
    // Three quarters this run, a quarter the other's rate; and the other way round.
    let most: Vec<String> = rows[..30_000]
        .iter()
        .chain(&mixed[30_000..])
        .cloned()
        .collect();
    let most = write("most.csv", &most);
    let some: Vec<String> = rows[..10_000]
        .iter()
        .chain(&mixed[10_000..])
        .cloned()
        .collect();
    let some = write("some.csv", &some);

    assert!(evaluate_in_sample(&cal, &trimmed), "less a row: held out");
    let label = evaluate_label(&cal, &trimmed);
    assert!(
        label.contains("(in-sample: the calibration log)"),
        "{label}"
    );
    assert!(evaluate_in_sample(&cal, &first));
    let label = evaluate_label(&cal, &first);
    assert!(
        label.contains("in-sample: a part of the calibration log, about"),
        "{label}"
    );
    assert!(evaluate_in_sample(&cal, &most));
    let json: serde_json::Value =
        serde_json::from_str(&ok(&["evaluate", &cal, &most, "--json"])).unwrap();
    let share = json["in_sample_share"].as_f64().expect("a share");
    assert!(
        (0.6..0.9).contains(&share),
        "three quarters of the samples: {share}"
    );
    // A quarter: held out, and said to be partly the calibration's.
    assert!(!evaluate_in_sample(&cal, &some));
    let label = evaluate_label(&cal, &some);
    assert!(
        label.contains("(held out, though about") && label.contains("calibration log's"),
        "{label}"
    );
    assert!(
        !evaluate_in_sample(&cal, &gyro_b),
        "another gyro: in-sample"
    );

    let json: serde_json::Value = serde_json::from_str(&ok(&[
        "compare", "--train", &log, "--test", &trimmed, &first, &gyro_b, "--models", "poly-t",
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
}

#[test]
fn the_calibration_log_binned_or_restamped_is_in_sample_with_no_share_of_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    let log = sample("calibration.csv");
    ok(&["calibrate", &log, "-o", &cal]);
    // The same file binned: in-sample by its bytes; its binned samples share nothing with the
    // run's, and no "about 0 %" is said.
    let label = ok(&["evaluate", &cal, &log, "--bin", "10"]);
    let first = label.lines().next().unwrap();
    assert!(
        first.contains("(in-sample: the calibration log)"),
        "{first}"
    );
    // Stamped from the epoch: the same samples.
    let (header, rows) = rows_of(&log);
    let epoch: Vec<String> = rows
        .iter()
        .map(|r| {
            let (t, rest) = r.split_once(',').unwrap();
            format!("{},{rest}", 1.7e9 + t.parse::<f64>().unwrap())
        })
        .collect();
    let path = p(dir.path(), "epoch.csv");
    std::fs::write(&path, format!("{header}\n{}\n", epoch.join("\n"))).unwrap();
    assert!(evaluate_in_sample(&cal, &path));
}

#[test]
fn a_unit_judged_on_a_log_of_its_own_and_other_axes_labels_each_axis() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "unit.json");
    let log = sample("imu3-calibration.csv");
    ok(&["calibrate", &log, "-o", &cal]);
    // gz replaced by the held-out run's gz: gx and gy are the calibration's own samples (the
    // file is a European spreadsheet's: `;` between cells, decimal commas).
    let (header, rows) = rows_of(&log);
    let (_, other) = rows_of(&sample("imu3-validation.csv"));
    let z = header
        .split(';')
        .position(|c| c == "gz_dps")
        .expect("gz_dps");
    let mixed: Vec<String> = rows
        .iter()
        .zip(&other)
        .map(|(mine, theirs)| {
            let mut cells: Vec<&str> = mine.split(';').collect();
            cells[z] = theirs.split(';').nth(z).unwrap();
            cells.join(";")
        })
        .collect();
    let path = p(dir.path(), "mixed.csv");
    std::fs::write(&path, format!("{header}\n{}\n", mixed.join("\n"))).unwrap();
    let text = ok(&["evaluate", &cal, &path]);
    let line = |axis: &str| {
        text.lines()
            .find(|l| l.starts_with(&format!("=== Axis {axis} ")))
            .unwrap_or_else(|| panic!("{text}"))
            .to_string()
    };
    assert!(
        text.lines()
            .next()
            .is_some_and(|l| l.contains("(in-sample on gx, gy; held out on gz)")),
        "{text}"
    );
    assert!(line("gx").contains("in-sample"), "{text}");
    assert!(line("gy").contains("in-sample"), "{text}");
    assert!(line("gz").contains("held out"), "{text}");
    // compare's summary of every axis says the same of the log.
    let text = ok(&[
        "compare", "--train", &log, "--test", &path, "--models", "poly-t",
    ]);
    assert!(
        text.contains("mixed.csv (in-sample on gx, gy; held out on gz)"),
        "{text}"
    );
}

/// The calibration log less some rows: a copy thinned to every other row (a 1 Hz logger
/// kept at 0.5 Hz), and one whose reader left out the rows with a blank temperature (one in
/// eight). No run of eight consecutive samples survives the first, few the second; every
/// sample does, and each is all the calibration log's.
#[test]
fn a_copy_less_some_rows_is_in_sample() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    let thinned: String = rows
        .iter()
        .enumerate()
        .filter(|(i, _)| *i == 0 || i % 2 == 1)
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    let blanked: String = rows
        .iter()
        .enumerate()
        .map(|(i, l)| {
            if i > 0 && i % 8 == 5 {
                // time, rate, temperature (blank), chamber
                let cells: Vec<&str> = l.split(',').collect();
                format!("{},{},,{}\n", cells[0], cells[1], cells[3])
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    for (name, body, label) in [
        (
            "thinned.csv",
            thinned,
            "a part of the calibration log, about",
        ),
        (
            "blanked.csv",
            blanked,
            "in-sample: a part of the calibration log",
        ),
    ] {
        std::fs::write(dir.path().join(name), body).unwrap();
        let log = p(dir.path(), name);
        let json: serde_json::Value =
            serde_json::from_str(&ok(&["evaluate", &cal, &log, "--json"])).unwrap();
        assert_eq!(json["in_sample"], true, "{name}");
        assert_eq!(json["in_sample_share"], 1.0, "{name}");
        // The share of the calibration log it holds: its samples counted, as every one of
        // them is the calibration log's (the file records the calibration log's count).
        let rows_kept = std::fs::read_to_string(dir.path().join(name))
            .unwrap()
            .lines()
            .filter(|l| !l.contains(",,"))
            .count()
            - 1;
        let want = rows_kept as f64 / (rows.len() - 1) as f64;
        let got = json["shared"]["share_of_calibration_log"].as_f64().unwrap();
        assert!((got - want).abs() < 1e-3, "{name}: {got} against {want}");
        let words = ok(&["evaluate", &cal, &log]);
        assert!(words.contains(label), "{name}: {}", &words[..200]);
    }
    // Another run, thinned the same way, is still held out.
    let other = std::fs::read_to_string(sample("validation.csv")).unwrap();
    let other: String = other
        .lines()
        .filter(|l| !l.starts_with('#'))
        .enumerate()
        .filter(|(i, _)| *i == 0 || i % 2 == 1)
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    std::fs::write(dir.path().join("other.csv"), other).unwrap();
    assert!(!evaluate_in_sample(&cal, &p(dir.path(), "other.csv")));
    // The validation log repeats the calibration run's first hour: held out, its share told
    // in JSON as in words.
    let json: serde_json::Value = serde_json::from_str(&ok(&[
        "evaluate",
        &cal,
        &sample("validation.csv"),
        "--json",
    ]))
    .unwrap();
    assert_eq!(json["in_sample"], false);
    let share = json["shared"]["share_of_log"].as_f64().unwrap();
    assert!((0.03..0.15).contains(&share), "{share}");
}

fn evaluate_json(cal: &str, log: &str) -> serde_json::Value {
    serde_json::from_str(&ok(&["evaluate", cal, log, "--json"])).unwrap()
}

/// `rows` (time, rate, temperature, ...) with the rate and the temperature rewritten.
fn rewrite(
    path: &str,
    header: &str,
    rows: &[String],
    rate: impl Fn(f64) -> String,
    temp: impl Fn(f64) -> String,
) {
    let body: String = rows
        .iter()
        .map(|r| {
            let mut cells: Vec<String> = r.split(',').map(String::from).collect();
            cells[1] = rate(cells[1].parse().unwrap());
            cells[2] = temp(cells[2].parse().unwrap());
            format!("{}\n", cells.join(","))
        })
        .collect();
    std::fs::write(path, format!("{header}\n{body}")).unwrap();
}

/// The calibration log converted without loss at its resolution (the rate in rad/s as
/// float32, as PX4, ArduPilot and ROS store it; with 9 significant digits; times 1.000001)
/// is all the calibration log; every rate moved by one step of its resolution is not.
#[test]
fn the_calibration_log_in_another_unit_without_loss_is_in_sample() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    let log = sample("calibration.csv");
    ok(&["calibrate", &log, "-o", &cal]);
    let (_, rows) = rows_of(&log);
    let to_rad = std::f64::consts::PI / 180.0 / 3600.0;
    let header = "time_s,gyro_x_rad_s,temp_c,temp_chamber_c";
    let same = |t: f64| format!("{t:.3}");
    let f32_path = p(d, "f32.csv");
    rewrite(
        &f32_path,
        header,
        &rows,
        |w| format!("{:.9e}", (w * to_rad) as f32),
        same,
    );
    let sig9 = p(d, "sig9.csv");
    rewrite(
        &sig9,
        header,
        &rows,
        |w| format!("{:.8e}", w * to_rad),
        same,
    );
    let scaled = p(d, "scaled.csv");
    let dph = "time_s,omega_dph,temp_c,temp_chamber_c";
    rewrite(&scaled, dph, &rows, |w| format!("{}", w * 1.000_001), same);
    for path in [&f32_path, &sig9, &scaled] {
        let json = evaluate_json(&cal, path);
        assert_eq!(json["in_sample"], true, "{path}");
        assert_eq!(json["in_sample_share"], 1.0, "{path}");
        assert_eq!(json["shared"]["share_of_calibration_log"], 1.0, "{path}");
    }
    // One LSB (0.0001 °/h) added to every rate: other numbers at the log's resolution.
    let lsb = p(d, "lsb.csv");
    rewrite(&lsb, dph, &rows, |w| format!("{:.4}", w + 0.0001), same);
    assert!(!evaluate_in_sample(&cal, &lsb));
}

/// Two independent runs of one program (seeds 1 and 2) written with a coarse rate: the
/// program's path sets their values, and the second shares nothing with the first.
#[test]
fn another_run_written_coarsely_is_held_out_sharing_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let other = p(d, "seed2.csv");
    ok(&["simulate", "--seed", "2", "--out", &other]);
    let (header, a_rows) = rows_of(&sample("calibration.csv"));
    let (_, b_rows) = rows_of(&other);
    for step in [0.5, 1.0, 2.0] {
        let coarse = |w: f64| format!("{}", (w / step).round() * step);
        let tenth = |t: f64| format!("{t:.1}");
        let (a, b) = (p(d, "a.csv"), p(d, "b.csv"));
        rewrite(&a, &header, &a_rows, coarse, tenth);
        rewrite(&b, &header, &b_rows, coarse, tenth);
        let cal = p(d, "a.json");
        ok(&["calibrate", &a, "-o", &cal]);
        let json = evaluate_json(&cal, &b);
        assert_eq!(json["in_sample"], false, "step {step}");
        assert!(json["shared"].is_null(), "step {step}: {}", json["shared"]);
    }
}

/// The calibration log followed by another run written twice: a third of its samples are
/// the calibration log's, and all of the calibration log is there.
#[test]
fn the_share_is_of_samples() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    let log = sample("calibration.csv");
    ok(&["calibrate", &log, "-o", &cal]);
    let other = p(d, "seed2.csv");
    ok(&["simulate", "--seed", "2", "--out", &other]);
    let (header, mine) = rows_of(&log);
    let (_, theirs) = rows_of(&other);
    let body: String = mine
        .iter()
        .chain(&theirs)
        .chain(&theirs)
        .enumerate()
        .map(|(i, r)| format!("{i},{}\n", r.split_once(',').unwrap().1))
        .collect();
    let path = p(d, "cat.csv");
    std::fs::write(&path, format!("{header}\n{body}")).unwrap();
    let json = evaluate_json(&cal, &path);
    assert_eq!(json["in_sample"], false);
    let share = json["shared"]["share_of_log"].as_f64().unwrap();
    assert!((0.25..0.42).contains(&share), "{share}");
    let of_cal = json["shared"]["share_of_calibration_log"].as_f64().unwrap();
    assert!(of_cal > 0.9, "{of_cal}");
}

/// A calibration written before values were hashed at the log's resolution (the sketch's
/// version-1 text, as the release before it wrote it for `calibration.csv`) still loads and
/// judges: a copy of its log is in-sample, the validation log held out with its shared hour.
#[test]
fn a_version_1_sketch_still_judges() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    let log = sample("calibration.csv");
    ok(&["calibrate", &log, "-o", &cal]);
    let old_sketch = include_str!("in_sample_v1_sketch.txt").trim();
    assert!(old_sketch.contains('+') && !old_sketch.contains(';'));
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    json.pointer_mut("/calibration/source/samples_sketch")
        .map(|s| *s = serde_json::Value::String(old_sketch.into()))
        .expect("a sketch");
    let old = p(d, "old.json");
    std::fs::write(&old, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    let copies = copies(d);
    assert!(evaluate_in_sample(&old, &copies[1]), "the bare copy");
    let json = evaluate_json(&old, &sample("validation.csv"));
    assert_eq!(json["in_sample"], false);
    let share = json["shared"]["share_of_log"].as_f64().unwrap();
    assert!((0.03..0.15).contains(&share), "{share}");
}
