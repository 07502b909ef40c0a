//! The report of a calibration fitted on a campaign: its campaign section shows the runs, the
//! bias repeatability and the thermal hysteresis with the numbers `driftlab calibrate --json`
//! prints of the same calibration, formatted as the page formats them; a calibration of one
//! run has no such section; run names are escaped.
//!
//! The simulated campaign is `fog-three-runs`: the runs of `tiny-three-runs` are too short for
//! their plateaus to settle past the first, which gives no hysteresis and no temperature the
//! cooling run shares with another (so `--per-run-offset` refuses it).

use crate::common::run::{fails, ok};
use driftlab::export::report::html::fmt_dph;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The campaign's runs written as CSV once, in a folder kept for the test binary's life; the
/// heating run under a name holding markup.
fn runs() -> &'static (tempfile::TempDir, Vec<PathBuf>) {
    static RUNS: OnceLock<(tempfile::TempDir, Vec<PathBuf>)> = OnceLock::new();
    RUNS.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let c = driftlab::sim::campaign::campaign("fog-three-runs").unwrap();
        let sims = driftlab::sim::campaign::simulate_campaign(&c);
        let paths: Vec<PathBuf> = c
            .runs
            .iter()
            .zip(&sims)
            .map(|(r, sim)| {
                let name = match r.name.as_str() {
                    "heating" => "heating<script>&.csv".to_string(),
                    _ => c.file_name(r),
                };
                let path = dir.path().join(name);
                sim.write_csv(&path).unwrap();
                path
            })
            .collect();
        (dir, paths)
    })
}

fn text(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `driftlab calibrate LOGS --json EXTRA` into `out`: the JSON it printed.
fn calibrate(logs: &[PathBuf], out: &Path, extra: &[&str]) -> Value {
    let mut args = vec!["calibrate"];
    args.extend(logs.iter().map(|p| text(p)));
    args.extend(["--out", text(out), "--json"]);
    args.extend(extra);
    serde_json::from_str(&ok(&args)).unwrap()
}

/// `driftlab report CAL LOGS --out DIR EXTRA`: the page written.
fn report(cal: &Path, logs: &[PathBuf], dir: &Path, extra: &[&str]) -> String {
    let mut args = vec!["report", text(cal)];
    args.extend(logs.iter().map(|p| text(p)));
    args.extend(["--out", text(dir)]);
    args.extend(extra);
    ok(&args);
    std::fs::read_to_string(dir.join("report.html")).unwrap()
}

/// The campaign section of a page: from its heading to the figures.
fn section(page: &str) -> &str {
    let start = page
        .find("<h2>Campaign of ")
        .expect("the page has a campaign section");
    let end = start + page[start..].find("<h2>Figures</h2>").unwrap();
    &page[start..end]
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

/// The section's repeatability and hysteresis rows are the JSON's, in order.
fn assert_figures_match(campaign: &Value, sec: &str) {
    let rep = campaign["repeatability"].as_array().unwrap();
    let hys = campaign["hysteresis"].as_array().unwrap();
    assert!(!rep.is_empty() && !hys.is_empty(), "{campaign}");
    let mut at = 0;
    for g in rep {
        let row = format!(
            "<tr><td class=\"num\">{:.2}</td><td class=\"num\">{}</td><td>",
            f(&g["temp_c"]),
            fmt_dph(f(&g["spread_dph"]))
        );
        let found = sec[at..]
            .find(&row)
            .unwrap_or_else(|| panic!("{row}\n{sec}"));
        at += found + row.len();
        for v in g["values"].as_array().unwrap() {
            assert!(sec[at..].contains(&format!(": {}", fmt_dph(f(v)))), "{sec}");
        }
    }
    for h in hys {
        let row = format!(
            "<tr><td class=\"num\">{:.2}</td><td class=\"num\">{}</td>\
             <td class=\"num\">{} ({})</td><td class=\"num\">{} ({})</td></tr>",
            f(&h["temp_c"]),
            fmt_dph(f(&h["difference_dph"])),
            fmt_dph(f(&h["heating_dph"])),
            h["heating_plateaus"],
            fmt_dph(f(&h["cooling_dph"])),
            h["cooling_plateaus"],
        );
        assert!(sec.contains(&row), "{row}\n{sec}");
    }
}

#[test]
fn campaign_section_shows_calibrates_figures_with_turn_on_offsets() {
    let (_, logs) = runs();
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal.json");
    let json = calibrate(logs, &cal, &["--per-run-offset"]);
    let campaign = &json["campaign"];
    let page = report(&cal, logs, &dir.path().join("rep"), &[]);
    let sec = section(&page);
    assert!(sec.contains("<h2>Campaign of 3 runs</h2>"), "{sec}");
    assert_figures_match(campaign, sec);
    assert!(sec.contains("net of the turn-on offsets."), "{sec}");
    for (k, r) in campaign["runs"].as_array().unwrap().iter().enumerate() {
        let offset = fmt_dph(f(&r["turn_on_offset_dph"]));
        let start = format!("<tr><td class=\"num\">{}</td>", k + 1);
        let row = &sec[sec.find(&start).unwrap()..];
        let row = &row[..row.find("</tr>").unwrap()];
        assert!(
            row.contains(&format!("<td class=\"num\">{offset}</td>")),
            "{row}"
        );
        assert!(row.contains("(in-sample)"), "{row}");
        assert!(page.contains(&format!(" run {} of the campaign</h3>", k + 1)));
    }
    assert!(!sec.contains("not estimated") && !sec.contains("not given"));
    // The runs' plateau biases drawn beside K0.
    assert!(page.contains("<b>Campaign.</b>"), "no campaign figure");
    assert!(dir.path().join("rep/campaign.png").is_file());
}

#[test]
fn campaign_section_without_offsets_says_so_and_names_the_runs_not_given() {
    let (_, logs) = runs();
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal.json");
    let json = calibrate(logs, &cal, &[]);
    let page = report(&cal, &logs[1..], &dir.path().join("rep"), &[]);
    let sec = section(&page);
    assert_figures_match(&json["campaign"], sec);
    assert_eq!(sec.matches("not estimated").count(), 3, "{sec}");
    assert!(sec.contains("turn-on differences between runs included"));
    // The heating run was not given: its row says so, the two others are logs of the page.
    assert_eq!(sec.matches("not given to the report").count(), 1, "{sec}");
    assert_eq!(sec.matches("(in-sample)").count(), 2, "{sec}");
    // Its name, markup in a file name, is text on the page.
    assert!(sec.contains("heating&lt;script&gt;&amp;.csv"), "{sec}");
    assert!(!page.contains("<script"), "the page holds a script tag");
}

#[test]
fn campaign_section_groups_by_the_tolerance_asked_and_refuses_none() {
    let (_, logs) = runs();
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal.json");
    calibrate(logs, &cal, &[]);
    let out = dir.path().join("rep");
    // Within 0.01 °C the runs' 20 °C plateaus (20.000 and 20.025 °C, 19.975 °C) part.
    let tight = calibrate(
        logs,
        &dir.path().join("tight.json"),
        &["--temp-tolerance", "0.01"],
    );
    let page = report(&cal, logs, &out, &["--temp-tolerance", "0.01"]);
    let sec = section(&page);
    assert!(sec.contains("within 0.01 °C"), "{sec}");
    let rep = tight["campaign"]["repeatability"].as_array().unwrap();
    let hys = tight["campaign"]["hysteresis"].as_array().unwrap();
    // The runs' rows, then a row per temperature of either table.
    assert_eq!(
        sec.matches("<tr><td class=\"num\">").count(),
        3 + rep.len() + hys.len(),
        "{sec}"
    );
    if hys.is_empty() {
        assert!(sec.contains("No temperature is reached both heating and cooling."));
    }
    for bad in ["0", "-1", "NaN", "inf"] {
        let err = fails(&[
            "report",
            text(&cal),
            text(&logs[0]),
            "--out",
            text(&out),
            &format!("--temp-tolerance={bad}"),
        ]);
        assert!(err.contains("--temp-tolerance"), "{bad}: {err}");
    }
}

#[test]
fn a_calibration_of_one_run_has_no_campaign_section() {
    let (_, logs) = runs();
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal.json");
    let json = calibrate(&logs[2..], &cal, &[]);
    assert!(json.get("campaign").is_none(), "{json}");
    let page = report(&cal, logs, &dir.path().join("rep"), &[]);
    assert!(!page.contains("Campaign") && !page.contains("of the campaign"));
    assert!(!page.contains("campaign-runs"));
    assert!(!dir.path().join("rep/campaign.png").exists());
}
