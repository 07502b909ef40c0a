//! The workbench opens a drone log as File › Open and the command line do: a PX4 ULog made
//! here from the bundled chamber run reads, calibrates and is judged as the CSV it was made of.

use crate::common;
use common::drone::ulog;
use common::gui::*;
use driftlab::gui::Workbench;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

/// rad/s in one °/h.
const RAD_S_PER_DPH: f64 = std::f64::consts::PI / 180.0 / 3600.0;

/// The bundled chamber run as a PX4 ULog at `dir/name`, its rate on gyro x (y and z read 0),
/// with the CSV it was made of and the float32 gyro and temperature written.
fn chamber_run_as_ulog(
    dir: &std::path::Path,
    name: &str,
) -> (std::path::PathBuf, driftlab::Log, Vec<[f32; 3]>, Vec<f32>) {
    let csv = driftlab::read_path(&sample("calibration.csv"), &Default::default()).unwrap();
    let gyro: Vec<[f32; 3]> = csv
        .omega_dph
        .iter()
        .map(|w| [(w * RAD_S_PER_DPH) as f32, 0.0, 0.0])
        .collect();
    let temp: Vec<f32> = csv.temp_c.iter().map(|&t| t as f32).collect();
    let path = dir.join(name);
    std::fs::write(&path, ulog(&csv.time_s, &gyro, &temp, 2_424_842)).unwrap();
    (path, csv, gyro, temp)
}

#[test]
fn a_px4_ulog_opens_calibrates_and_is_judged_like_its_csv() {
    let dir = tempfile::tempdir().unwrap();
    let (path, csv, gyro, temp) = chamber_run_as_ulog(dir.path(), "thermal.ulg");
    let rad_s = RAD_S_PER_DPH;

    let mut wb = Workbench::new(
        Default::default(),
        None,
        Box::new(driftlab::gui::ScriptedDialogs::new()),
    );
    // As File › Open: a drone log has no columns to map, so no import view.
    wb.open_log(path.clone(), Default::default(), true);
    assert!(wb.import_view().is_none(), "no columns to map in a ULog");
    let mut h = harness(wb);
    settle(&mut h);
    let loaded = h
        .state()
        .state
        .shown
        .log
        .as_ref()
        .expect("the ULog is read");
    assert_eq!(loaded.log.len(), csv.len());
    assert_eq!(loaded.log.axis, "gyro_x");
    // The gyro's float32 values, in °/h, and the temperature as stored.
    let back = (gyro[1000][0] as f64) / rad_s;
    assert!((loaded.log.omega_dph[1000] - back).abs() <= 1e-9 * back.abs().max(1.0));
    assert_eq!(loaded.log.temp_c[1000], temp[1000] as f64);
    // Calibrated as the CSV is, up to the float32 rounding of its samples.
    let from_ulog = p2p_corrected(&h);
    let mut h_csv = harness(Workbench::new(
        Default::default(),
        None,
        Box::new(driftlab::gui::ScriptedDialogs::new()),
    ));
    h_csv
        .state_mut()
        .open_log(sample("calibration.csv"), Default::default(), false);
    settle(&mut h_csv);
    let from_csv = p2p_corrected(&h_csv);
    assert!(
        (from_ulog - from_csv).abs() <= 0.02 * from_csv,
        "ULog {from_ulog} °/h, CSV {from_csv} °/h"
    );
}

/// File › Gyro of the log reads another gyro of a drone log (as `--gyro N`), and the
/// temperature from another source (as `--temp-from`); the session keeps the choice.
#[test]
fn another_gyro_of_a_drone_log_is_chosen_from_the_menu() {
    use common::drone::ulog_of_subscriptions;
    // The bundled chamber run as gyro 0, and as gyro 1 reading 1e-4 rad/s more: told apart
    // by their rates.
    let csv = driftlab::read_path(&sample("calibration.csv"), &Default::default()).unwrap();
    let n = csv.len();
    let rad_s = RAD_S_PER_DPH;
    let rate = |extra: f64| -> Vec<[f32; 3]> {
        csv.omega_dph
            .iter()
            .map(|w| {
                let v = (w * rad_s + extra) as f32;
                [v, v, v]
            })
            .collect()
    };
    let (rate_a, rate_b) = (rate(0.0), rate(1e-4));
    let temp: Vec<f32> = csv.temp_c.iter().map(|&t| t as f32).collect();
    let ids_a = vec![2_424_842u32; n];
    let ids_b = vec![3_670_050u32; n];
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("two_gyros.ulg");
    std::fs::write(
        &path,
        ulog_of_subscriptions(&csv.time_s, &temp, &[(&ids_a, &rate_a), (&ids_b, &rate_b)]),
    )
    .unwrap();
    let mut h = harness(Workbench::new_for_test(&path));
    settle(&mut h);
    let dph = |v: f32| f64::from(v) / rad_s;
    let read = |h: &Harness<'_, Workbench>| {
        let l = h.state().state.shown.log.as_ref().expect("read");
        let d = l.drone.as_ref().expect("a drone log");
        (d.chosen, d.instances.len(), l.log.omega_dph[100])
    };
    let (chosen, gyros, omega) = read(&h);
    assert_eq!((chosen, gyros), (0, 2));
    assert!((omega - dph(rate_a[100][0])).abs() < 1e-6, "{omega}");
    h.get_by_label_contains("gyro 0 (2 in the log)");

    h.get_by_label("File").click();
    h.run_ok();
    h.get_by_label_contains("Gyro of the log").click();
    h.run_ok();
    h.get_by_label_contains("gyro 1  sensor_gyro multi_id 1")
        .click();
    settle(&mut h);
    let (chosen, _, omega) = read(&h);
    assert_eq!(chosen, 1);
    assert!((omega - dph(rate_b[100][0])).abs() < 1e-6, "{omega}");
    let session = h.state().state.session();
    assert_eq!(session.log.as_ref().unwrap().instance.gyro, Some(1));

    // The temperature from the accelerometer of the same IMU: this log has none, so the
    // read is refused with the reader's reason and the work stays as it was (gyro 1).
    h.get_by_label("File").click();
    h.run_ok();
    h.get_by_label_contains("Gyro of the log").click();
    h.run_ok();
    h.get_by_label("the accelerometer's of the same IMU")
        .click();
    settle(&mut h);
    h.get_by_label_contains("Could not read the log. Nothing was changed.");
    h.get_by_label_contains("has no accel temperature");
    h.get_by_label_contains("could use File › Gyro of the log › Temperature from own");
    let l = h.state().state.shown.log.as_ref().unwrap();
    assert_eq!(l.options.instance.gyro, Some(1));
    assert_eq!(l.options.instance.temp_from, None);
    assert_eq!(l.drone.as_ref().unwrap().chosen, 1);
}

/// A drone log whose axes the reader doubts (two that read one value throughout) is worked
/// on as read, the doubt said in the status line: the import view maps a CSV's columns and
/// would read the ULog as text ("a binary file, not a text log"), and as a modal it took the
/// engineer's next click.
#[test]
fn a_drone_log_with_a_stuck_axis_opens_without_the_import_view() {
    let dir = tempfile::tempdir().unwrap();
    let (path, ..) = chamber_run_as_ulog(dir.path(), "stuck.ulg");
    let mut wb = Workbench::new(
        Default::default(),
        None,
        Box::new(driftlab::gui::ScriptedDialogs::new()),
    );
    wb.open_log(path, Default::default(), true);
    let mut h = harness(wb);
    settle(&mut h);
    assert!(h.state_mut().import_view().is_none(), "no import view");
    let (_, said) = h.state().state.status.clone().expect("a status");
    assert!(
        said.contains("stuck.ulg") && said.contains("gyro_y"),
        "{said}"
    );
    // The menu opens at the first click: nothing modal stands over the window.
    h.get_by_label("File").click();
    h.run_ok();
    h.get_by_label_contains("Open session");
}
