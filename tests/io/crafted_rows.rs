//! Rows a crafted log slips in, each named by the reader with its line: an infinite cell (not
//! "blank or NaN"), rows with more cells than the file has columns, and a stray time stamp alone
//! at either end of the log, which would otherwise make a "1e300-s log".

use driftlab::log::ingest::{ReadOptions, read_bytes, read_rate_series};
use driftlab::log::{Problem, ProblemKind};

use crate::common;
use common::ingest::*;

/// The problems of one kind (shared with `stray_stamps.rs`).
pub(crate) fn problems(log: &driftlab::Log, kind: ProblemKind) -> Vec<Problem> {
    log.info
        .problems
        .iter()
        .filter(|p| p.kind == kind)
        .cloned()
        .collect()
}

#[test]
fn an_infinite_cell_is_named_as_infinite() {
    let text = "time,omega,temp\n0,1,20\n1,inf,20\n2,2,-Infinity\n3,3,20\n4,1e400,20\n5,,20\n";
    let log = read(text);
    close(&log.time_s, &[0.0, 3.0]);
    let miss = problems(&log, ProblemKind::MissingValue);
    assert_eq!(miss.len(), 3, "{miss:?}");
    // By column, then by kind: omega's infinite cells (lines 3 and 6), its blank (line 7), and
    // temp's infinite cell (line 4).
    let find = |needle: &str| {
        miss.iter()
            .find(|p| p.message.contains(needle))
            .unwrap_or_else(|| panic!("{needle}: {miss:?}"))
    };
    let inf = find("infinite value in column \"omega\"");
    assert_eq!((inf.line, inf.count, inf.column), (3, 2, Some(2)));
    assert!(inf.message.starts_with("2 rows dropped"), "{}", inf.message);
    let blank = find("blank or NaN in column \"omega\"");
    assert_eq!((blank.line, blank.count), (7, 1));
    let temp = find("infinite value in column \"temp\"");
    assert_eq!((temp.line, temp.count, temp.column), (4, 1, Some(3)));
    // None left: the refusal says infinite too.
    let e = fail(b"time,omega,temp\n0,inf,20\n1,2,inf\n", &opts());
    assert!(e.message.contains("blank, NaN or infinite value"), "{e}");
}

#[test]
fn an_infinite_rate_stops_a_rate_series_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rate.txt");
    std::fs::write(&path, "rate\n1\n2\ninf\n3\n").unwrap();
    let e = read_rate_series(&path, &ReadOptions::default()).unwrap_err();
    assert_eq!(e.line, 4, "{e}");
    assert!(e.message.contains("\"inf\" is infinite"), "{e}");
}

/// The problem for rows longer than the file's columns.
fn long_rows(log: &driftlab::Log) -> Option<Problem> {
    problems(log, ProblemKind::RaggedRow)
        .into_iter()
        .find(|p| p.message.contains("more fields than"))
}

#[test]
fn rows_with_extra_cells_are_counted_with_their_first_line() {
    // Every column read (the fast path) and extra cells on rows 2 and 4 (lines 3 and 5).
    let text = "time,omega,temp\n0,1,20\n1,2,21,9,9\n2,3,22\n3,4,23,\n4,5,24\n";
    let log = read(text);
    close(&log.temp_c, &[20.0, 21.0, 22.0, 23.0, 24.0]);
    let p = long_rows(&log).expect("told");
    assert_eq!((p.line, p.count), (3, 2), "{p:?}");
    assert!(
        p.message
            .starts_with("2 rows have more fields than the file's 3 columns; the extra cells"),
        "{}",
        p.message
    );
    // A trailing column that is not read (text): rows of its length are fine, longer are not.
    let text = "time,omega,temp,note\n0,1,20,a\n1,2,21,b\n2,3,22,c,d\n3,4,23\n";
    let log = read(text);
    let p = long_rows(&log).expect("told");
    assert_eq!((p.line, p.count), (4, 1), "{p:?}");
    // Columns separated by blanks, trailing blanks being no field.
    let text = "time omega temp\n0 1 20  \n1 2 21 7\n2 3 22\n";
    let p = long_rows(&read(text)).expect("told");
    assert_eq!((p.line, p.count), (3, 1), "{p:?}");
    // Quoted cells send rows down the careful path: counted the same.
    let text = "time,omega,temp,note\n0,1,20,\"a\"\n1,2,21,\"b\",\"c\"\n2,3,22,\"d\"\n";
    let p = long_rows(&read(text)).expect("told");
    assert_eq!((p.line, p.count), (3, 1), "{p:?}");
    // Rows of the header's length: nothing to tell.
    let text = "time,omega,temp\n0,1,20\n1,2,21\n";
    assert!(long_rows(&read(text)).is_none());
}

/// The 1 Hz log of `n` rows with `first` and `last` in place of the first and last stamps.
fn log_text(n: usize, first: Option<&str>, last: Option<&str>) -> String {
    let mut s = String::from("time_s,omega_dph,temp_c\n");
    for i in 0..n {
        let t = match (i, first, last) {
            (0, Some(f), _) => f.to_string(),
            (i, _, Some(l)) if i == n - 1 => l.to_string(),
            _ => i.to_string(),
        };
        s += &format!("{t},0.1,{}\n", 20.0 + i as f64 * 0.01);
    }
    s
}

/// The problems of stray time stamps (shared with `stray_stamps.rs`).
pub(crate) fn stray(log: &driftlab::Log) -> Vec<Problem> {
    problems(log, ProblemKind::TimeBackwards)
        .into_iter()
        .filter(|p| p.message.contains("stray time stamp"))
        .collect()
}

#[test]
fn a_stray_last_stamp_is_dropped_with_its_line() {
    let log = read(&log_text(1000, None, Some("1e300")));
    assert_eq!(log.len(), 999);
    assert_eq!(log.duration_s(), 998.0);
    assert_eq!(log.info.rows_read, 1000);
    let s = stray(&log);
    assert_eq!(s.len(), 1, "{:?}", log.info.problems);
    // Row 1000 is on line 1001.
    assert_eq!((s[0].line, s[0].column, s[0].count), (1001, Some(1), 1));
    assert!(
        s[0].message
            .contains("its time 1e300 s stands alone 1e300 s after the rest of the log"),
        "{}",
        s[0].message
    );
    // No gap is left to report: the log is one segment.
    assert!(problems(&log, ProblemKind::Gap).is_empty());
    assert!(log.timing().is_contiguous());
}

#[test]
fn a_stray_first_stamp_is_dropped_with_its_line() {
    for first in ["-1e300", "-1700000000"] {
        let log = read(&log_text(1000, Some(first), None));
        assert_eq!(log.time_s[0], 1.0, "{first}");
        assert_eq!(log.duration_s(), 998.0);
        let s = stray(&log);
        assert_eq!(s.len(), 1, "{first}: {:?}", log.info.problems);
        assert_eq!(s[0].line, 2);
        assert!(s[0].message.contains("before the rest of the log"));
    }
    // Both ends, and a second stray behind the first: all dropped, each with its line.
    let mut text = log_text(1000, Some("-1e300"), Some("1e300"));
    text.insert_str(text.rfind("1e300,").unwrap(), "1e299,0.1,20\n");
    let log = read(&text);
    assert_eq!((log.time_s[0], log.duration_s()), (1.0, 997.0));
    let lines: Vec<usize> = stray(&log).iter().map(|p| p.line).collect();
    assert_eq!(lines, [2, 1001, 1002], "{:?}", log.info.problems);
}

#[test]
fn a_lone_sample_after_an_ordinary_gap_is_kept() {
    // A gap of 50 times the 998-s run before it: an outage, kept and told as a gap.
    let log = read(&log_text(1000, None, Some("50898")));
    assert_eq!(log.len(), 1000);
    assert!(stray(&log).is_empty());
    assert_eq!(problems(&log, ProblemKind::Gap).len(), 1);
    // Past a hundred times: a stray stamp.
    let log = read(&log_text(1000, None, Some("101000")));
    assert_eq!(log.len(), 999);
    assert_eq!(stray(&log).len(), 1);
    // Three samples far away are a segment, not stray stamps (a glitch garbles a row or two,
    // tests/io/stray_stamps.rs): kept, and the gap told.
    let mut text = log_text(100, None, None);
    text += "1e9,0.1,20\n1000000001,0.1,20\n1000000002,0.1,20\n";
    let log = read(&text);
    assert_eq!(log.len(), 103);
    assert!(stray(&log).is_empty());
    assert_eq!(problems(&log, ProblemKind::Gap).len(), 1);
}

#[test]
fn a_two_row_log_is_not_a_stray_stamp() {
    let log = read_bytes("two.csv", b"time,omega,temp\n0,1,20\n1e300,1,20\n", &opts()).unwrap();
    assert_eq!(log.len(), 2);
}

#[test]
fn a_stray_last_stamp_of_a_drone_log_is_dropped_with_its_sample() {
    // A PX4 ULog at 1 Hz whose last message is stamped a million seconds later.
    let mut time_s: Vec<f64> = (0..600).map(f64::from).collect();
    time_s.push(1e6);
    let gyro = vec![[0.001f32, 0.0, 0.0]; time_s.len()];
    let temp: Vec<f32> = (0..time_s.len()).map(|i| 20.0 + i as f32 * 0.01).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("stray.ulg");
    std::fs::write(&path, common::drone::ulog(&time_s, &gyro, &temp, 1)).unwrap();
    let log = driftlab::log::read::read_any(&path, &opts(), &Default::default())
        .unwrap()
        .log;
    assert_eq!(log.len(), 600);
    assert_eq!(log.duration_s(), 599.0);
    let s = stray(&log);
    assert_eq!(s.len(), 1, "{:?}", log.info.problems);
    assert_eq!(s[0].line, 601);
    assert!(s[0].message.contains("(sample 601)"), "{}", s[0].message);
}

#[test]
fn a_drone_log_running_newest_first_is_refused_as_a_csv_is() {
    // The same 8000 samples with their stamps reversed: every sample after the first went
    // "back in time", and the reader kept one sample of 8000 (`apply` wrote one row and
    // succeeded). Refused, as the CSV reader refuses rows written newest first.
    let time_s: Vec<f64> = (0..8000).rev().map(|i| f64::from(i) * 0.1).collect();
    let gyro = vec![[0.001f32, 0.0, 0.0]; time_s.len()];
    let temp: Vec<f32> = (0..time_s.len()).map(|i| 20.0 + i as f32 * 0.001).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("backwards.ulg");
    std::fs::write(&path, common::drone::ulog(&time_s, &gyro, &temp, 1)).unwrap();
    let e = driftlab::log::read::read_any(&path, &opts(), &Default::default())
        .expect_err("refused")
        .to_string();
    assert!(
        e.contains("7999 of the 8000 samples") && e.contains("not in time order"),
        "{e}"
    );
    assert!(e.starts_with(&path.display().to_string()), "{e}");
    // A log that goes back once, late, keeps what came before, and says so.
    let mut once: Vec<f64> = (0..8000).map(|i| f64::from(i) * 0.1).collect();
    once[7000..].iter_mut().for_each(|t| *t -= 50.0);
    let path = dir.path().join("once.ulg");
    std::fs::write(&path, common::drone::ulog(&once, &gyro, &temp, 1)).unwrap();
    let log = driftlab::log::read::read_any(&path, &opts(), &Default::default())
        .unwrap()
        .log;
    assert!(log.len() > 7000, "{}", log.len());
}
