//! Stray time stamps in the middle of a log: a clock glitch stamps a row (or two side by side)
//! 1e6 s, 1e300 s or 0 between rows that keep time. Both readers (CSV, and a drone log's) must
//! drop exactly the glitched rows and say so with their line, and nothing else: the log reads as
//! the clean file does, with its duration, and a genuine gap stays a gap.
//!
//! The truth each read is held to is the clean file's read (the same rows without the glitch),
//! never a value taken from the reader's own output.

use driftlab::log::ProblemKind;

use crate::common;
use crate::crafted_rows::{problems as kinds, stray as strays};
use common::ingest::*;

/// Rows at 1 Hz from 100 s on, each with its own rate and temperature, so that a log that
/// lost or kept the wrong row cannot equal another.
fn rows(n: usize) -> Vec<String> {
    (0..n)
        .map(|i| {
            format!(
                "{},{},{}",
                100 + i,
                0.001 * (i % 97) as f64,
                20.0 + 0.01 * i as f64
            )
        })
        .collect()
}

fn text(rows: &[String]) -> String {
    let mut s = String::from("time_s,omega_dph,temp_c\n");
    for r in rows {
        s += r;
        s.push('\n');
    }
    s
}

/// The file line of row `i` (0-based) of [`text`]: the header is line 1.
fn line_of_row(i: usize) -> usize {
    i + 2
}

/// The columns, duration and timing of `got` are those of `want`.
fn same_log(got: &driftlab::Log, want: &driftlab::Log, what: &str) {
    assert_eq!(got.time_s, want.time_s, "{what}: {:?}", got.info.problems);
    assert_eq!(got.omega_dph, want.omega_dph, "{what}");
    assert_eq!(got.temp_c, want.temp_c, "{what}");
    assert_eq!(got.duration_s(), want.duration_s(), "{what}");
    assert_eq!(got.timing(), want.timing(), "{what}");
}

#[test]
fn stray_rows_slipped_in_read_as_the_clean_log() {
    let clean_rows = rows(3000);
    let clean = read(&text(&clean_rows));
    assert!(clean.info.problems.is_empty(), "{:?}", clean.info.problems);
    // Glitched rows slipped in after row 1500: the rows around them keep the 1-s step.
    for glitch in [
        &["1000000"][..],
        &["1e300"],
        &["0"],
        &["-1e300"],
        &["1000000", "1000001"],
        &["1000000", "0"],
        &["0", "1"],
    ] {
        let mut r = clean_rows.clone();
        for (k, t) in glitch.iter().enumerate() {
            r.insert(1501 + k, format!("{t},0.5,99"));
        }
        let log = read(&text(&r));
        same_log(&log, &clean, &format!("{glitch:?}"));
        assert_eq!(log.info.rows_read, 3000 + glitch.len());
        let s = strays(&log);
        assert_eq!(s.len(), 1, "{glitch:?}: {:?}", log.info.problems);
        assert_eq!(
            (s[0].line, s[0].count, s[0].column),
            (line_of_row(1501), glitch.len(), Some(1)),
            "{glitch:?}: {}",
            s[0].message
        );
        assert!(
            s[0].message
                .contains(&format!("(line {})", line_of_row(1501))),
            "{}",
            s[0].message
        );
        // Nothing else to tell: no time going backwards, no gap.
        assert_eq!(log.info.problems.len(), 1, "{:?}", log.info.problems);
    }
}

#[test]
fn a_glitched_stamp_drops_its_row_and_no_other() {
    let clean_rows = rows(3000);
    // The stamps of rows 1500 (and 1501) garbled: the log is the clean one without those rows.
    for glitch in [
        &["1000000"][..],
        &["0"],
        &["1e300"],
        &["1000000", "1000001"],
    ] {
        let mut r = clean_rows.clone();
        let mut without = clean_rows.clone();
        for (k, t) in glitch.iter().enumerate() {
            let cells = r[1500 + k].split_once(',').unwrap().1.to_string();
            r[1500 + k] = format!("{t},{cells}");
        }
        without.drain(1500..1500 + glitch.len());
        let log = read(&text(&r));
        let want = read(&text(&without));
        same_log(&log, &want, &format!("{glitch:?}"));
        assert_eq!(log.duration_s(), 2999.0, "{glitch:?}");
        let s = strays(&log);
        assert_eq!(s.len(), 1, "{glitch:?}: {:?}", log.info.problems);
        assert_eq!((s[0].line, s[0].count), (line_of_row(1500), glitch.len()));
        // Whatever else is told is what the clean file without those rows tells (two rows
        // missing at 1 Hz are a hole of 3 s, which is a gap).
        let others = |l: &driftlab::Log| -> Vec<ProblemKind> {
            l.info
                .problems
                .iter()
                .filter(|p| !p.message.contains("stray time stamp"))
                .map(|p| p.kind)
                .collect()
        };
        assert_eq!(others(&log), others(&want), "{glitch:?}");
    }
}

#[test]
fn strays_in_several_places_are_told_once_with_the_first_line() {
    let clean_rows = rows(3000);
    let clean = read(&text(&clean_rows));
    let mut r = clean_rows.clone();
    // From the end, so that the earlier places keep their index.
    for at in [2500, 1000, 200] {
        r.insert(at, "1e9,0.5,99".to_string());
    }
    let log = read(&text(&r));
    same_log(&log, &clean, "three strays");
    let s = strays(&log);
    assert_eq!(s.len(), 1, "{:?}", log.info.problems);
    assert_eq!((s[0].line, s[0].count), (line_of_row(200), 3));
    assert!(s[0].message.contains("in 3 places"), "{}", s[0].message);
}

#[test]
fn a_genuine_gap_stays_a_gap() {
    // An hour's pause of the chamber: time goes on from the later value.
    let mut r = rows(3000);
    for (i, row) in r.iter_mut().enumerate().skip(1500) {
        let cells = row.split_once(',').unwrap().1.to_string();
        *row = format!("{},{cells}", 100 + i + 3600);
    }
    let log = read(&text(&r));
    assert_eq!(log.len(), 3000);
    assert!(strays(&log).is_empty(), "{:?}", log.info.problems);
    let gaps = kinds(&log, ProblemKind::Gap);
    assert_eq!(gaps.len(), 1, "{:?}", log.info.problems);
    assert_eq!(gaps[0].line, line_of_row(1500));
    assert_eq!(log.timing().segments, vec![0..1500, 1500..3000]);

    // A lone sample between two outages is data between two gaps, not a stray stamp.
    let mut r = rows(3000);
    for (i, row) in r.iter_mut().enumerate().skip(1500) {
        let late = if i == 1500 { 3600 } else { 7200 };
        let cells = row.split_once(',').unwrap().1.to_string();
        *row = format!("{},{cells}", 100 + i + late);
    }
    let log = read(&text(&r));
    assert_eq!(log.len(), 3000);
    assert!(strays(&log).is_empty(), "{:?}", log.info.problems);
    assert_eq!(log.timing().gaps.len(), 2);
}

#[test]
fn time_that_is_set_back_is_not_a_stray_stamp() {
    // The clock set back 50 s for good (not a glitch: the rows after the step keep the new
    // time): the rows up to the old time are dropped as going backwards, as before.
    let mut r = rows(3000);
    for (i, row) in r.iter_mut().enumerate().skip(1500) {
        let cells = row.split_once(',').unwrap().1.to_string();
        *row = format!("{},{cells}", 100 + i - 50);
    }
    let log = read(&text(&r));
    assert!(strays(&log).is_empty(), "{:?}", log.info.problems);
    let back = kinds(&log, ProblemKind::TimeBackwards);
    let rep = kinds(&log, ProblemKind::TimeRepeated);
    assert_eq!((back.len(), rep.len()), (1, 1), "{:?}", log.info.problems);
    assert_eq!(back[0].count + rep[0].count, 50);
}

#[test]
fn two_stray_rows_at_an_end_are_dropped_with_their_lines() {
    // 1000 rows (999 s), then two rows a step apart 1e9 s on: more than a hundred times the
    // log, a segment of two samples that no window fits in.
    let clean_rows = rows(1000);
    let clean = read(&text(&clean_rows));
    let mut r = clean_rows.clone();
    r.push("1000000000,0.5,99".into());
    r.push("1000000001,0.5,99".into());
    let log = read(&text(&r));
    same_log(&log, &clean, "two at the end");
    let s = strays(&log);
    assert_eq!(s.len(), 1, "{:?}", log.info.problems);
    assert_eq!((s[0].line, s[0].count), (line_of_row(1000), 2));
    assert!(
        s[0].message.contains(&format!(
            "(lines {} and {})",
            line_of_row(1000),
            line_of_row(1001)
        )),
        "{}",
        s[0].message
    );
    assert!(kinds(&log, ProblemKind::Gap).is_empty());
    // At the start too.
    let mut r = clean_rows.clone();
    r.insert(0, "-1000000001,0.5,99".into());
    r.insert(1, "-1000000000,0.5,99".into());
    let log = read(&text(&r));
    same_log(&log, &clean, "two at the start");
    assert_eq!(strays(&log)[0].line, line_of_row(0));
    // An outage of a few times the log, then two rows: kept, and the gap told.
    let mut r = clean_rows.clone();
    r.push("50000,0.5,99".into());
    r.push("50001,0.5,99".into());
    let log = read(&text(&r));
    assert_eq!(log.len(), 1002);
    assert!(strays(&log).is_empty(), "{:?}", log.info.problems);
    assert_eq!(kinds(&log, ProblemKind::Gap).len(), 1);
}

/// A PX4 ULog at 1 Hz with these stamps.
fn ulog_log(time_s: &[f64]) -> driftlab::Log {
    let gyro: Vec<[f32; 3]> = (0..time_s.len())
        .map(|i| [0.001 * (i % 97) as f32, 0.0, 0.0])
        .collect();
    let temp: Vec<f32> = (0..time_s.len()).map(|i| 20.0 + i as f32 * 0.01).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("log.ulg");
    std::fs::write(&path, common::drone::ulog(time_s, &gyro, &temp, 1)).unwrap();
    driftlab::log::read::read_any(&path, &opts(), &Default::default())
        .unwrap()
        .log
}

#[test]
fn a_drone_log_drops_a_stray_stamp_by_the_same_rule() {
    let clean_t: Vec<f64> = (0..1200).map(|i| 100.0 + f64::from(i)).collect();
    for glitch in [&[1e6][..], &[0.0], &[1e6, 1e6 + 1.0]] {
        let mut t = clean_t.clone();
        for (k, &g) in glitch.iter().enumerate() {
            t[600 + k] = g;
        }
        let mut without = clean_t.clone();
        without.drain(600..600 + glitch.len());
        let log = ulog_log(&t);
        assert_eq!(log.time_s, without, "{glitch:?}: {:?}", log.info.problems);
        assert_eq!(log.duration_s(), 1199.0);
        let s = strays(&log);
        assert_eq!(s.len(), 1, "{glitch:?}: {:?}", log.info.problems);
        // Sample 601 is the 600th of the instance, counted from 0.
        assert_eq!((s[0].line, s[0].count), (601, glitch.len()));
        assert!(s[0].message.contains("(sample 601)"), "{}", s[0].message);
        // The rows kept are the clean log's rows without the glitched ones, rate and all.
        let mut rate = ulog_log(&clean_t).omega_dph;
        rate.drain(600..600 + glitch.len());
        assert_eq!(log.omega_dph, rate);
    }
}

#[test]
fn a_stray_stamp_ahead_at_the_start_or_behind_at_the_end_reads_as_the_clean_log() {
    // With one neighbour only, the rows on the other side vouch: a first row stamped far
    // ahead made every later row "go backwards" (the whole log dropped); a last row stamped
    // far behind was only told as time going backwards.
    let clean_rows = rows(3000);
    let clean = read(&text(&clean_rows));
    for glitch in [&["1000000"][..], &["1e300"], &["1000000", "1000001"]] {
        let mut r = clean_rows.clone();
        for (k, t) in glitch.iter().enumerate() {
            r.insert(k, format!("{t},0.5,99"));
        }
        let log = read(&text(&r));
        same_log(&log, &clean, &format!("start {glitch:?}"));
        let s = strays(&log);
        assert_eq!(s.len(), 1, "{glitch:?}: {:?}", log.info.problems);
        assert_eq!((s[0].line, s[0].count), (line_of_row(0), glitch.len()));
        assert!(
            s[0].message.contains("the rows after") && s[0].message.contains("from 100 s on"),
            "{}",
            s[0].message
        );
    }
    for glitch in [&["0"][..], &["-1e300"], &["5", "6"]] {
        let mut r = clean_rows.clone();
        for t in glitch {
            r.push(format!("{t},0.5,99"));
        }
        let log = read(&text(&r));
        same_log(&log, &clean, &format!("end {glitch:?}"));
        let s = strays(&log);
        assert_eq!(s.len(), 1, "{glitch:?}: {:?}", log.info.problems);
        assert_eq!((s[0].line, s[0].count), (line_of_row(3000), glitch.len()));
        assert!(
            s[0].message.contains("the rows before") && s[0].message.contains("up to 3099 s"),
            "{}",
            s[0].message
        );
    }
    // A clock set back at the end for good (a run of rows of its own) is no stray: told as
    // time going backwards, as before.
    let mut r = clean_rows.clone();
    r.extend((0..5).map(|i| format!("{i},0.5,99")));
    let log = read(&text(&r));
    assert!(strays(&log).is_empty(), "{:?}", log.info.problems);
}

/// The problems that tell a run stamped ahead of the rows after it.
fn ahead(log: &driftlab::Log) -> Vec<driftlab::log::Problem> {
    kinds(log, ProblemKind::TimeBackwards)
        .into_iter()
        .filter(|p| p.message.contains("stamped ahead"))
        .collect()
}

#[test]
fn a_longer_run_stamped_ahead_drops_the_run_not_the_hours_after_it() {
    // Three rows or more side by side stamped +10,000 s are no stray stamp (those are one or
    // two rows), but the rows after them go on from the rows before: read first way only,
    // the three were kept and the 1,500 rows after them dropped as going backwards.
    let clean_rows = rows(3000);
    for (at, run) in [(1500, 3), (1500, 40), (0, 3)] {
        let mut r = clean_rows.clone();
        for (i, row) in r.iter_mut().enumerate().skip(at).take(run) {
            let cells = row.split_once(',').unwrap().1.to_string();
            *row = format!("{},{cells}", 100 + i + 10_000);
        }
        let mut kept = clean_rows.clone();
        kept.drain(at..at + run);
        let log = read(&text(&r));
        let want = read(&text(&kept));
        assert_eq!(
            log.time_s, want.time_s,
            "{at} {run}: {:?}",
            log.info.problems
        );
        assert_eq!(log.omega_dph, want.omega_dph);
        let a = ahead(&log);
        assert_eq!(a.len(), 1, "{at} {run}: {:?}", log.info.problems);
        assert_eq!((a[0].line, a[0].count), (line_of_row(at), run));
        assert!(
            a[0].message.contains(&format!(
                "the log goes on at line {} with {} s",
                line_of_row(at + run),
                100 + at + run
            )),
            "{}",
            a[0].message
        );
    }
}

#[test]
fn a_drone_log_drops_a_run_stamped_ahead_by_the_same_rule() {
    let clean_t: Vec<f64> = (0..1200).map(|i| 100.0 + f64::from(i)).collect();
    let mut t = clean_t.clone();
    for v in &mut t[600..605] {
        *v += 10_000.0;
    }
    let mut without = clean_t.clone();
    without.drain(600..605);
    let log = ulog_log(&t);
    assert_eq!(log.time_s, without, "{:?}", log.info.problems);
    let a = ahead(&log);
    assert_eq!((a[0].line, a[0].count), (601, 5), "{:?}", log.info.problems);
    assert!(
        a[0].message.contains("the log goes on at sample 606"),
        "{}",
        a[0].message
    );
}

#[test]
fn a_logger_restarted_keeps_one_run_whole_not_two_spliced() {
    // 1000 rows, then the clock restarts at 100 s for 3000 rows: the first run goes whole
    // (it spliced before: the first run, then the second's rows past 1099 s).
    let first = rows(1000);
    let second: Vec<String> = rows(3000)
        .into_iter()
        .map(|r| {
            let (t, cells) = r.split_once(',').unwrap();
            let t: f64 = t.parse().unwrap();
            format!("{},{cells}", t, cells = cells.replace(",2", ",3"))
        })
        .collect();
    let mut all = first.clone();
    all.extend(second.iter().cloned());
    let log = read(&text(&all));
    let want = read(&text(&second));
    assert_eq!(log.time_s, want.time_s, "{:?}", log.info.problems);
    assert_eq!(log.temp_c, want.temp_c);
    let r = kinds(&log, ProblemKind::TimeBackwards);
    assert_eq!(r.len(), 1, "{:?}", log.info.problems);
    assert_eq!((r[0].line, r[0].count), (line_of_row(0), 1000));
    assert!(
        r[0].message.contains(&format!(
            "the clock goes back at line {} (100 s after 1099 s)",
            line_of_row(1000)
        )) && r[0]
            .message
            .contains("the rows before it, the shorter part"),
        "{}",
        r[0].message
    );
    // A block of rows sent twice loses its second copy, not the log before it.
    let mut twice = rows(3000);
    let block = twice[1495..1500].to_vec();
    for (k, b) in block.into_iter().enumerate() {
        twice.insert(1500 + k, b);
    }
    let log = read(&text(&twice));
    assert_eq!(log.time_s, read(&text(&rows(3000))).time_s);
}

#[test]
fn rows_stamped_before_the_clock_was_set_are_stray_not_decades_of_log() {
    // Three rows at 0, 0.5 and 0.7 s, then a log stamped in Unix time: the log is the Unix
    // part, not 55 years long.
    let body: Vec<String> = (0..3000)
        .map(|i| format!("{},{},{}", 1_733_397_000 + i, 0.001 * (i % 97) as f64, 20.0))
        .collect();
    let mut all = vec![
        "0,0.5,99".to_string(),
        "0.5,0.5,99".into(),
        "0.7,0.5,99".into(),
    ];
    all.extend(body.iter().cloned());
    let log = read(&text(&all));
    assert_eq!(
        log.time_s,
        read(&text(&body)).time_s,
        "{:?}",
        log.info.problems
    );
    let s = strays(&log);
    assert_eq!(
        (s[0].line, s[0].count),
        (line_of_row(0), 3),
        "{:?}",
        log.info.problems
    );
    assert!(
        s[0].message.contains("their times 0 s to 0.7 s stand")
            && s[0].message.contains("(lines 2 to 4)"),
        "{}",
        s[0].message
    );
}

#[test]
fn two_runs_that_begin_alike_are_runs_not_a_block_sent_twice() {
    // The sample calibration and validation runs begin with the same rows (one chamber
    // program, one simulator) and then differ: 20000 rows of each, one after the other, are
    // two runs of a clock that restarted, of which one is kept whole (the first, on a tie),
    // not the first run spliced with whatever of the second passes its last stamp.
    let lines = |name: &str| -> Vec<String> {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("sample_logs")
            .join(name);
        std::fs::read_to_string(path)
            .unwrap()
            .lines()
            .skip(2)
            .take(20_000)
            .map(str::to_string)
            .collect()
    };
    let (cal, val) = (lines("calibration.csv"), lines("validation.csv"));
    assert_eq!(cal[..3], val[..3], "the two runs begin alike");
    assert_ne!(cal, val, "and differ");
    let head = "# two runs\ntime_s,omega_dph,temp_c,temp_chamber_c\n";
    let text = |rows: &[String]| format!("{head}{}\n", rows.join("\n"));
    let mut both = cal.clone();
    both.extend(val.iter().cloned());
    let log = read(&text(&both));
    let first = read(&text(&cal));
    assert_eq!(log.time_s, first.time_s, "{:?}", log.info.problems);
    assert_eq!(log.omega_dph, first.omega_dph);
    let r = kinds(&log, ProblemKind::TimeBackwards);
    assert!(
        r.len() == 1 && r[0].message.contains("as many as the rows before it"),
        "{:?}",
        log.info.problems
    );
}
