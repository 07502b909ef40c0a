//! Accelerometer axes in the workbench: a six-axis log (the simulator's MEMS IMU) opens with its
//! accelerometers in the axis strip beside the gyro axes, each shown in m/s² with the axis
//! that carries gravity said; the exports hold them as `driftlab calibrate --accel` and
//! `driftlab apply` write them (the command line run beside the window, as an engineer would);
//! the switch that leaves them out is kept by the session, and a session written without it
//! opens with them.

use super::common::gui::{harness, settle, with_dialogs};
use driftlab::export::firmware::Format;
use driftlab::files::calibration;
use driftlab::gui::{Action, Workbench};
use driftlab::log::AxisKind;
use driftlab::log::accel_axes::{self, AccelAsk};
use driftlab::log::ingest::{self, ReadOptions};
use eframe::egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `driftlab ARGS` (which must succeed) and returns what it printed.
pub(crate) fn driftlab(args: &[&std::ffi::OsStr]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "driftlab {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The six-axis MEMS IMU of seed 1, written into `dir` by `driftlab simulate` as the
/// documentation tells an engineer to make it.
pub(crate) fn imu6(dir: &Path) -> PathBuf {
    let path = dir.join("imu6.csv");
    driftlab(&[
        "simulate".as_ref(),
        "--profile".as_ref(),
        "mems-imu".as_ref(),
        "--seed".as_ref(),
        "1".as_ref(),
        "-o".as_ref(),
        path.as_os_str(),
    ]);
    path
}

/// The accelerometer axes the engine makes of the log's columns, read apart from the window.
fn accel_names(path: &Path) -> Vec<String> {
    let mut log = ingest::read_path(path, &ReadOptions::default()).unwrap();
    accel_axes::take(&mut log, &AccelAsk::default()).unwrap();
    log.axes_of(AxisKind::Accel)
}

pub(crate) fn opened(path: &Path) -> Harness<'static, Workbench> {
    let mut h = harness(Workbench::new_for_test(path));
    settle(&mut h);
    h
}

pub(crate) fn act(h: &mut Harness<'_, Workbench>, a: Action) {
    let ctx = h.ctx.clone();
    h.state_mut().act(&ctx, a);
    h.run_ok();
    settle(h);
}

/// A calibration file as JSON with the time it was written taken out of every axis (the only
/// field two runs of one calibration may differ in).
pub(crate) fn without_dates(path: &Path) -> serde_json::Value {
    fn strip(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Object(o) => {
                o.remove("created");
                o.values_mut().for_each(strip);
            }
            serde_json::Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    strip(&mut v);
    v
}

#[test]
fn a_six_axis_log_lists_its_accelerometers_and_shows_them_in_m_s2() {
    let dir = tempfile::tempdir().unwrap();
    let log = imu6(dir.path());
    let names = accel_names(&log);
    assert_eq!(names.len(), 3, "the simulated IMU has three accelerometers");
    // The command line's figures and its gravity axis, for the same log.
    let cli_out = dir.path().join("cli.json");
    let printed = driftlab(&[
        "calibrate".as_ref(),
        log.as_os_str(),
        "--accel".as_ref(),
        "--json".as_ref(),
        "--out".as_ref(),
        cli_out.as_os_str(),
    ]);
    let cli: serde_json::Value = serde_json::from_str(&printed).unwrap();
    let gravity_axis = cli["gravity"]["axis"].as_str().unwrap().to_string();

    let mut h = opened(&log);
    let s = &h.state().state;
    assert!(s.accel_on(), "accelerometer axes are on by default");
    assert_eq!(s.accel.as_ref().unwrap().names, names);
    assert!(s.accel_current(), "calibrated on opening");
    // Each in the strip, beside the gyro axes, with its figures in m/s².
    for name in &names {
        let mark = if *name == gravity_axis { " g" } else { "" };
        h.get_by_label_contains(&format!("{name}{mark}  p2p "));
    }
    assert_eq!(
        h.query_all_by_label_contains(" m/s²").count(),
        names.len(),
        "every accelerometer's figures in m/s²"
    );

    // Shown: its figures in m/s², as the command line gives them, and no °/h anywhere.
    let k = 1;
    h.get_by_label_contains(&format!("{}  p2p ", names[k]))
        .click();
    h.run_ok();
    assert_eq!(h.state().state.accel_shown(), Some(k));
    h.get_by_label_contains(&format!("Accelerometer axis {}", names[k]));
    // (the figures panel's table, headed by the axis's unit)
    h.get_by_label("m/s²");
    let axis = cli["axes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["name"] == names[k].as_str())
        .expect("the command line's axis");
    assert_eq!(axis["unit"], "m/s^2");
    let figures = &axis["in_sample"]["comparison"];
    for which in ["raw", "corrected"] {
        for figure in ["p2p_m_s2", "std_m_s2"] {
            let v = figures[which][figure].as_f64().unwrap();
            h.get_by_label(&driftlab::number::fixed(v, 6));
        }
    }
    h.get_by_label_contains(&format!("Gravity: axis {gravity_axis} carries it"));
    assert_eq!(
        h.query_all_by_label_contains("°/h").count(),
        0,
        "no °/h on an accelerometer axis"
    );

    // A gyro axis chosen again: its own page.
    act(&mut h, Action::SelectAxis(0));
    assert_eq!(h.state().state.accel_shown(), None);
}

#[test]
fn exports_hold_the_accelerometer_axes_as_calibrate_accel_and_apply_write_them() {
    let dir = tempfile::tempdir().unwrap();
    let log = imu6(dir.path());
    let mut h = opened(&log);
    let dialogs = with_dialogs(h.state_mut());

    let window = dir.path().join("window.json");
    dialogs.answer(Some(window.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    settle(&mut h);
    let cli = dir.path().join("cli.json");
    driftlab(&[
        "calibrate".as_ref(),
        log.as_os_str(),
        "--accel".as_ref(),
        "--out".as_ref(),
        cli.as_os_str(),
    ]);
    let unit = calibration::load_unit(&window).expect("the window's unit reads back");
    assert_eq!(
        unit.axes
            .iter()
            .filter(|a| a.kind == AxisKind::Accel)
            .map(|a| a.name.clone())
            .collect::<Vec<_>>(),
        accel_names(&log)
    );
    // Every axis, coefficient for coefficient, kept means and records alike.
    assert_eq!(without_dates(&window), without_dates(&cli));

    // The corrected log: what `driftlab apply` writes with the command line's calibration.
    let csv = dir.path().join("window-corrected.csv");
    dialogs.answer(Some(csv.clone()));
    h.key_press_modifiers(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::E);
    settle(&mut h);
    let applied = dir.path().join("applied.csv");
    driftlab(&[
        "apply".as_ref(),
        cli.as_os_str(),
        log.as_os_str(),
        "--out".as_ref(),
        applied.as_os_str(),
    ]);
    let body = |p: &Path| {
        std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    let written = body(&csv);
    assert!(
        written[0].contains("acc_x_raw_m_s2"),
        "the accelerometer axes' columns: {}",
        written[0]
    );
    assert_eq!(written, body(&applied));

    // ArduPilot's file: what `driftlab export` writes of the command line's calibration, the
    // accelerometers' parameters among them.
    let parm = dir.path().join("window.parm");
    dialogs.answer(Some(parm.clone()));
    act(&mut h, Action::ExportFlight(Format::ArdupilotParm));
    let exported = dir.path().join("exported.parm");
    driftlab(&[
        "export".as_ref(),
        cli.as_os_str(),
        "--format".as_ref(),
        "ardupilot-parm".as_ref(),
        "--out".as_ref(),
        exported.as_os_str(),
    ]);
    let written = body(&parm);
    assert!(
        written.iter().any(|l| l.starts_with("INS_TCAL1_ACC1_X")),
        "{written:?}"
    );
    assert_eq!(written, body(&exported));

    // The report: every axis, the accelerometers' with the axis that carries gravity.
    let report = dir.path().join("report");
    dialogs.answer(Some(report.clone()));
    act(&mut h, Action::ExportReport);
    let html = std::fs::read_to_string(report.join("report.html")).expect("the report is written");
    for name in accel_names(&log) {
        assert!(html.contains(&name), "axis {name} in the report");
    }
    assert!(html.contains("carries gravity"));
}

#[test]
fn the_switch_leaves_them_out_and_the_session_keeps_it() {
    let dir = tempfile::tempdir().unwrap();
    let log = imu6(dir.path());
    let mut h = opened(&log);
    let dialogs = with_dialogs(h.state_mut());

    // A session saved with them on says nothing of them: as written before they existed.
    let on = dir.path().join("on.session.json");
    dialogs.answer(Some(on.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    settle(&mut h);
    let text = std::fs::read_to_string(&on).unwrap();
    assert!(!text.contains("accelerometers"), "{text}");

    // Off: the strip says so, the export holds the gyro axes alone, the session is unsaved.
    h.get_by_label("Accelerometers").click();
    h.run_ok();
    settle(&mut h);
    assert!(!h.state().state.accel_on());
    assert!(h.state().state.dirty(), "turning them off is a change");
    assert_eq!(h.query_all_by_label_contains(" m/s²").count(), 0);
    let gyro_only = dir.path().join("gyro.json");
    dialogs.answer(Some(gyro_only.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    settle(&mut h);
    let unit = calibration::load_unit(&gyro_only).unwrap();
    assert!(unit.axes.iter().all(|a| a.kind == AxisKind::Gyro));
    assert_eq!(unit.axes.len(), 3);
    let off = dir.path().join("off.session.json");
    dialogs.answer(Some(off.clone()));
    act(&mut h, Action::SaveSessionAs);
    assert!(
        std::fs::read_to_string(&off)
            .unwrap()
            .contains("\"accelerometers_off\": true")
    );

    // Each session opens as it was saved.
    for (session, want_on) in [(off, false), (on, true)] {
        let mut other = opened(&log);
        let ctx = other.ctx.clone();
        other
            .state_mut()
            .act(&ctx, Action::OpenSessionPath(session.clone()));
        settle(&mut other);
        let s = &other.state().state;
        assert_eq!(s.accel_on(), want_on, "{}", session.display());
        assert!(!s.dirty(), "{}: nothing unsaved", session.display());
    }
}

#[test]
fn a_calibration_opened_beside_is_judged_on_the_accelerometer_axes_as_evaluate_judges_it() {
    use super::open_calibration::evaluate_json;
    use driftlab::gui::action::OpenLog;
    use driftlab::gui::jobs::AxisVerdict;
    let dir = tempfile::tempdir().unwrap();
    let log = imu6(dir.path());
    let cal = dir.path().join("cli.json");
    driftlab(&[
        "calibrate".as_ref(),
        log.as_os_str(),
        "--accel".as_ref(),
        "--out".as_ref(),
        cal.as_os_str(),
    ]);
    let cli = evaluate_json(&cal, &log, &[]);
    let mut h = opened(&log);
    act(&mut h, Action::OpenCalibrationPath(cal.clone()));
    let v = h.state().opened().unwrap().verified.as_ref().unwrap();
    let axes = &v
        .logs
        .iter()
        .find(|l| l.which == OpenLog::Calibration)
        .unwrap()
        .axes;
    let names = accel_names(&log);
    let file = calibration::load_unit(&cal).unwrap();
    for (k, ax) in file.axes.iter().enumerate() {
        let AxisVerdict::Judged(j) = &axes[k] else {
            panic!("axis {} is not judged on the log", ax.name);
        };
        assert_eq!(j.log_axis, ax.name);
        let want = &cli["axes"][k];
        assert_eq!(want["name"], ax.name.as_str());
        // The engine's figures, named in the axis's unit as the command names them.
        let mut got = serde_json::to_value(j.evaluation).unwrap();
        ax.kind.name_fields_in_unit(&mut got);
        assert_eq!(got, want["evaluation"], "axis {}", ax.name);
    }
    assert!(names.iter().all(|n| file.axes.iter().any(|a| a.name == *n)));
}

/// The simulated IMU of `dir` with its gyro axes but the first left out: a log of one gyro
/// axis (`omega_x_dph`) and three accelerometers.
pub(crate) fn one_gyro(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(imu6(dir)).unwrap();
    let mut out = String::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let cells: Vec<&str> = line.split(',').collect();
        out.push_str(&[&cells[..2], &cells[4..]].concat().join(","));
        out.push('\n');
    }
    assert!(out.starts_with("time_s,omega_x_dph,acc_x_g,acc_y_g,acc_z_g,temp_c,"));
    let path = dir.join("one-gyro.csv");
    std::fs::write(&path, out).unwrap();
    path
}

#[test]
fn a_log_of_one_gyro_axis_is_a_unit_with_its_accelerometers_as_calibrate_accel_makes_it() {
    let dir = tempfile::tempdir().unwrap();
    let log = one_gyro(dir.path());
    let names = accel_names(&log);
    assert_eq!(names, ["acc_x", "acc_y", "acc_z"]);
    let mut h = opened(&log);
    let dialogs = with_dialogs(h.state_mut());
    let s = &h.state().state;
    assert!(s.unit.is_none(), "one gyro axis");
    assert!(s.accel_on() && s.accel_current());
    assert_eq!(s.accel.as_ref().unwrap().names, names);
    // The strip: the gyro axis by its name, then the accelerometers.
    h.get_by_label_contains("omega_x  ");
    // (the simulated IMU reads g on z)
    for name in &names {
        let mark = if name == "acc_z" { " g" } else { "" };
        h.get_by_label_contains(&format!("{name}{mark}  p2p "));
    }
    h.get_by_label_contains("acc_y  p2p ").click();
    h.run_ok();
    assert_eq!(h.state().state.accel_shown(), Some(1));
    h.get_by_label_contains("Accelerometer axis acc_y");
    h.get_by_label_contains("omega_x  ").click();
    h.run_ok();
    assert_eq!(h.state().state.accel_shown(), None, "back to the gyro axis");

    // Its calibration: the unit `calibrate --accel` writes of the log, every axis.
    let window = dir.path().join("window.json");
    dialogs.answer(Some(window.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    settle(&mut h);
    let cli = dir.path().join("cli.json");
    let os = std::ffi::OsStr::new;
    driftlab(&[
        os("calibrate"),
        log.as_os_str(),
        os("--accel"),
        os("--out"),
        cli.as_os_str(),
    ]);
    let unit = calibration::load_unit(&window).expect("the window's unit reads back");
    assert_eq!(unit.axis_names(), ["omega_x", "acc_x", "acc_y", "acc_z"]);
    assert_eq!(without_dates(&window), without_dates(&cli));

    // Its corrected log: `apply`'s of that calibration, every axis.
    let csv = dir.path().join("window-corrected.csv");
    dialogs.answer(Some(csv.clone()));
    h.key_press_modifiers(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::E);
    settle(&mut h);
    let applied = dir.path().join("applied.csv");
    driftlab(&[
        os("apply"),
        cli.as_os_str(),
        log.as_os_str(),
        os("--out"),
        applied.as_os_str(),
    ]);
    let body = |p: &Path| {
        std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    assert_eq!(body(&csv), body(&applied));

    // That calibration opened beside the fit is judged on every axis of the log, the
    // accelerometers' among them.
    act(&mut h, Action::OpenCalibrationPath(cli.clone()));
    let v = h.state().opened().unwrap().verified.as_ref().unwrap();
    let on_log = v
        .logs
        .iter()
        .find(|l| l.which == driftlab::gui::action::OpenLog::Calibration)
        .unwrap();
    for (k, name) in unit.axis_names().iter().enumerate() {
        match &on_log.axes[k] {
            driftlab::gui::jobs::AxisVerdict::Judged(j) => assert_eq!(j.log_axis, *name),
            _ => panic!("axis {name} is not judged on the log"),
        }
    }
    act(&mut h, Action::CloseCalibration);

    // Switched off, the log is the one axis it was: the file `calibrate` writes without
    // --accel (version 1, one unnamed axis).
    h.get_by_label("Accelerometers").click();
    h.run_ok();
    settle(&mut h);
    let alone = dir.path().join("alone.json");
    dialogs.answer(Some(alone.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    settle(&mut h);
    let cli_alone = dir.path().join("cli-alone.json");
    driftlab(&[
        os("calibrate"),
        log.as_os_str(),
        os("--out"),
        cli_alone.as_os_str(),
    ]);
    assert_eq!(without_dates(&alone), without_dates(&cli_alone));
}
