//! The workbench opens a drone log as File › Open and the command line do: a PX4 ULog made
//! here from the bundled chamber run reads, calibrates and is judged as the CSV it was made of.

use crate::common;
use common::gui::*;
use driftlab::gui::Workbench;

/// A PX4 ULog of one `sensor_gyro` (x, y, z in rad/s and its temperature, as float32) at the
/// times given: the topic PX4's thermal-calibration logging records.
fn ulog(time_s: &[f64], gyro_x_rad_s: &[f32], temp_c: &[f32]) -> Vec<u8> {
    fn message(ty: u8, body: &[u8]) -> Vec<u8> {
        let mut m = (body.len() as u16).to_le_bytes().to_vec();
        m.push(ty);
        m.extend_from_slice(body);
        m
    }
    let mut b = b"ULog\x01\x12\x35".to_vec();
    b.push(1);
    b.extend_from_slice(&0u64.to_le_bytes());
    b.extend(message(b'B', &[0u8; 40]));
    b.extend(message(
        b'F',
        b"sensor_gyro:uint64_t timestamp;uint32_t device_id;float x;float y;float z;\
          float temperature;",
    ));
    let mut a = vec![0u8, 0, 0];
    a.extend_from_slice(b"sensor_gyro");
    b.extend(message(b'A', &a));
    for ((t, g), temp) in time_s.iter().zip(gyro_x_rad_s).zip(temp_c) {
        let mut d = vec![0u8, 0];
        d.extend_from_slice(&((t * 1e6) as u64).to_le_bytes());
        d.extend_from_slice(&2_424_842u32.to_le_bytes());
        for v in [*g, 0.0, 0.0, *temp] {
            d.extend_from_slice(&v.to_le_bytes());
        }
        b.extend(message(b'D', &d));
    }
    b
}

#[test]
fn a_px4_ulog_opens_calibrates_and_is_judged_like_its_csv() {
    let csv = driftlab::read_path(&sample("calibration.csv"), &Default::default()).unwrap();
    let rad_s = std::f64::consts::PI / 180.0 / 3600.0;
    let gyro: Vec<f32> = csv.omega_dph.iter().map(|w| (w * rad_s) as f32).collect();
    let temp: Vec<f32> = csv.temp_c.iter().map(|&t| t as f32).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("thermal.ulg");
    std::fs::write(&path, ulog(&csv.time_s, &gyro, &temp)).unwrap();

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
    let loaded = h.state().state.log.as_ref().expect("the ULog is read");
    assert_eq!(loaded.log.len(), csv.len());
    assert_eq!(loaded.log.axis, "gyro_x");
    // The gyro's float32 values, in °/h, and the temperature as stored.
    let back = (gyro[1000] as f64) / rad_s;
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
