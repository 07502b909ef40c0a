//! Names from files reach every output quoted by what writes it: the corrected CSV of `apply`
//! and the lookup tables of `export` read back by the `csv` crate's reader with every name as
//! it was (formula-like ones neutralised), the C header compiled with axes named like its own
//! identifiers, and nothing a terminal would obey printed by the command line.

use crate::common;

use common::run::{driftlab, fails, ok, sample};
use std::path::Path;

/// A unit calibration of the three-axis sample with its axes renamed `names` (axis k reads
/// the sample's axis k % 3), written to `dir/unit.json`.
fn unit_named(dir: &Path, names: &[&str]) -> String {
    let out = dir.join("unit.json").display().to_string();
    ok(&["calibrate", &sample("imu3-calibration.csv"), "--out", &out]);
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let axes = json["axes"].as_array().unwrap().clone();
    json["axes"] = names
        .iter()
        .enumerate()
        .map(|(k, n)| {
            let mut a = axes[k % 3].clone();
            a["name"] = serde_json::Value::from(*n);
            a
        })
        .collect();
    std::fs::write(&out, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    out
}

/// Names a spreadsheet or a CSV reader would trip on.
const CRAFTED: [&str; 4] = [
    "=HYPERLINK(\"http://x\",\"y\")",
    "a,b \"c\"",
    "two lines",
    "-gx",
];

/// A name as a spreadsheet is to see it: a formula-like one after a single quote.
fn shown(name: &str) -> String {
    if name.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        format!("'{name}")
    } else {
        name.to_string()
    }
}

#[test]
fn apply_writes_crafted_axis_names_quoted_and_formulas_neutralised() {
    let dir = tempfile::tempdir().unwrap();
    let unit = unit_named(dir.path(), &CRAFTED);
    let out = dir.path().join("cor.csv");
    ok(&[
        "apply",
        &unit,
        &sample("imu3-validation.csv"),
        "--out",
        &out.display().to_string(),
    ]);
    let mut reader = csv::ReaderBuilder::new().from_path(&out).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    let mut expected = vec!["time_s".to_string()];
    for n in CRAFTED {
        for k in ["raw", "pred", "cor"] {
            expected.push(shown(&format!("{n}_{k}_dph")));
        }
    }
    expected.push("temp_c".into());
    assert_eq!(header, expected);
    // Every row: numbers, negative ones as they are (no quote before them).
    let mut rows = 0;
    let mut negative = 0;
    for r in reader.records() {
        let r = r.unwrap();
        assert_eq!(r.len(), expected.len());
        for cell in &r {
            let v: f64 = cell.parse().unwrap_or_else(|_| panic!("{cell:?}"));
            negative += usize::from(v < 0.0 && cell.starts_with('-'));
        }
        rows += 1;
    }
    let log_rows = std::fs::read_to_string(sample("imu3-validation.csv"))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .count()
        - 1;
    assert_eq!(rows, log_rows);
    assert!(negative > 0);
}

#[test]
fn the_lookup_tables_of_crafted_axes_read_back_with_their_names() {
    let dir = tempfile::tempdir().unwrap();
    let names = ["#gx", "a,b \"c\"", "+1", "two lines"];
    let unit = unit_named(dir.path(), &names);
    let text = ok(&["export", &unit, "--format", "csv-table", "--points", "5"]);
    // The `#` lines are comments; a name holding `#` is quoted so no row starts as one.
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let header = reader.headers().unwrap().clone();
    assert_eq!(&header[0], "axis");
    assert_eq!(header.len(), 11);
    let mut per_axis = std::collections::BTreeMap::<String, usize>::new();
    for r in reader.records() {
        let r = r.unwrap();
        assert_eq!(r.len(), 11);
        for cell in r.iter().skip(1) {
            cell.parse::<f64>().unwrap();
        }
        *per_axis.entry(r[0].to_string()).or_default() += 1;
    }
    let expected: std::collections::BTreeMap<String, usize> =
        names.iter().map(|n| (shown(n), 5)).collect();
    assert_eq!(per_axis, expected);
}

/// What a crafted name would make a terminal do: clear the screen, set the window's title.
const TRAP: &str = "\u{1b}[2J\u{1b}]0;pwned\u{7}";

/// Asserts that `bytes` hold nothing a terminal would obey: no ESC, BEL, other C0 control but
/// line breaks and tabs, DEL, C1 control (CSI U+009B among them) or bidirectional override.
fn printable(what: &str, bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    let bad: Vec<char> = text
        .chars()
        .filter(|&c| {
            (c.is_control() && c != '\n' && c != '\t') || ('\u{202a}'..='\u{202e}').contains(&c)
        })
        .collect();
    assert!(bad.is_empty(), "{what}: {bad:?} in {text:?}");
}

#[test]
fn nothing_a_terminal_would_obey_reaches_it_from_a_name() {
    let dir = tempfile::tempdir().unwrap();
    // A log whose file name and rate column carry the escape sequences.
    let log = dir.path().join(format!("log{TRAP}.csv"));
    // The column also with a C1 control (CSI) and a right-to-left override, which JSON
    // writes as they are.
    let column = format!("omega{TRAP}\u{9b}\u{202e}_dph");
    let mut text = format!("time_s,{column},temp_c\n");
    for i in 0..600 {
        let t = i as f64;
        text.push_str(&format!("{t},{},{}\n", (t / 50.0).sin(), 20.0 + t * 0.01));
    }
    std::fs::write(&log, text).unwrap();
    let log = log.display().to_string();
    let inspect = driftlab(&["inspect", &log]);
    assert!(inspect.status.success());
    printable("inspect", &inspect.stdout);
    printable("inspect", &inspect.stderr);
    let shown = String::from_utf8_lossy(&inspect.stdout);
    assert!(
        shown.contains("omega\\u001b[2J\\u001b]0;pwned\\u0007\\u009b\\u202e_dph"),
        "{shown}"
    );
    // As JSON: valid, every such character escaped, the name read back as it is.
    let json = driftlab(&["inspect", &log, "--json"]);
    assert!(json.status.success());
    printable("inspect --json", &json.stdout);
    let json: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(json["info"]["columns"][1]["name"], column.as_str());
    // An error naming the file.
    let missing = dir.path().join(format!("missing{TRAP}\u{9b}2J.csv"));
    let e = driftlab(&["inspect", &missing.display().to_string()]);
    assert!(!e.status.success());
    printable("an error", &e.stderr);
    assert!(String::from_utf8_lossy(&e.stderr).contains("\\u001b"));
    // Axis names and a gyro id of a calibration, through the commands that print them.
    let unit = unit_named(dir.path(), &[TRAP, "gy\u{202e}x", "gz\r\u{9b}2J"]);
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&unit).unwrap()).unwrap();
    json["gyro_id"] = serde_json::Value::from(format!("id{TRAP}"));
    std::fs::write(&unit, json.to_string()).unwrap();
    let val = sample("imu3-validation.csv");
    let out = dir.path().join("cor.csv").display().to_string();
    for args in [
        vec!["evaluate", &unit, &val],
        vec!["apply", &unit, &val, "--out", &out],
        vec!["export", &unit, "--format", "px4-params"],
        vec!["export", &unit, "--format", "nonsense"],
    ] {
        let run = driftlab(&args);
        printable(&format!("{args:?}"), &run.stdout);
        printable(&format!("{args:?}"), &run.stderr);
    }
}

/// Characters that print as nothing, Unicode format characters (category Cf) and a tag
/// character: a zero-width space, a byte order mark, a soft hyphen, a word joiner, and the tag
/// of the letter A (U+E0041).
const INVISIBLE: [char; 5] = ['\u{200b}', '\u{feff}', '\u{ad}', '\u{2060}', '\u{e0041}'];

#[test]
fn a_gyro_id_with_an_invisible_character_is_refused() {
    // `FOG-0001` and `FOG-0001` followed by tag characters spelling a hidden text print alike
    // on a terminal, and are two serial numbers to every output that copies them.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cal.json").display().to_string();
    let log = sample("calibration.csv");
    let hidden: String = "flash unit 7"
        .chars()
        .map(|c| char::from_u32(0xE0000 + c as u32).unwrap())
        .collect();
    let ids = INVISIBLE
        .iter()
        .map(|&c| (format!("FOG-0001{c}"), c))
        .chain([(format!("FOG-0001{hidden}"), '\u{e0066}')]);
    for (id, first) in ids {
        let err = fails(&["calibrate", &log, "--gyro-id", &id, "--out", &out]);
        let want = format!(
            "gyro_id (--gyro-id): holds the control character U+{:04X}",
            first as u32
        );
        assert!(err.contains(&want), "{id:?}: wanted {want}, got {err}");
        assert!(!Path::new(&out).exists(), "{id:?}");
    }
}

/// Characters outside Unicode's format category that still print as nothing or as a blank,
/// or that are no character every font draws alike: the Hangul fillers (letters, Lo), the
/// braille blank (a symbol, So), the combining grapheme joiner, the emoji variation selector
/// and a Khmer inherent vowel (marks, Mn, all default-ignorable), the no-break, en quad and
/// ideographic spaces (Zs), the noncharacter U+FFFE, U+0378 (assigned to no character in
/// Unicode 16.0) and the first private-use character.
const BLANK_OR_NO_CHARACTER: [char; 14] = [
    '\u{3164}', '\u{115f}', '\u{1160}', '\u{ffa0}', '\u{2800}', '\u{34f}', '\u{fe0f}', '\u{17b4}',
    '\u{a0}', '\u{2000}', '\u{3000}', '\u{fffe}', '\u{378}', '\u{e000}',
];

#[test]
fn a_gyro_id_that_prints_as_another_is_refused() {
    // `FOG-0001` followed by a Hangul filler printed as `FOG-0001` and went into every output
    // as another serial number; so did one with a space before or after it. Each is refused,
    // naming the character; a serial number of printable text in any script, a space inside
    // it or a visible combining accent, is taken.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cal.json").display().to_string();
    let log = sample("calibration.csv");
    for c in BLANK_OR_NO_CHARACTER {
        let id = format!("FOG-0001{c}");
        let err = fails(&["calibrate", &log, "--gyro-id", &id, "--out", &out]);
        let want = format!("gyro_id (--gyro-id): holds U+{:04X}, ", c as u32);
        assert!(err.contains(&want), "{id:?}: wanted {want}, got {err}");
        assert!(!Path::new(&out).exists(), "{id:?}");
    }
    for id in [" FOG-0001", "FOG-0001 "] {
        let err = fails(&["calibrate", &log, "--gyro-id", id, "--out", &out]);
        assert!(
            err.contains("gyro_id (--gyro-id): starts or ends with a space"),
            "{id:?}: {err}"
        );
        assert!(!Path::new(&out).exists(), "{id:?}");
    }
    for id in ["FOG 0001", "ГИРО-7", "陀螺仪-7", "FOG-0001e\u{301}"] {
        ok(&["calibrate", &log, "--gyro-id", id, "--out", &out]);
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        assert_eq!(json["calibration"]["gyro_id"], id, "{id:?}");
        std::fs::remove_file(&out).unwrap();
    }
    // A calibration file whose serial number was edited to hold one is refused on load,
    // naming the field and the character.
    ok(&["calibrate", &log, "--gyro-id", "FOG-0001", "--out", &out]);
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    json["calibration"]["gyro_id"] = serde_json::Value::from("FOG-0001\u{3164}");
    std::fs::write(&out, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    let header = dir.path().join("cal.h").display().to_string();
    let err = fails(&["export", &out, "--format", "c-header", "--out", &header]);
    assert!(
        err.contains("gyro_id") && err.contains("holds U+3164, "),
        "{err}"
    );
    assert!(!Path::new(&header).exists());
}

#[test]
fn an_invisible_character_in_a_column_name_is_shown_escaped() {
    // A column name that holds a zero-width space and a tag character is shown with both as
    // their escapes (the tag character, above U+FFFF, as its UTF-16 surrogate pair, as JSON
    // writes it), so that it does not print as another name; `--json` reads back the name.
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("log.csv");
    let column = "omega\u{200b}\u{e0041}_dph";
    let mut text = format!("time_s,{column},temp_c\n");
    for i in 0..600 {
        let t = i as f64;
        text.push_str(&format!("{t},{},{}\n", (t / 50.0).sin(), 20.0 + t * 0.01));
    }
    std::fs::write(&log, text).unwrap();
    let log = log.display().to_string();
    let shown = ok(&["inspect", &log]);
    assert!(shown.contains("omega\\u200b\\udb40\\udc41_dph"), "{shown}");
    assert!(!shown.contains('\u{200b}') && !shown.contains('\u{e0041}'));
    let json = ok(&["inspect", &log, "--json"]);
    let json: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(json["info"]["columns"][1]["name"], column);
}

#[test]
fn an_axis_name_with_a_line_break_is_refused_on_load() {
    // A line break (or any control character) in a name would start a line of its own on the
    // terminal and in every text output: a unit file holding one is refused, naming the axis.
    let dir = tempfile::tempdir().unwrap();
    let unit = unit_named(dir.path(), &["gx", "two\nlines", "gz"]);
    let err = fails(&[
        "apply",
        &unit,
        &sample("imu3-validation.csv"),
        "--out",
        &dir.path().join("cor.csv").display().to_string(),
    ]);
    assert!(
        err.contains("axes.name: axis 1's name holds the control character U+000A"),
        "{err}"
    );
    assert!(!dir.path().join("cor.csv").exists());
}
