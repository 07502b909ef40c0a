//! A lot in the workbench (File › Open lot, `driftlab gui --lot OUT`): the simulated lot of the
//! lot's tests, calibrated by the engine, shown as its table; sorted by a column, the units
//! stand in the order of that figure's values in the lot's outcome (either way, the unit
//! without it last); a unit clicked opens its log(s) and its calibration on the Calibration
//! page; `lot.csv` reads as the same table as `lot.json`; a malformed table leaves the lot
//! shown before as it was and names its file, line and column.

use crate::common::gui::*;
use crate::common::lot::{CAMPAIGN, CORRUPT, NOISY, ORDINARY, spec_json, write_lot};
use driftlab::gui::settings::Settings;
use driftlab::gui::{Action, Page, ScriptedDialogs, Workbench};
use driftlab::lot::open::{self, SortBy};
use driftlab::lot::{Lot, LotOutcome, Spec, Status, figures};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::{Path, PathBuf};

/// The simulated lot calibrated into `dir/out`, and its outcome.
fn made_lot(dir: &Path) -> (PathBuf, LotOutcome) {
    let units = dir.join("units");
    std::fs::create_dir(&units).unwrap();
    write_lot(&units);
    let out = dir.join("out");
    let lot = Lot {
        inputs: vec![units],
        spec: Spec::from_json(&spec_json()).unwrap(),
        out: out.clone(),
        recipe: None,
        jobs: 2,
        shard: None,
        report: false,
    };
    let outcome = driftlab::lot::run(&lot, &mut |_| {}).unwrap();
    (out, outcome)
}

fn empty_workbench() -> Harness<'static, Workbench> {
    harness(Workbench::new(
        Settings::default(),
        None,
        Box::new(ScriptedDialogs::new()),
    ))
}

fn act(h: &mut Harness<'_, Workbench>, a: Action) {
    let ctx = h.ctx.clone();
    h.state_mut().act(&ctx, a);
    h.run_ok();
}

/// The units in the order the table shows them, top to bottom.
fn shown_order(h: &Harness<'_, Workbench>, outcome: &LotOutcome) -> Vec<String> {
    let mut at: Vec<(f32, String)> = outcome
        .units
        .iter()
        .map(|u| (h.get_by_label(&u.unit).rect().min.y, u.unit.clone()))
        .collect();
    at.sort_by(|a, b| a.0.total_cmp(&b.0));
    at.into_iter().map(|(_, u)| u).collect()
}

/// The units ordered by their ARW in the outcome, ascending or descending; the units without
/// it last.
fn by_arw(outcome: &LotOutcome, descending: bool) -> Vec<String> {
    let arw = |u: &driftlab::lot::UnitOutcome| {
        u.axes
            .first()
            .and_then(|a| a.get(figures::ARW))
            .and_then(|f| f.value)
    };
    let mut with: Vec<(f64, String)> = outcome
        .units
        .iter()
        .filter_map(|u| Some((arw(u)?, u.unit.clone())))
        .collect();
    with.sort_by(|a, b| a.0.total_cmp(&b.0));
    if descending {
        with.reverse();
    }
    let mut order: Vec<String> = with.into_iter().map(|(_, u)| u).collect();
    order.extend(
        outcome
            .units
            .iter()
            .filter(|u| arw(u).is_none())
            .map(|u| u.unit.clone()),
    );
    order
}

fn same_file(a: &Path, b: &Path) -> bool {
    std::fs::canonicalize(a).unwrap() == std::fs::canonicalize(b).unwrap()
}

#[test]
fn a_lot_is_shown_sorted_by_a_column_and_a_unit_opens_on_the_calibration_page() {
    let dir = tempfile::tempdir().unwrap();
    let (out, outcome) = made_lot(dir.path());
    let mut h = empty_workbench();
    act(&mut h, Action::OpenLotPath(out.clone()));
    assert_eq!(h.state().page(), Page::Lot);
    let lot = h.state().state.lot.clone().expect("the lot is open");
    assert!(same_file(&lot.file, &out.join("lot.json")));
    assert_eq!(lot.rows.len(), outcome.units.len());
    let names: Vec<_> = outcome.units.iter().map(|u| u.unit.clone()).collect();
    assert_eq!(shown_order(&h, &outcome), names, "the lot's order first");

    // A click on a heading sorts by it; a second, the other way.
    h.get_by_label(figures::ARW).click();
    h.run_ok();
    let arw_column = lot
        .columns
        .iter()
        .position(|c| c.figure == figures::ARW)
        .unwrap();
    assert_eq!(
        h.state_mut().lot_view().sort,
        Some((SortBy::Figure(arw_column), false))
    );
    let ascending = shown_order(&h, &outcome);
    assert_eq!(ascending, by_arw(&outcome, false));
    assert_eq!(ascending[ascending.len() - 2], NOISY);
    assert_eq!(ascending.last().unwrap(), CORRUPT);
    h.get_by_label(&format!("{} ^", figures::ARW)).click();
    h.run_ok();
    let descending = shown_order(&h, &outcome);
    assert_eq!(descending, by_arw(&outcome, true));
    assert_eq!(descending[0], NOISY);

    // A unit clicked: its log and its calibration, on the Calibration page.
    h.get_by_label(ORDINARY[0]).click();
    h.run_ok();
    settle(&mut h);
    assert_eq!(h.state().page(), Page::Calibration);
    let unit = outcome
        .units
        .iter()
        .find(|u| u.unit == ORDINARY[0])
        .unwrap();
    let s = &h.state().state;
    let log = s.shown.log.as_ref().expect("the unit's log is open");
    assert!(same_file(&log.path, Path::new(&unit.runs_at[0])));
    assert!(s.shown.fit.is_some());
    let opened = h.state().opened().expect("its calibration is opened");
    assert!(same_file(
        &opened.path,
        &out.join(unit.calibration.as_ref().unwrap())
    ));

    // A unit of two runs opens as a campaign of both.
    act(&mut h, Action::ShowPage(Page::Lot));
    h.get_by_label(CAMPAIGN).click();
    h.run_ok();
    settle(&mut h);
    let log = h.state().state.shown.log.as_ref().unwrap();
    assert_eq!(log.log.runs().len(), 2);
    let opened = h.state().opened().unwrap();
    assert!(
        opened
            .path
            .ends_with(Path::new(CAMPAIGN).join("calibration.json"))
    );
}

#[test]
fn lot_csv_reads_as_the_same_table_as_lot_json() {
    let dir = tempfile::tempdir().unwrap();
    let (out, outcome) = made_lot(dir.path());
    let json = open::open(&out.join("lot.json")).unwrap();
    let csv = open::open(&out.join("lot.csv")).unwrap();
    assert_eq!(csv.columns, json.columns);
    assert_eq!(csv.rows.len(), outcome.units.len());
    for (c, j) in csv.rows.iter().zip(&json.rows) {
        assert_eq!(c.unit, j.unit);
        assert_eq!(c.status, j.status);
        assert_eq!(c.reasons, j.reasons);
        assert_eq!(c.calibration, j.calibration);
        // Every figure to the bit: the CSV writes the shortest text that reads back the same.
        assert_eq!(c.values, j.values, "{}", c.unit);
        assert_eq!(c.unavailable, j.unavailable, "{}", c.unit);
        // The CSV writes an outlier's distance to a tenth.
        for (a, b) in c.outliers.iter().zip(&j.outliers) {
            match (a, b) {
                (Some(a), Some(b)) => assert!((a - b).abs() <= 0.05 + 1e-9, "{a} {b}"),
                (None, None) => {}
                _ => panic!("{}: outlier marks {a:?} against {b:?}", c.unit),
            }
        }
        // The runs come from each calibrated unit's record; an error has none.
        if c.status == Status::Error {
            assert!(c.runs.is_empty());
        } else {
            assert_eq!((&c.runs, &c.runs_at), (&j.runs, &j.runs_at));
        }
    }
    assert!(json.rows.iter().any(|r| r.is_outlier()));
    // The folder opens its lot.json.
    assert_eq!(open::open(&out).unwrap(), json);
}

#[test]
fn a_malformed_lot_leaves_the_lot_shown_and_names_its_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let (out, _) = made_lot(dir.path());
    let mut h = empty_workbench();
    act(&mut h, Action::OpenLotPath(out.clone()));
    let before = h.state().state.lot.clone().unwrap();

    // A unit's name that is a number, on line 4.
    let bad_json = dir.path().join("bad").join("lot.json");
    std::fs::create_dir_all(bad_json.parent().unwrap()).unwrap();
    let text =
        "{\n  \"spec\": {},\n  \"units\": [\n    { \"unit\": 5 }\n  ],\n  \"outliers\": []\n}\n";
    std::fs::write(&bad_json, text).unwrap();
    let column = text.lines().nth(3).unwrap().find('5').unwrap() + 1;
    // A figure that is no number, in the second line of lot.csv.
    let good_csv = std::fs::read_to_string(out.join("lot.csv")).unwrap();
    let mut lines: Vec<String> = good_csv.lines().map(String::from).collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let field = header
        .iter()
        .position(|h| *h == figures::ARW)
        .expect("an ARW column");
    let mut cells: Vec<String> = lines[1].split(',').map(String::from).collect();
    assert_eq!(
        cells.len(),
        header.len(),
        "a first row without quoted commas"
    );
    cells[field] = "zz".into();
    lines[1] = cells.join(",");
    let bad_csv = dir.path().join("bad").join("lot.csv");
    std::fs::write(&bad_csv, lines.join("\n") + "\n").unwrap();

    for (file, place) in [
        (&bad_json, format!("lot.json:4:{column}")),
        (&bad_csv, format!("lot.csv:2:{}", field + 1)),
    ] {
        act(&mut h, Action::OpenLotPath(file.clone()));
        let shown = h.get_by_label_contains("Could not open the lot. Nothing was changed.");
        let text = format!("{shown:?}");
        assert!(text.contains(&place), "{place}: {text}");
        assert_eq!(h.state().state.lot.as_ref(), Some(&before));
        assert_eq!(h.state().page(), Page::Lot);
        h.get_by_label("OK").click();
        h.run_ok();
    }
}

#[test]
fn a_unit_opened_over_unsaved_work_asks_first_and_cancel_keeps_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let (out, outcome) = made_lot(dir.path());
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    assert!(h.state().state.dirty(), "the plateaus are unsaved work");
    let choices = h.state().state.shown.choices.clone();
    act(&mut h, Action::OpenLotPath(out));
    h.get_by_label(ORDINARY[1]).click();
    h.run_ok();
    h.get_by_label("Unsaved work");
    h.get_by_label("Cancel").click();
    h.run_ok();
    settle(&mut h);
    let s = &h.state().state;
    assert!(same_file(
        &s.shown.log.as_ref().unwrap().path,
        &sample("calibration.csv")
    ));
    assert_eq!(s.shown.choices, choices);
    assert!(h.state().opened().is_none());

    // Discarded: the unit opens.
    h.get_by_label(ORDINARY[1]).click();
    h.run_ok();
    h.get_by_label("Discard").click();
    h.run_ok();
    settle(&mut h);
    let unit = outcome
        .units
        .iter()
        .find(|u| u.unit == ORDINARY[1])
        .unwrap();
    let log = h.state().state.shown.log.as_ref().unwrap();
    assert!(same_file(&log.path, Path::new(&unit.runs_at[0])));
    assert!(h.state().opened().is_some());
}

#[test]
fn a_lot_of_a_three_axis_unit_reads_its_axes_columns_from_lot_csv_as_from_lot_json() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let lot = Lot {
        inputs: vec![sample("imu3-calibration.csv")],
        spec: Spec::from_json(r#"{ "reference_temps_c": [0.5, 20] }"#).unwrap(),
        out: out.clone(),
        recipe: None,
        jobs: 1,
        shard: None,
        report: false,
    };
    let outcome = driftlab::lot::run(&lot, &mut |_| {}).unwrap();
    let axes: Vec<&str> = outcome.units[0]
        .axes
        .iter()
        .map(|a| a.axis.as_str())
        .collect();
    assert_eq!(axes, ["gx", "gy", "gz"]);
    let json = open::open(&out.join("lot.json")).unwrap();
    let csv = open::open(&out.join("lot.csv")).unwrap();
    assert_eq!(csv.columns, json.columns);
    assert!(
        json.columns
            .iter()
            .any(|c| c.axis == "gy" && c.figure == figures::k0_at(0.5))
    );
    assert_eq!(csv.rows[0].values, json.rows[0].values);
}
