//! Reading test-stand logs from files: large files read exactly across parallel blocks,
//! progress and cancel, the preview. The 10M-row read's speed is `benches/read_big_log.rs`.

use driftlab::log::ingest::{preview, preview_bytes, read_path, read_path_with_progress};
use driftlab::log::{ColumnRole, ProblemKind};
use std::io::Write;

use crate::common;
use common::ingest::*;

// ---------------------------------------------------------------------------------------------
// Files, blocks, progress, preview

/// A log large enough for several parallel blocks, with known values and some faults.
fn big_text(rows: usize) -> (String, Vec<f64>, Vec<f64>) {
    let mut s = String::from("# long run\ntime_s,omega_dph,temp_c,aux\n");
    let (mut t, mut w) = (Vec::new(), Vec::new());
    for i in 0..rows {
        let ti = i as f64 * 0.5;
        let wi = ((i * 7919) % 1000) as f64 * 0.001 - 0.5;
        s += &format!("{ti},{wi},{:.4},{}\n", 20.0 + i as f64 * 1e-4, i % 13);
        t.push(ti);
        w.push(wi);
    }
    (s, t, w)
}

#[test]
fn large_file_is_read_exactly_across_blocks() {
    let rows = 400_000;
    let (text, t, w) = big_text(rows);
    assert!(text.len() > 12 << 20, "several blocks");
    let log = read(&text);
    assert_eq!(log.len(), rows);
    assert_eq!(log.time_s, t);
    assert_eq!(log.omega_dph, w);
    assert_eq!(log.extra.len(), 1);
    assert_eq!(log.extra[0].values[rows - 1], ((rows - 1) % 13) as f64);
    assert!(log.info.problems.is_empty());

    // A fault deep in the file is reported at its exact line.
    let line_of_row = |r: usize| r + 3;
    let row = 333_333;
    let needle = format!("\n{},", t[row]);
    let pos = text.find(&needle).expect("row present") + 1;
    let mut bad = text.clone();
    bad.replace_range(pos..pos + needle.len() - 2, "1e");
    let e = fail(bad.as_bytes(), &opts());
    assert_eq!((e.line, e.column), (line_of_row(row), 1), "{e}");

    // Dropped rows deep in the file too; three in a row leave a gap.
    let mut holes = text.clone();
    let row = 250_001;
    for r in row..row + 3 {
        let needle = format!("\n{},{},", t[r], w[r]);
        let pos = holes.find(&needle).expect("row present");
        holes.replace_range(pos + 1..pos + needle.len() - 1, &format!("{},", t[r]));
    }
    let log = read(&holes);
    assert_eq!(log.len(), rows - 3);
    let p = &log.info.problems;
    assert_eq!(p.len(), 2, "{p:?}");
    assert_eq!(
        (p[0].kind, p[0].line, p[0].count),
        (ProblemKind::MissingValue, line_of_row(row), 3)
    );
    assert_eq!(
        (p[1].kind, p[1].line, p[1].count),
        (ProblemKind::Gap, line_of_row(row + 3), 1)
    );
}

#[test]
fn files_progress_and_cancel() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.csv");
    let (text, t, _) = big_text(300_000);
    std::fs::File::create(&path)
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    let log = read_path(&path, &opts()).unwrap();
    assert_eq!(log.time_s, t);
    assert_eq!(log.source, path.display().to_string());

    let seen = std::sync::Mutex::new(Vec::new());
    let log = read_path_with_progress(&path, &opts(), &|f| {
        seen.lock().unwrap().push(f);
        true
    })
    .unwrap();
    assert_eq!(log.len(), t.len());
    let seen = seen.into_inner().unwrap();
    assert!(seen.len() >= 2, "{seen:?}");
    assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
    assert_eq!(seen.last(), Some(&1.0));

    let calls = std::sync::atomic::AtomicUsize::new(0);
    let e = read_path_with_progress(&path, &opts(), &|_| {
        calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed) < 1
    })
    .unwrap_err();
    assert_eq!(e.message, "cancelled");

    let e = read_path(&dir.path().join("missing.csv"), &opts()).unwrap_err();
    assert!(e.message.contains("cannot open"), "{e}");
    let e = read_path(dir.path(), &opts()).unwrap_err();
    assert!(e.message.contains("directory"), "{e}");
}

#[test]
fn preview_shows_dialect_rows_and_mapping() {
    let text =
        "# stand 2\nTime [ms];Rate [deg/s];Temp [°C];note\n0;1,5;20;a\n10;2,5;21;b\n20;3,5;22;c\n";
    let p = preview_bytes("p.csv", text.as_bytes(), &opts(), 2).unwrap();
    assert_eq!(p.delimiter, ';');
    assert!(p.decimal_comma);
    assert!(p.has_header);
    assert_eq!(p.header_line, 2);
    assert_eq!(p.names, ["Time [ms]", "Rate [deg/s]", "Temp [°C]", "note"]);
    assert_eq!(p.rows, [["0", "1,5", "20", "a"], ["10", "2,5", "21", "b"]]);
    assert_eq!(p.row_lines, [3, 4]);
    let roles: Vec<_> = p
        .columns
        .iter()
        .map(|c| (c.role, c.unit.as_str()))
        .collect();
    assert_eq!(
        roles,
        [
            (ColumnRole::Time, "ms"),
            (ColumnRole::Rate, "deg/s"),
            (ColumnRole::Temperature, "°C"),
            (ColumnRole::Ignored, "")
        ]
    );
    assert!(p.mapping_error.is_none());

    // A mapping that cannot be made still previews.
    let p = preview_bytes("p.csv", b"a,b\n1,2\n", &opts(), 10).unwrap();
    assert!(p.mapping_error.is_some());
    assert_eq!(p.rows.len(), 1);

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.csv");
    std::fs::write(&path, text).unwrap();
    let q = preview(&path, &opts(), 2).unwrap();
    assert_eq!(q.rows.len(), 2);
}
