//! `driftlab gui CAL.json LOG`: a calibration given beside the log (in either order) is opened
//! beside its fit; two logs or two calibrations are refused before any window opens, naming
//! both; a calibration that cannot be read ends a `--screenshot` run with its message.

use driftlab::gui::action::OpenLog;
use driftlab::gui::dialogs::ScriptedDialogs;
use driftlab::gui::settings::Settings;
use driftlab::gui::{ScreenshotOutcome, StartFiles, Workbench, split_files};
use std::path::PathBuf;

use super::open_calibration::{calibrate, judged};
use crate::common;
use common::gui::*;

/// `driftlab gui ARGS` with no display: refused before any window opens; its message.
fn refused(args: &[&std::ffi::OsStr]) -> String {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .arg("gui")
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(!out.status.success(), "{args:?}");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn a_calibration_and_a_log_are_told_apart_in_either_order() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("gyro7.json");
    calibrate(&sample("calibration.csv"), &cal, &[]);
    let log = sample("calibration.csv");
    let both = StartFiles {
        log: Some(log.clone()),
        more_runs: Vec::new(),
        calibration: Some(cal.clone()),
    };
    assert_eq!(split_files(&[cal.clone(), log.clone()]), Ok(both.clone()));
    assert_eq!(split_files(&[log.clone(), cal.clone()]), Ok(both));
    // A session is told by what it says, whatever its name; a calibration beside it is taken.
    let session = dir.path().join("monday.json");
    std::fs::write(
        &session,
        r#"{ "format": "driftlab-session", "version": 1, "session": {} }"#,
    )
    .unwrap();
    assert_eq!(
        split_files(&[cal.clone(), session.clone()]),
        Ok(StartFiles {
            log: Some(session.clone()),
            more_runs: Vec::new(),
            calibration: Some(cal.clone()),
        })
    );
    assert_eq!(
        split_files(std::slice::from_ref(&log)),
        Ok(StartFiles {
            log: Some(log.clone()),
            more_runs: Vec::new(),
            calibration: None,
        })
    );
    // A `.json` that says nothing readable is a calibration unless named as a session: its
    // loader then says where it is not one.
    let broken = dir.path().join("broken.json");
    std::fs::write(&broken, "{ oops").unwrap();
    assert_eq!(
        split_files(std::slice::from_ref(&broken))
            .unwrap()
            .calibration,
        Some(broken)
    );

    // Several logs are the runs of one campaign, in the order given.
    let other = sample("validation.csv");
    assert_eq!(
        split_files(&[log.clone(), cal.clone(), other.clone()]),
        Ok(StartFiles {
            log: Some(log.clone()),
            more_runs: vec![other.clone()],
            calibration: Some(cal.clone()),
        })
    );
    let cal2 = dir.path().join("gyro8.json");
    std::fs::copy(&cal, &cal2).unwrap();
    let session2 = dir.path().join("tuesday.json");
    std::fs::copy(&session, &session2).unwrap();
    for (args, names) in [
        (
            vec![cal.clone(), cal2.clone()],
            ["gyro7.json", "gyro8.json"],
        ),
        (
            vec![session.clone(), log.clone()],
            ["monday.json", "calibration.csv"],
        ),
        (
            vec![session.clone(), session2.clone()],
            ["monday.json", "tuesday.json"],
        ),
    ] {
        let message = split_files(&args).unwrap_err();
        let shown: Vec<&std::ffi::OsStr> = args.iter().map(|p| p.as_os_str()).collect();
        let e = refused(&shown);
        for n in names {
            assert!(message.contains(n) && e.contains(n), "{n}: {e}");
        }
        assert!(e.contains("two "), "{e}");
    }
    let gone = dir.path().join("gone.json");
    let e = refused(&[log.as_os_str(), gone.as_os_str()]);
    assert!(e.contains("gone.json") && e.contains("no such file"), "{e}");
}

/// As `driftlab gui LOG CAL.json` starts its window: the log read and calibrated, the
/// calibration opened beside it and judged; with `--screenshot`, a calibration that cannot be
/// read ends the run with its message (file, line and column).
#[test]
fn the_gui_command_opens_the_calibration_beside_the_log() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("gyro7.json");
    calibrate(&sample("calibration.csv"), &cal, &[]);
    let mut wb = Workbench::new(Settings::default(), None, Box::new(ScriptedDialogs::new()));
    driftlab::gui::start(
        &mut wb,
        Some(sample("calibration.csv")),
        Default::default(),
        None,
    );
    wb.open_calibration(cal.clone());
    let mut h = harness(wb);
    settle(&mut h);
    assert_eq!(h.state().opened().unwrap().path, cal);
    assert!(judged(&h, OpenLog::Calibration, 0).in_sample);

    let bad: PathBuf = dir.path().join("bad.json");
    std::fs::write(
        &bad,
        "{\n  \"format\": \"driftlab-calibration\",\n  oops\n}\n",
    )
    .unwrap();
    let outcome = ScreenshotOutcome::default();
    let mut wb = Workbench::new(Settings::default(), None, Box::new(ScriptedDialogs::new()));
    let shot = Some((dir.path().join("shot.png"), outcome.clone()));
    driftlab::gui::start(
        &mut wb,
        Some(sample("calibration.csv")),
        Default::default(),
        shot,
    );
    wb.open_calibration(bad);
    let mut h = harness(wb);
    for _ in 0..40 {
        if outcome.is_done() {
            break;
        }
        h.state_mut().wait_for_jobs();
        h.step();
    }
    match outcome.take() {
        Some(Err(e)) => assert!(
            e.contains("bad.json") && e.contains("line 3 column 3") && !e.contains('\n'),
            "{e}"
        ),
        other => panic!("the run ends with the calibration's message, not {other:?}"),
    }
}
