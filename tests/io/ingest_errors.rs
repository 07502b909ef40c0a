//! Reading test-stand logs: every kind of broken file, and the problems reported for rows
//! dropped or kept, each located by file, line and column.

use driftlab::log::ProblemKind;
use driftlab::log::ingest::{IngestError, read_bytes};

use crate::common;
use common::ingest::*;

// ---------------------------------------------------------------------------------------------
// Problems and errors

#[test]
fn bad_cell_is_an_error_with_file_line_and_column() {
    let mut text = String::from("time,omega_dph,temp\n");
    for i in 0..820 {
        let omega = if i == 810 {
            "1.2.3".to_string()
        } else {
            format!("{}", i as f64 * 0.5)
        };
        text += &format!("{i},{omega},20\n");
    }
    let e = match read_bytes("run7.csv", text.as_bytes(), &opts()) {
        Err(e) => e,
        Ok(_) => panic!("expected an error"),
    };
    assert_eq!(e.file, "run7.csv");
    assert_eq!(e.line, 812);
    assert_eq!(e.column, 2);
    assert_eq!(
        e.to_string(),
        "run7.csv:812:2: cannot read \"1.2.3\" as a number (column \"omega_dph\")"
    );
}

#[test]
fn bad_cells_in_every_used_column() {
    let e = fail(b"time;omega;temp\n0;1;2\n1;2;2,5,5\n", &opts());
    assert_eq!((e.line, e.column), (3, 3), "{e}");
    let e = fail(b"time,omega,temp\n0,1,2\nabc,2,2\n", &opts());
    assert_eq!((e.line, e.column), (3, 1), "{e}");
    assert!(e.message.contains("\"abc\""), "{e}");
    // Decimal comma in a comma file without quotes: the cell is split, the row is ragged or
    // wrong, but never silently read.
    let e = fail(b"time;omega;temp\n0;1;20\n1;0x10;20\n", &opts());
    assert_eq!((e.line, e.column), (3, 2), "{e}");
}

#[test]
fn blank_and_nan_cells_drop_the_row() {
    let text =
        "time,omega,temp,extra\n0,1,20,1\n1,,20,1\n2,nan,20,1\n3,4,NaN,1\n4,5,20,\n5,6,20,1\n";
    let log = read(text);
    close(&log.time_s, &[0.0, 4.0, 5.0]);
    close(&log.omega_dph, &[1.0, 5.0, 6.0]);
    assert_eq!(log.info.rows_read, 6);
    let miss: Vec<_> = log
        .info
        .problems
        .iter()
        .filter(|p| p.kind == ProblemKind::MissingValue)
        .collect();
    assert_eq!(miss.len(), 2, "{:?}", log.info.problems);
    assert_eq!(
        (miss[0].line, miss[0].count, miss[0].column),
        (3, 2, Some(2))
    );
    assert_eq!(
        (miss[1].line, miss[1].count, miss[1].column),
        (5, 1, Some(3))
    );
    // Blanks in extras are NaN, no problem reported.
    assert!(log.extra[0].values[1].is_nan());
}

#[test]
fn time_backwards_and_repeated_rows_are_dropped() {
    let text = "time,omega,temp\n0,0,20\n1,1,20\n2,2,20\n2,99,20\n3,3,20\n1.5,99,20\n4,4,20\n3.5,99,20\n5,5,20\n";
    let log = read(text);
    close(&log.time_s, &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    close(&log.omega_dph, &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    assert_eq!(log.info.rows_read, 9);
    let p = |k| log.info.problems.iter().find(|p| p.kind == k).cloned();
    let rep = p(ProblemKind::TimeRepeated).expect("repeat reported");
    assert_eq!((rep.line, rep.count, rep.column), (5, 1, Some(1)));
    let back = p(ProblemKind::TimeBackwards).expect("backwards reported");
    assert_eq!((back.line, back.count), (7, 2));
    assert!(p(ProblemKind::Gap).is_none());
}

#[test]
fn gaps_are_reported_and_kept() {
    let mut text = String::from("# header follows\ntime,omega,temp\n");
    let mut times = Vec::new();
    let mut t = 0.0;
    for i in 0..50 {
        if i == 20 {
            t += 10.0;
        } else if i == 40 {
            t += 3.0;
        } else {
            t += 1.0;
        }
        times.push(t);
        text += &format!("{t},1,20\n");
    }
    let log = read(&text);
    close(&log.time_s, &times);
    let gap = log
        .info
        .problems
        .iter()
        .find(|p| p.kind == ProblemKind::Gap)
        .expect("gap reported");
    // Row i is on line i + 3.
    assert_eq!((gap.line, gap.count), (23, 2), "{gap:?}");
}

#[test]
fn ragged_rows() {
    // Too few fields for a used column: an error at that line.
    let e = fail(b"time,omega,temp\n0,1,20\n1,2\n2,3,20\n", &opts());
    assert_eq!(e.line, 3, "{e}");
    assert!(e.message.contains("temp"), "{e}");
    // Extra trailing fields are fine.
    let log = read("time,omega,temp\n0,1,20,9,9\n1,2,21,\n");
    close(&log.temp_c, &[20.0, 21.0]);
    // Too few fields for an extra column: NaN and a problem.
    let log = read("time,omega,temp,aux\n0,1,20,5\n1,2,21\n2,3,22,6\n");
    close(&log.time_s, &[0.0, 1.0, 2.0]);
    assert!(log.extra[0].values[1].is_nan());
    let r = log
        .info
        .problems
        .iter()
        .find(|p| p.kind == ProblemKind::RaggedRow)
        .expect("ragged reported");
    assert_eq!((r.line, r.count), (3, 1));
}

#[test]
fn unreadable_extra_cells_are_nan_and_reported() {
    let log = read("time,omega,temp,aux\n0,1,20,5\n1,2,21,6\n2,3,22,oops\n");
    assert!(log.extra[0].values[2].is_nan());
    assert!(
        log.info
            .problems
            .iter()
            .any(|p| p.line == 4 && p.column == Some(4) && p.kind == ProblemKind::BadExtraValue),
        "{:?}",
        log.info.problems
    );
}

#[test]
fn broken_files_give_clear_errors() {
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("empty", vec![], "empty"),
        ("bom only", b"\xEF\xBB\xBF".to_vec(), "empty"),
        ("comments only", b"# a\n\n# b\n".to_vec(), "no data"),
        ("header only", b"time,omega,temp\n".to_vec(), "no data rows"),
        ("one column", b"1\n2\n3\n".to_vec(), "one column"),
        ("one named column", b"omega\n1\n2\n".to_vec(), "one column"),
        ("binary", b"\x00\x01\x02\xff\xfe\x00abc".to_vec(), "binary"),
        (
            "invalid utf-8 header",
            b"time,\xff\xfe,temp\n0,1,2\n".to_vec(),
            "UTF-8",
        ),
        (
            "invalid utf-8 cell",
            b"time,omega,temp\n0,1,\xff\n".to_vec(),
            "cannot read",
        ),
        (
            "all rows blank",
            b"time,omega,temp\n0,,1\n1,,2\n".to_vec(),
            "none of the 2",
        ),
        (
            "lone CRs",
            b"time,omega,temp\r0,1,2\r1,2,3\r".to_vec(),
            "CR",
        ),
    ];
    for (what, bytes, needle) in cases {
        let e = match read_bytes("t.csv", &bytes, &opts()) {
            Err(e) => e,
            Ok(l) => panic!("{what}: expected an error, got {} rows", l.len()),
        };
        assert!(e.message.contains(needle), "{what}: {e}");
        assert_eq!(e.file, "t.csv");
    }
}

#[test]
fn any_number_of_comment_lines_before_the_header_is_skipped() {
    // Far more comment bytes than the head sniffed at once (a logger's settings dump).
    for (bom, end) in [("", "\n"), ("\u{feff}", "\r\n")] {
        let preamble = format!("# setting = value{end}\n").repeat(20_000);
        let rows = "time,omega,temp\n0,1,20\n1,2,21\n2,3,22\n";
        let log = read(&format!("{bom}{preamble}{rows}"));
        close(&log.omega_dph, &[1.0, 2.0, 3.0]);
        close(&log.temp_c, &[20.0, 21.0, 22.0]);
        // Lines keep their numbers in the file: 40,000 preamble lines, the header, three rows.
        let bad = format!("{bom}{preamble}{rows}3,x,23\n");
        let e = read_bytes("t.csv", bad.as_bytes(), &opts()).unwrap_err();
        assert_eq!((e.line, e.column), (40_005, 2), "{e}");
    }
    let e = read_bytes("t.csv", "# c\n".repeat(20_000).as_bytes(), &opts()).unwrap_err();
    assert!(
        e.message
            .contains("its 20000 lines are all blank or comment lines"),
        "{e}"
    );
}

#[test]
fn huge_lines_are_refused() {
    let mut big = b"time,omega,temp\n0,1,20\n".to_vec();
    big.extend(std::iter::repeat_n(b'7', 9 << 20));
    big.extend_from_slice(b"\n1,2,3\n");
    let e = fail(&big, &opts());
    assert_eq!(e.line, 3, "{e}");
    assert!(e.message.contains("longer"), "{e}");
    let e = fail(&vec![b'x'; 6 << 20], &opts());
    assert!(e.message.contains("longer"), "{e}");
}

#[test]
fn error_display_leaves_out_unknown_positions() {
    let e = IngestError {
        file: "a.csv".into(),
        line: 0,
        column: 0,
        message: "cancelled".into(),
    };
    assert_eq!(e.to_string(), "a.csv: cancelled");
    let e = IngestError { line: 4, ..e };
    assert_eq!(e.to_string(), "a.csv:4: cancelled");
}
