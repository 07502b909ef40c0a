//! The workbench opens a drone log as File › Open and the command line do: a PX4 ULog made
//! here from the bundled chamber run reads, calibrates and is judged as the CSV it was made of.

use crate::common;
use common::drone::ulog;
use common::gui::*;
use driftlab::gui::Workbench;

#[test]
fn a_px4_ulog_opens_calibrates_and_is_judged_like_its_csv() {
    let csv = driftlab::read_path(&sample("calibration.csv"), &Default::default()).unwrap();
    let rad_s = std::f64::consts::PI / 180.0 / 3600.0;
    let gyro: Vec<[f32; 3]> = csv
        .omega_dph
        .iter()
        .map(|w| [(w * rad_s) as f32, 0.0, 0.0])
        .collect();
    let temp: Vec<f32> = csv.temp_c.iter().map(|&t| t as f32).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("thermal.ulg");
    std::fs::write(&path, ulog(&csv.time_s, &gyro, &temp, 2_424_842)).unwrap();

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
