//! A time column whose numbers, in the unit they are read in, are no chamber run's time. The
//! bundled calibration log (1 s steps over 11.2 h) is written here in ms under a name that states
//! no unit, and in ns since the epoch under `time_s`: the reader names the time column, what it
//! read it as, and the unit the test wrote it in, before any fit speaks of slow ramps. Stamps at
//! the ends of the double range (steps of 1e-300 s, a span past the largest double) are refused
//! at their line, never printed as `inf`. The truth each check is held to is the unit the test
//! wrote the stamps in.

use driftlab::log::ingest::{ReadOptions, TimeUnit, read_bytes};
use driftlab::log::{Log, ProblemKind};

use crate::common;
use common::run::{driftlab, p, sample};

/// The bundled calibration log's rows (time in s, 1 s apart), without its comment line.
fn calibration_rows() -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

/// The calibration log with its time column named `time_name` and written as
/// `offset + t · per_s` (the time in s turned into the test's unit), every other column as is.
fn rewritten(time_name: &str, per_s: f64, offset: f64) -> String {
    let mut out = format!("{time_name},omega_dph,temp_c,temp_chamber_c\n");
    for row in calibration_rows() {
        let t: f64 = row[0].parse().unwrap();
        out.push_str(&format!("{}", offset + t * per_s));
        for cell in &row[1..] {
            out.push(',');
            out.push_str(cell);
        }
        out.push('\n');
    }
    out
}

fn read(text: &str, o: &ReadOptions) -> Log {
    read_bytes("t.csv", text.as_bytes(), o).unwrap()
}

/// The problem that doubts the time column, if any.
fn time_doubt(log: &Log) -> Option<String> {
    log.info
        .problems
        .iter()
        .find(|p| p.kind == ProblemKind::Implausible && p.column == Some(1))
        .map(|p| p.message.clone())
}

#[test]
fn a_time_in_ms_or_ns_read_as_seconds_is_told_with_the_unit_it_was_written_in() {
    // (time column's name, the unit the test writes it in, s → that unit, epoch offset)
    for (name, unit, per_s, offset) in [
        ("time", TimeUnit::Millis, 1e3, 0.0),
        ("time_s", TimeUnit::Nanos, 1e9, 1.7e18),
    ] {
        let text = rewritten(name, per_s, offset);
        let log = read(&text, &ReadOptions::default());
        let told = time_doubt(&log).unwrap_or_else(|| panic!("{name}: {:?}", log.info.problems));
        for want in [
            format!("\"{name}\""),
            "read in s".to_string(),
            format!("time_unit {unit}"),
        ] {
            assert!(told.contains(&want), "{name}: {want:?} not in: {told}");
        }
        assert!(!told.contains("inf") && !told.contains("NaN"), "{told}");

        // Read in the unit the numbers were written in, the log is the 1 s calibration log
        // again, and nothing doubts its time.
        let o = ReadOptions {
            time_unit: Some(unit),
            ..ReadOptions::default()
        };
        let log = read(&text, &o);
        assert_eq!(time_doubt(&log), None, "{name}: {:?}", log.info.problems);
        let rows = calibration_rows();
        let last: f64 = rows[rows.len() - 1][0].parse().unwrap();
        let span = log.time_s[log.len() - 1] - log.time_s[0];
        assert!(
            (span - last).abs() < 1e-3,
            "{name}: span {span} s, not {last} s"
        );
    }
}

#[test]
fn the_bundled_logs_time_is_not_doubted() {
    for name in ["calibration.csv", "validation.csv", "imu3-calibration.csv"] {
        let log = driftlab::read_path(std::path::Path::new(&sample(name)), &ReadOptions::default())
            .unwrap();
        assert_eq!(time_doubt(&log), None, "{name}");
    }
}

#[test]
fn calibrate_names_the_time_column_before_any_ramp() {
    let dir = tempfile::tempdir().unwrap();
    let path = p(dir.path(), "ms.csv");
    std::fs::write(&path, rewritten("time", 1e3, 0.0)).unwrap();
    let out = driftlab(&["calibrate", &path, "-o", &p(dir.path(), "c.json")]);
    let err = String::from_utf8_lossy(&out.stderr);
    let time = err
        .find("the time column \"time\"")
        .unwrap_or_else(|| panic!("the time column is not named: {err}"));
    assert!(err[time..].contains("--time-unit ms"), "{err}");
    // Whatever else is said comes after it: no fit's reason first.
    let first_said = err
        .find("warning:")
        .into_iter()
        .chain(err.find("error:"))
        .min()
        .unwrap();
    assert!(err[first_said..time].lines().count() <= 1, "{err}");
    assert!(!err.contains("time_unit"), "{err}");

    // Given the unit it was written in, the same log calibrates.
    let out = driftlab(&[
        "calibrate",
        &path,
        "--time-unit",
        "ms",
        "-o",
        &p(dir.path(), "c.json"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A log of `n` rows whose stamps are `stamp(i)`, in s, under `time_s`.
fn stamped(n: usize, stamp: impl Fn(usize) -> f64) -> String {
    let mut text = "time_s,omega_dph,temp_c\n".to_string();
    for i in 0..n {
        text.push_str(&format!(
            "{:e},{},{}\n",
            stamp(i),
            0.1 * (i % 13) as f64,
            20.0 + 0.001 * (i % 3) as f64
        ));
    }
    text
}

#[test]
fn stamps_at_the_ends_of_the_double_range_are_refused_at_their_line() {
    // (log, the file line the refusal must name: the second row, whose step is the first)
    let cases = [
        (stamped(2000, |i| i as f64 * 1e-300), 3),
        (stamped(2000, |i| i as f64 * 5e-324), 3),
        // Half a gigahertz's step: shorter than any sampling interval driftlab takes.
        (stamped(2000, |i| i as f64 * 5e-10), 3),
        // The span from the first stamp past the largest double, at the second.
        (
            "time_s,omega_dph,temp_c\n-1.7e308,1,20\n1.7e308,2,30\n1.79e308,1,40\n".to_string(),
            3,
        ),
    ];
    for (text, line) in cases {
        let e = read_bytes("t.csv", text.as_bytes(), &ReadOptions::default()).unwrap_err();
        assert_eq!(e.line, line, "{e}");
        assert_eq!(e.column, 1, "{e}");
        assert!(
            e.message.contains("\"time_s\"")
                && e.message.contains("time_unit")
                && !e.message.contains("inf"),
            "{e}"
        );
    }

    // The fastest sampling the sample-rate setting takes, a gigahertz, is read as written.
    let log = read(&stamped(2000, |i| i as f64 * 1e-9), &ReadOptions::default());
    let step = (log.time_s[1999] - log.time_s[0]) / 1999.0;
    assert!((step - 1e-9).abs() < 1e-18, "{step}");

    // On the command line: the flag, and no inf anywhere.
    let dir = tempfile::tempdir().unwrap();
    let path = p(dir.path(), "sub.csv");
    std::fs::write(&path, stamped(2000, |i| i as f64 * 1e-300)).unwrap();
    let out = driftlab(&["inspect", &path]);
    assert!(!out.status.success());
    let all =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(
        all.contains("--time-unit") && !all.contains("inf") && !all.contains("Hz)"),
        "{all}"
    );
}

#[test]
fn a_long_run_in_a_stated_unit_is_not_doubted_but_one_past_a_year_is() {
    // A static run of 15 days at a minute a sample, its time in s as its name says: a real
    // Allan run, not a unit slip (it was told to use ms).
    let two_weeks = stamped(21_600, |i| 60.0 * i as f64);
    assert_eq!(time_doubt(&read(&two_weeks, &ReadOptions::default())), None);
    // The calibration log in ms under `time_s`: 465 days in the unit its name states.
    let ms = rewritten("time_s", 1e3, 0.0);
    let told = time_doubt(&read(&ms, &ReadOptions::default())).expect("doubted");
    assert!(told.contains("time_unit ms"), "{told}");
}

/// The problem that tells a temperature moving faster than any chamber moves a gyro's.
fn too_fast(log: &Log) -> Option<&driftlab::log::Problem> {
    log.info.problems.iter().find(|p| {
        p.message
            .contains("faster than any chamber moves a gyro's temperature")
    })
}

#[test]
fn a_time_in_minutes_read_as_seconds_is_told_by_the_temperatures_rate() {
    // The calibration log (1 °C/min ramps, 11.2 h at 1 s) with its time in minutes under a
    // name that states no unit, as chamber controllers write it: read as s, the run lasts
    // 11 minutes and the ramps go at 1 °C/s.
    let text = rewritten("time", 1.0 / 60.0, 0.0);
    let log = read(&text, &ReadOptions::default());
    let told = too_fast(&log).unwrap_or_else(|| panic!("{:?}", log.info.problems));
    assert_eq!(
        (told.kind, told.column),
        (ProblemKind::Implausible, Some(3))
    );
    // The truth: the first row whose temperature, in the seconds it was written in, moves by
    // more than 0.5 °C in the next minute (30 °C/min read in minutes as seconds).
    let rows = calibration_rows();
    let temp: Vec<f64> = rows.iter().map(|r| r[2].parse().unwrap()).collect();
    let first = (0..temp.len() - 60)
        .find(|&i| (temp[i + 60] - temp[i]).abs() > 0.5)
        .unwrap();
    let line = first + 2; // the header, and lines counted from 1
    assert!(
        told.line.abs_diff(line) <= 300,
        "told at line {}, the ramp passes 30 °C/min at line {line}",
        told.line
    );
    for want in [
        format!("first at line {}", told.line),
        "the time column \"time\", read in s (the default".to_string(),
        "may count minutes: in minutes the run lasts 11.2 h at steps of 1 s".to_string(),
        "time_unit min".to_string(),
    ] {
        assert!(
            told.message.contains(&want),
            "{want:?} not in: {}",
            told.message
        );
    }
    // Read in minutes, it is the calibration log again, and nothing is told.
    let o = ReadOptions {
        time_unit: Some(TimeUnit::Minutes),
        ..ReadOptions::default()
    };
    let log = read(&text, &o);
    assert_eq!(too_fast(&log), None, "{:?}", log.info.problems);
    let last: f64 = rows[rows.len() - 1][0].parse().unwrap();
    let span = log.time_s[log.len() - 1] - log.time_s[0];
    assert!(
        (span - last).abs() < 1e-6 * last,
        "span {span} s, not {last} s"
    );

    // The command line lists it among the problems, and calibrate warns of it.
    let dir = tempfile::tempdir().unwrap();
    let path = p(dir.path(), "minutes.csv");
    std::fs::write(&path, &text).unwrap();
    let out = driftlab(&["inspect", &path]);
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        !said.contains("problems: none") && said.contains("--time-unit min"),
        "{said}"
    );
    let out = driftlab(&["calibrate", &path, "-o", &p(dir.path(), "c.json")]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("warning:") && err.contains("--time-unit min"),
        "{err}"
    );
}

#[test]
fn a_temperature_faster_than_a_chamber_in_a_stated_unit_or_out_of_order_is_told() {
    // Minutes under `time_s`: the name states seconds, so no other unit is offered, but the
    // rate is told and the unit is to be checked.
    let log = read(
        &rewritten("time_s", 1.0 / 60.0, 0.0),
        &ReadOptions::default(),
    );
    let told = too_fast(&log).unwrap_or_else(|| panic!("{:?}", log.info.problems));
    assert!(
        told.message
            .contains("read in s (as its name says): check its unit (time_unit)")
            && !told.message.contains("time_unit min"),
        "{}",
        told.message
    );
    // The calibration log's blocks of 1000 rows in reverse order, stamped anew 1 s apart:
    // the temperature steps at every joint that is not on a plateau.
    let rows = calibration_rows();
    let mut text = "time_s,omega_dph,temp_c,temp_chamber_c\n".to_string();
    for (i, row) in rows.chunks(1000).rev().flatten().enumerate() {
        text.push_str(&format!("{i},{}\n", row[1..].join(",")));
    }
    let log = read(&text, &ReadOptions::default());
    let told = too_fast(&log).unwrap_or_else(|| panic!("{:?}", log.info.problems));
    assert!(told.count >= 3, "{told:?}");
    assert!(told.message.contains("the rows' order"), "{}", told.message);
    assert_eq!(log.len(), rows.len(), "the samples are kept");
}
