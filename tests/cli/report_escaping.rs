//! Names that are markup stay text in every report page: a gyro id, an axis, a model and the
//! logs' file names set to `<script>alert(1)</script>` and `"'&<>` appear in the page and in
//! the figures only in their escaped form (the HTML entities written out here, not computed by
//! the code under test), and the page keeps its structure.

use crate::common::run::ok;
use std::path::{Path, PathBuf};

const SCRIPT: &str = "<script>alert(1)</script>";
const SCRIPT_ESCAPED: &str = "&lt;script&gt;alert(1)&lt;/script&gt;";
const QUOTES: &str = "\"'&<>";
const QUOTES_ESCAPED: &str = "&quot;'&amp;&lt;&gt;";
/// A file name cannot hold `/`: the log named like a script tag stops at its opening tag.
const SCRIPT_LOG: &str = "<script>alert(1).csv";
const SCRIPT_LOG_ESCAPED: &str = "&lt;script&gt;alert(1).csv";

fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name)
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// Copies of the sample logs `own` and `other` named `"'&<>.csv` and `<script>alert(1).csv`.
fn crafted_logs(dir: &Path, own: &str, other: &str) -> (String, String) {
    let a = dir.join(format!("{QUOTES}.csv"));
    let b = dir.join(SCRIPT_LOG);
    std::fs::copy(sample(own), &a).unwrap();
    std::fs::copy(sample(other), &b).unwrap();
    (s(&a), s(&b))
}

/// The JSON file at `path` edited by `edit`.
fn edit(path: &str, edit: impl FnOnce(&mut serde_json::Value)) {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    edit(&mut v);
    std::fs::write(path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
}

/// Every file of the report folder `dir` with the extension `ext`, below it too.
fn files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(files(&p, ext));
        } else if p.extension().is_some_and(|x| x == ext) {
            out.push(p);
        }
    }
    out
}

/// The checks every page and figure must pass: no crafted name raw, the tags of the page
/// balanced. Returns the page.
fn page_of(dir: &Path) -> String {
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    assert!(!html.contains("<script"), "a raw script tag in the page");
    assert!(!html.contains(QUOTES), "raw \"'&<> in the page");
    assert!(!html.contains(SCRIPT_LOG), "a raw log name in the page");
    for tag in [
        "figure", "table", "tr", "p", "pre", "svg", "h2", "b", "code",
    ] {
        let opens =
            html.matches(&format!("<{tag}>")).count() + html.matches(&format!("<{tag} ")).count();
        let closes = html.matches(&format!("</{tag}>")).count();
        assert_eq!(opens, closes, "<{tag}> unbalanced in the page");
    }
    let svgs = files(dir, "svg");
    assert!(!svgs.is_empty());
    for svg in svgs {
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(!text.contains("<script"), "{}", svg.display());
        assert!(!text.contains(QUOTES), "{}", svg.display());
    }
    html
}

#[test]
fn a_calibration_named_like_markup_gives_a_page_of_text() {
    let dir = tempfile::tempdir().unwrap();
    let (own, other) = crafted_logs(dir.path(), "calibration.csv", "validation.csv");
    let cal = s(&dir.path().join("cal.json"));
    ok(&["calibrate", &own, "--gyro-id", SCRIPT, "--out", &cal]);
    let out = dir.path().join("rep");
    ok(&["report", &cal, &own, &other, "--out", &s(&out)]);
    let html = page_of(&out);
    assert!(html.contains(&format!(
        "<title>Thermal drift calibration report: {SCRIPT_ESCAPED}</title>"
    )));
    assert!(html.contains(&format!("<b class=\"gyro-id\">{SCRIPT_ESCAPED}</b>")));
    assert!(html.contains(&format!(
        "<tr><th>gyro id</th><td>{SCRIPT_ESCAPED}</td></tr>"
    )));
    assert!(html.contains(&format!(
        "<table class=\"merit\" data-log=\"{QUOTES_ESCAPED}.csv\" data-set=\"in-sample\">"
    )));
    assert!(html.contains(&format!(
        "<table class=\"merit\" data-log=\"{SCRIPT_LOG_ESCAPED}\" data-set=\"held-out\">"
    )));
    // The recipe as stored, with its gyro id, is JSON inside <pre>: quoted and escaped.
    assert!(html.contains(&format!(
        "&quot;gyro_id&quot;: &quot;{SCRIPT_ESCAPED}&quot;"
    )));
    // The figures' titles name the logs; the SVG escapes them as text too.
    let drift = std::fs::read_to_string(out.join("drift-_script_alert_1_.svg")).unwrap();
    assert!(
        drift.contains(SCRIPT_LOG_ESCAPED),
        "the drift figure's title"
    );
}

#[test]
fn a_regression_model_named_like_markup_gives_a_page_of_text() {
    let dir = tempfile::tempdir().unwrap();
    let (own, other) = crafted_logs(dir.path(), "laser-gyro.csv", "laser-gyro-2.csv");
    let cal = s(&dir.path().join("cal.json"));
    ok(&["calibrate", &own, "--model", "sukhanov", "--out", &cal]);
    edit(&cal, |v| {
        v["calibration"]["gyro_id"] = QUOTES.into();
        v["calibration"]["model"]["spec"]["name"] = SCRIPT.into();
    });
    let out = dir.path().join("rep");
    ok(&["report", &cal, &own, &other, "--out", &s(&out)]);
    let html = page_of(&out);
    assert!(html.contains(&format!("<b class=\"gyro-id\">{QUOTES_ESCAPED}</b>")));
    assert!(html.contains(&format!("<b class=\"model-name\">{SCRIPT_ESCAPED}</b>")));
    assert!(html.contains(&format!("<tr><th>model</th><td>{SCRIPT_ESCAPED}</td></tr>")));
    assert!(html.contains(&format!(
        "<tr><th>calibration log</th><td>{QUOTES_ESCAPED}.csv</td></tr>"
    )));
}

#[test]
fn a_unit_with_axes_named_like_markup_gives_a_page_of_text() {
    let dir = tempfile::tempdir().unwrap();
    let (own, other) = crafted_logs(dir.path(), "imu3-calibration.csv", "imu3-validation.csv");
    let cal = s(&dir.path().join("unit.json"));
    ok(&["calibrate", &own, "--out", &cal]);
    edit(&cal, |v| {
        v["gyro_id"] = SCRIPT.into();
        v["axes"][0]["name"] = SCRIPT.into();
        v["axes"][1]["name"] = QUOTES.into();
    });
    let out = dir.path().join("rep");
    ok(&["report", &cal, &own, &other, "--out", &s(&out)]);
    let html = page_of(&out);
    assert!(html.contains(&format!("<b class=\"gyro-id\">{SCRIPT_ESCAPED}</b>")));
    for (axis, escaped) in [(SCRIPT, SCRIPT_ESCAPED), (QUOTES, QUOTES_ESCAPED)] {
        assert!(
            html.contains(&format!(
                "<h2 class=\"axis\" id=\"axis-{escaped}\">Axis {escaped}</h2>"
            )),
            "the heading of axis {axis}"
        );
        // One summary row per log.
        assert_eq!(
            html.matches(&format!("<tr data-axis=\"{escaped}\"><td>{escaped}</td>"))
                .count(),
            2,
            "the summary rows of axis {axis}"
        );
    }
    assert!(html.contains(&format!(
        "<tr><th>axes</th><td>{SCRIPT_ESCAPED}, {QUOTES_ESCAPED}, gz</td></tr>"
    )));
    // The axes' folders are file-name-safe.
    assert!(out.join("_script_alert_1___script_").is_dir());
    assert!(out.join("_____").is_dir());
}
