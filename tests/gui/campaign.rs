//! A campaign in the workbench: several runs of one gyro opened as one (on the command line,
//! dropped, or File › Add run), fitted together, exported with the runs' records, and kept by
//! the session. The command line's `calibrate A B C` is the other face of the same engine: the
//! workbench's export must say what it says.

use super::common::gui::{harness, settle};
use driftlab::files::calibration;
use driftlab::files::session;
use driftlab::gui::dialogs::ScriptedDialogs;
use driftlab::gui::jobs::{LoadOptions, Target};
use driftlab::gui::{Action, Workbench};
use driftlab::models::DriftModel;
use egui_kittest::kittest::Queryable;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The runs of the simulator's tiny campaign, written as CSV files into `dir`.
fn tiny_runs(dir: &Path) -> Vec<PathBuf> {
    let out = Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(["simulate", "--campaign", "tiny-three-runs", "--out-dir"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut runs: Vec<PathBuf> = ["heating", "repeat", "cooling"]
        .iter()
        .map(|r| dir.join(format!("tiny-three-runs-{r}.csv")))
        .collect();
    runs.retain(|p| p.is_file());
    assert_eq!(runs.len(), 3, "the simulator wrote its three runs");
    runs
}

/// A workbench that has read `runs` as one campaign and calibrated it.
fn opened(runs: &[PathBuf]) -> Workbench {
    let mut wb = Workbench::new_for_test(&runs[0]);
    let options = LoadOptions {
        more_runs: runs[1..].to_vec(),
        ..LoadOptions::default()
    };
    wb.start_load(runs[0].clone(), options, Target::Calibration);
    wb.wait_for_jobs();
    wb
}

/// `driftlab calibrate RUNS... [ARGS] --out OUT`, as an engineer runs it.
fn calibrate_cli(runs: &[PathBuf], args: &[&str], out: &Path) {
    let done = Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .arg("calibrate")
        .args(runs)
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    assert!(
        done.status.success(),
        "{}",
        String::from_utf8_lossy(&done.stderr)
    );
}

/// `action` asked of the workbench with `path` answered to its file dialog, and its work done.
fn answered(wb: &mut Workbench, action: Action, path: &Path) {
    let dialogs = ScriptedDialogs::new();
    dialogs.answer(Some(path.to_path_buf()));
    wb.set_dialogs(Box::new(dialogs));
    wb.act(&eframe::egui::Context::default(), action);
    wb.wait_for_jobs();
}

fn sha256sum(path: &Path) -> String {
    let out = Command::new("sha256sum").arg(path).output().unwrap();
    assert!(out.status.success());
    String::from_utf8_lossy(&out.stdout)
        .split_whitespace()
        .next()
        .unwrap()
        .to_string()
}

fn vakhrameev(path: &Path) -> driftlab::models::vakhrameev::Calibration {
    match calibration::load_model(path).expect("a calibration") {
        DriftModel::Vakhrameev(c) => *c,
        other => panic!("not Vakhrameev's model: {}", other.name()),
    }
}

#[test]
fn three_runs_open_as_one_campaign_and_export_what_calibrate_writes() {
    let dir = tempfile::tempdir().unwrap();
    let runs = tiny_runs(dir.path());
    let mut wb = opened(&runs);
    let log = wb.state.shown.log.as_ref().expect("the campaign is read");
    assert_eq!(log.log.runs().len(), 3, "{:?}", wb.state.status);
    let fit = wb.state.shown.fit.as_ref().expect("calibrated");
    assert_eq!(fit.outcome.in_sample.per_run.len(), 3);
    assert_eq!(fit.outcome.runs.len(), 3);
    // Each run's figures are of its own samples: a run's peak-to-peak of raw drift is at
    // most the whole campaign's.
    let whole = fit.outcome.in_sample.evaluation.comparison.raw.p2p_dph;
    for c in &fit.outcome.in_sample.per_run {
        assert!(c.raw.p2p_dph.is_finite() && c.raw.p2p_dph <= whole + 1e-12);
    }

    // The export, through the menu's path.
    let from_window = dir.path().join("window.json");
    answered(&mut wb, Action::ExportCalibration, &from_window);
    assert!(from_window.is_file(), "{:?}", wb.state.status);

    // The command line on the same three files.
    let from_cli = dir.path().join("cli.json");
    calibrate_cli(&runs, &[], &from_cli);

    let (w, c) = (vakhrameev(&from_window), vakhrameev(&from_cli));
    assert_eq!(w.source.runs.len(), 3);
    assert_eq!(
        w.source.runs, c.source.runs,
        "the runs' records of both faces"
    );
    assert_eq!(w.source.name, c.source.name);
    assert_eq!(w.source.sha256, "", "a campaign has no hash of its own");
    assert_eq!(w.source.temp_tolerance_c, c.source.temp_tolerance_c);
    for (r, path) in w.source.runs.iter().zip(&runs) {
        assert_eq!(r.sha256, sha256sum(path), "{}", r.name);
        assert_eq!(
            r.name,
            path.file_name().unwrap().to_string_lossy(),
            "each run named by its file"
        );
        assert!(!r.plateaus.is_empty());
    }
    // The report from the window has the campaign section, and judges each run as the run
    // of the campaign it is.
    let report = dir.path().join("report");
    answered(&mut wb, Action::ExportReport, &report);
    let html = std::fs::read_to_string(report.join("report.html")).expect("the report page");
    assert!(html.contains("Campaign of 3 runs"), "the campaign section");
    for path in &runs {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(html.contains(&name), "the report names {name}");
    }
    // One engine: the same K0 from either face.
    for t in [-30.0, 0.0, 20.0, 45.0] {
        assert_eq!(w.k0.eval(t), c.k0.eval(t), "K0 at {t} °C");
    }
}

#[test]
fn a_session_reopens_the_campaign_and_a_run_added_keeps_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let runs = tiny_runs(dir.path());

    // The first run alone, a choice made on it, then File › Add run twice.
    let mut wb = Workbench::new_for_test(&runs[0]);
    assert!(wb.state.shown.log.as_ref().unwrap().log.runs().is_empty());
    wb.state.recipe_mut().filter_s = 57.0;
    let ctx = eframe::egui::Context::default();
    for run in &runs[1..] {
        wb.act(&ctx, Action::AddRunPath(run.clone()));
        wb.wait_for_jobs();
    }
    let log = wb.state.shown.log.as_ref().unwrap();
    assert_eq!(log.log.runs().len(), 3, "{:?}", wb.state.status);
    assert_eq!(
        wb.state.shown.choices.recipe.filter_s, 57.0,
        "the work stays"
    );

    // A run of another gyro (three axes, not one) is refused by name; nothing changes.
    let mut h = harness(wb);
    settle(&mut h);
    let other = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/imu3-calibration.csv");
    let hctx = h.ctx.clone();
    h.state_mut().act(&hctx, Action::AddRunPath(other));
    settle(&mut h);
    h.get_by_label_contains("Could not read the log. Nothing was changed.");
    h.get_by_label_contains("imu3-calibration.csv is not a run of the gyro of");
    let wb = h.state();
    assert_eq!(wb.state.shown.log.as_ref().unwrap().log.runs().len(), 3);
    assert_eq!(wb.state.shown.choices.recipe.filter_s, 57.0);

    // The session names every run; reopened, it is the same campaign and fit.
    let path = dir.path().join("campaign.session.json");
    std::fs::write(&path, session::to_json(&wb.state.session())).unwrap();
    let saved = session::load(&path).unwrap();
    let log_ref = saved.log.as_ref().unwrap();
    assert_eq!(log_ref.more_runs.len(), 2);
    let k0 = |wb: &Workbench| {
        let c = &wb.state.shown.fit.as_ref().unwrap().outcome.calibration;
        [c.k0.eval(-20.0), c.k0.eval(40.0)]
    };
    let before = k0(wb);
    let mut again = Workbench::new_for_test(&runs[0]);
    again.open_session(path);
    again.wait_for_jobs();
    let log = again.state.shown.log.as_ref().unwrap();
    assert_eq!(log.log.runs().len(), 3, "{:?}", again.state.status);
    assert_eq!(again.state.shown.choices.recipe.filter_s, 57.0);
    assert_eq!(k0(&again), before);
}

#[test]
fn the_run_strip_shows_each_run_and_a_click_shows_its_span() {
    let dir = tempfile::tempdir().unwrap();
    let runs = tiny_runs(dir.path());
    let mut h = harness(opened(&runs));
    settle(&mut h);
    // Each run's button names its file.
    for r in &runs {
        let name = r.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            h.query_all_by_label_contains(&name).next().is_some(),
            "the strip names {name}"
        );
    }
    let span = {
        let log = &h.state().state.shown.log.as_ref().unwrap().log;
        let r = &log.runs()[1];
        (log.time_s[r.samples.start], log.time_s[r.samples.end - 1])
    };
    // The run's button (its number, then its name): the menu bar names the first run only.
    h.get_by_label_contains("2 tiny-three-runs-repeat.csv")
        .click();
    settle(&mut h);
    let (a, b) = h
        .state()
        .visible_time_s()
        .expect("the time plots are drawn");
    let slack = 0.05 * (span.1 - span.0);
    assert!(
        (a - span.0).abs() <= slack && (b - span.1).abs() <= slack,
        "shown {a}..{b} s, run 2 spans {}..{} s",
        span.0,
        span.1
    );
}

#[test]
fn the_models_page_shows_each_model_judged_on_the_runs_left_out() {
    let dir = tempfile::tempdir().unwrap();
    let runs = tiny_runs(dir.path());
    let mut h = harness(opened(&runs));
    settle(&mut h);
    // Ctrl+2, then Compare, as a hand does it.
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::Num2);
    h.run_ok();
    h.get_by_role_and_label(eframe::egui::accesskit::Role::Button, "Compare")
        .click();
    h.run_ok();
    settle(&mut h);
    let compared = h
        .state()
        .state
        .shown
        .models
        .clone()
        .expect("the models are compared");
    let with = compared
        .reports
        .iter()
        .filter(|r| r.leave_one_run_out.is_some())
        .count();
    assert!(
        with > 0,
        "a campaign's models are judged on the runs left out"
    );
    assert_eq!(
        h.query_all_by_label("runs left out, mean").count(),
        with,
        "one mean row under each model judged so"
    );
    assert_eq!(h.query_all_by_label("runs left out, worst").count(), with);

    // A model of the page exported records the campaign's runs, as `calibrate --model` does.
    let path = dir.path().join("poly-t.json");
    let dialogs = ScriptedDialogs::new();
    dialogs.answer(Some(path.clone()));
    h.state_mut().set_dialogs(Box::new(dialogs));
    // (Its row may lie below the table's fold: chosen as the page's selection.)
    h.state_mut().models_view().selected = Some("poly-t".into());
    h.run_ok();
    h.get_by_label("Export poly-t…").click();
    settle(&mut h);
    let window = calibration::load_model(&path).expect("the model is written");
    let cli = dir.path().join("poly-t-cli.json");
    calibrate_cli(&runs, &["--model", "poly-t"], &cli);
    let cli = calibration::load_model(&cli).unwrap();
    assert_eq!(window.source().runs.len(), 3);
    assert_eq!(window.source().runs, cli.source().runs);
}

/// A campaign of a unit (two runs of a three-axis IMU): every axis exported with the runs'
/// records `calibrate` writes for it.
#[test]
fn a_units_campaign_is_exported_with_every_axis_recording_the_runs() {
    let dir = tempfile::tempdir().unwrap();
    let sample = |n: &str| {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("sample_logs")
            .join(n)
    };
    let runs = [
        sample("imu3-calibration.csv"),
        sample("imu3-validation.csv"),
    ];
    let mut wb = opened(&runs);
    assert_eq!(wb.state.axis_count(), 3, "{:?}", wb.state.status);
    let from_window = dir.path().join("window.json");
    answered(&mut wb, Action::ExportCalibration, &from_window);
    assert!(from_window.is_file(), "{:?}", wb.state.status);
    let from_cli = dir.path().join("cli.json");
    calibrate_cli(&runs, &[], &from_cli);
    let (w, c) = (
        calibration::load_unit(&from_window).unwrap(),
        calibration::load_unit(&from_cli).unwrap(),
    );
    assert_eq!(w.axis_names(), c.axis_names());
    for (a, b) in w.axes.iter().zip(&c.axes) {
        assert_eq!(a.model.source().runs.len(), 2, "axis {}", a.name);
        assert_eq!(
            a.model.source().runs,
            b.model.source().runs,
            "axis {}",
            a.name
        );
    }
}
