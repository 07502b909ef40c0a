//! A six-axis MEMS IMU calibrated on the command line (`calibrate --accel`) and exported from
//! its one unit file, each export held to what `driftlab apply` subtracts on a held-out run:
//! PX4's `TC_A0_*` and `TC_G0_*` evaluated as `calc_thermal_offsets_3D` evaluates them, in
//! float32, and ArduPilot's `INS_TCAL1_ACC*` and `_GYR*` as `TCal::correct_sensor` does, each
//! equal to `apply`'s prediction up to the constant its convention leaves to the ordinary
//! calibration (none for PX4's gyro); and the C header of all six axes, compiled and run, bit
//! for bit with `apply`.

use crate::common;
use crate::firmware_unit::c_unit_agrees;
use crate::flight_exports::{
    DPH_PER_RAD_S, ardupilot_correction, ardupilot_file, px4_file, px4_offset,
};
use common::firmware::driftlab;
use driftlab::export::flight::axis_index;
use driftlab::files::calibration;
use driftlab::log::accel_axes::{self, AccelAsk};
use driftlab::log::ingest::{self, ReadOptions};
use std::path::Path;

/// Runs `driftlab ARGS`, which must succeed; what it printed.
fn ok(args: &[&str]) -> String {
    let out = driftlab(args);
    assert!(
        out.status.success(),
        "driftlab {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn at(dir: &Path, name: &str) -> String {
    dir.join(name).display().to_string()
}

/// The `mems-imu` runs of seeds 1 (calibration) and 2 (held out) in m/s², and the unit
/// calibrated on the first: every axis a cubic in T − Tref, the firmwares' form.
fn calibrated(dir: &Path) -> (String, String) {
    for seed in ["1", "2"] {
        ok(&[
            "simulate",
            "--profile",
            "mems-imu",
            "--seed",
            seed,
            "--accel-unit",
            "m/s2",
            "--out",
            &at(dir, &format!("mems{seed}.csv")),
        ]);
    }
    let cal = at(dir, "imu.json");
    ok(&[
        "calibrate",
        &at(dir, "mems1.csv"),
        "--accel",
        "--model",
        "poly-t3",
        "--out",
        &cal,
    ]);
    (cal, at(dir, "mems2.csv"))
}

/// `apply`'s predictions on `log`: each `_pred_` column with its axis's sensor and place
/// (0 = X), in rad/s or m/s² as the firmwares take them, and the temperature of each row.
struct Applied {
    /// (sensor is an accelerometer, place, predictions in the firmware's unit).
    axes: Vec<(bool, usize, Vec<f64>)>,
    temp_c: Vec<f64>,
}

fn applied(dir: &Path, cal: &str, log: &str) -> Applied {
    let out = at(dir, "applied.csv");
    ok(&["apply", cal, log, "--out", &out]);
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
        .collect();
    let column = |c: usize| rows.iter().map(|r| r[c]).collect::<Vec<f64>>();
    let mut axes = Vec::new();
    for (c, h) in header.iter().enumerate() {
        if let Some(axis) = h.strip_suffix("_pred_m_s2") {
            axes.push((true, axis_index(axis).unwrap(), column(c)));
        } else if let Some(axis) = h.strip_suffix("_pred_dph") {
            let rad_s = column(c).iter().map(|v| v / DPH_PER_RAD_S).collect();
            axes.push((false, axis_index(axis).unwrap(), rad_s));
        }
    }
    let t = header.iter().position(|h| h == "temp_c").unwrap();
    Applied {
        axes,
        temp_c: column(t),
    }
}

/// The spread over the log of `apply`'s prediction less the firmware's correction: zero up to
/// float32 where they differ by a constant alone.
fn spread(pred: &[f64], firmware: impl Fn(usize) -> f64) -> (f64, f64) {
    let d: Vec<f64> = pred
        .iter()
        .enumerate()
        .map(|(i, p)| p - firmware(i))
        .collect();
    let lo = d.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = d.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    (hi - lo, d[0])
}

#[test]
fn px4_and_ardupilot_files_of_an_imu_correct_as_apply_up_to_their_constants() {
    let dir = tempfile::tempdir().unwrap();
    let (cal, held_out) = calibrated(dir.path());
    let a = applied(dir.path(), &cal, &held_out);
    assert_eq!(a.axes.len(), 6);
    // The firmware reads the temperature as the float32 its driver logs.
    let temps: Vec<f32> = a.temp_c.iter().map(|&t| t as f32).collect();

    let text = ok(&[
        "export",
        &cal,
        "--format",
        "px4-params",
        "--device-id",
        "2424842",
    ]);
    let p = px4_file(&text);
    assert_eq!((p["TC_A_ENABLE"], p["TC_G_ENABLE"]), (1.0, 1.0));
    assert_eq!(p["TC_A0_ID"], 2424842.0);
    // X0 of the accelerometer is left to PX4's accelerometer calibration.
    for k in 0..3 {
        assert_eq!(p[&format!("TC_A0_X0_{k}")], 0.0);
    }
    let (mut accel_worst, mut gyro_worst) = (0.0f64, 0.0f64);
    for (accel, k, pred) in &a.axes {
        let prefix = if *accel { "TC_A0" } else { "TC_G0" };
        let (s, constant) = spread(pred, |i| f64::from(px4_offset(&p, prefix, *k, temps[i])));
        if *accel {
            accel_worst = accel_worst.max(s);
            // The constant left out is the bias about the mean at TREF: at most a few mg.
            assert!(constant.abs() < 0.2, "{prefix} axis {k}: {constant}");
        } else {
            // The gyro's constant is in X0: PX4 subtracts apply's prediction itself.
            gyro_worst = gyro_worst.max(s).max(constant.abs());
        }
    }
    eprintln!(
        "PX4 against apply: accelerometer spread {accel_worst:.3e} m/s^2, gyro {gyro_worst:.3e} \
         rad/s"
    );
    // Float32 parameters hold 7 digits of corrections up to 0.2 m/s², and the temperature
    // read as a float32 moves them as much again: a few 1e-8 m/s², a thousandth of a µg.
    assert!(accel_worst < 2e-7, "{accel_worst}");
    assert!(gyro_worst < 1e-8, "{gyro_worst}");

    let text = ok(&["export", &cal, "--format", "ardupilot-parm", "--imu", "1"]);
    assert!(text.contains("INS_TCAL1_ACC3_Z"), "{text}");
    let q = ardupilot_file(&text);
    let cal_temp = 25.0f32;
    let mut worst = [0.0f64; 2];
    for (accel, k, pred) in &a.axes {
        let (kind, axis) = (if *accel { "ACC" } else { "GYR" }, ["X", "Y", "Z"][*k]);
        let (s, _) = spread(pred, |i| {
            f64::from(ardupilot_correction(&q, 1, kind, axis, temps[i], cal_temp))
        });
        worst[usize::from(*accel)] = worst[usize::from(*accel)].max(s);
    }
    eprintln!(
        "ArduPilot against apply: accelerometer spread {:.3e} m/s^2, gyro {:.3e} rad/s",
        worst[1], worst[0]
    );
    assert!(worst[1] < 2e-7, "{}", worst[1]);
    assert!(worst[0] < 1e-8, "{}", worst[0]);
}

#[test]
fn the_c_header_of_a_six_axis_unit_corrects_every_axis_as_apply_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let (cal, held_out) = calibrated(dir.path());
    let unit = calibration::load_unit(Path::new(&cal)).unwrap();
    let mut log = ingest::read_path(Path::new(&held_out), &ReadOptions::default()).unwrap();
    accel_axes::take(&mut log, &AccelAsk::default()).unwrap();
    let header = ok(&["export", &cal, "--format", "c-header"]);
    assert!(
        header.contains("a unit of 6 axes, 3 of a gyro and 3 of an accelerometer,"),
        "{header}"
    );
    assert!(
        header.contains("[5] acc_z (accelerometer, m/s^2"),
        "{header}"
    );
    let Some((agreement, c)) = c_unit_agrees(&unit, &log) else {
        return;
    };
    assert_eq!(agreement.compared, 6 * log.len());
    assert_eq!(agreement.identical, agreement.compared, "{agreement:?}");
    // And what `apply` writes, every corrected column.
    let out = at(dir.path(), "applied.csv");
    ok(&["apply", &cal, &held_out, "--out", &out]);
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let cols: Vec<usize> = header
        .iter()
        .enumerate()
        .filter(|(_, h)| h.contains("_cor_"))
        .map(|(c, _)| c)
        .collect();
    assert_eq!(cols.len(), 6);
    let mut same = 0;
    for (i, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        for (k, &col) in cols.iter().enumerate() {
            let applied: f64 = cells[col].parse().unwrap();
            same += usize::from(c[i * 6 + k].cor.to_bits() == applied.to_bits());
        }
    }
    assert_eq!(same, 6 * log.len());
}

/// The MEMS IMU's run (seed 5) written as PX4 logs it into `dir/thermal.ulg`: sensor_gyro in
/// rad/s and sensor_accel in m/s², float32, with the die's temperature, the two sensors'
/// `device_id`s as given; the file and its temperatures.
fn mems_ulog(dir: &Path, device_ids: [u32; 2]) -> (String, Vec<f32>) {
    let run = driftlab::sim::simulate(&driftlab::sim::profile("mems-imu").unwrap(), 5);
    let g: Vec<[f32; 3]> = (0..run.len())
        .map(|i| [0, 1, 2].map(|k| (run.axes[k].omega_dph[i] / DPH_PER_RAD_S) as f32))
        .collect();
    let a: Vec<[f32; 3]> = (0..run.len())
        .map(|i| [0, 1, 2].map(|k| (run.accelerometers[k].values_g[i] * 9.80665) as f32))
        .collect();
    let t: Vec<f32> = run.temp_c.iter().map(|&v| v as f32).collect();
    let ulg = at(dir, "thermal.ulg");
    let bytes = common::drone::ulog_imu_of(&run.time_s, &run.time_s, &g, &a, &t, device_ids);
    std::fs::write(&ulg, bytes).unwrap();
    (ulg, t)
}

#[test]
fn a_ulog_of_gyro_and_accelerometer_calibrates_and_loads_into_px4_as_apply_predicts() {
    // The MEMS IMU's run written as PX4 logs it: sensor_gyro in rad/s and sensor_accel in
    // m/s² of one device, float32, with the die's temperature.
    let dir = tempfile::tempdir().unwrap();
    let (ulg, t) = mems_ulog(dir.path(), [2424842, 2424842]);
    let cal = at(dir.path(), "cal.json");
    let printed = ok(&[
        "calibrate",
        &ulg,
        "--accel",
        "--model",
        "px4",
        "--out",
        &cal,
    ]);
    assert!(
        printed.contains("(gyro_x, gyro_y, gyro_z, accel_x, accel_y, accel_z)"),
        "{printed}"
    );
    assert!(
        printed.contains("Gravity: axis accel_z carries it"),
        "{printed}"
    );
    // The accelerometer's device id is the gyro's unless given: one chip.
    let text = ok(&[
        "export",
        &cal,
        "--format",
        "px4-params",
        "--device-id",
        "2424842",
    ]);
    let p = px4_file(&text);
    assert_eq!(p["TC_A0_ID"], 2424842.0);
    let applied = applied(dir.path(), &cal, &ulg);
    let mut worst = 0.0f64;
    for (accel, k, pred) in applied.axes.iter().filter(|(accel, _, _)| *accel) {
        assert!(*accel);
        let (s, _) = spread(pred, |i| f64::from(px4_offset(&p, "TC_A0", *k, t[i])));
        worst = worst.max(s);
    }
    eprintln!("ULog, PX4 against apply: accelerometer spread {worst:.3e} m/s^2");
    assert!(worst < 2e-7, "{worst}");
}

#[test]
fn an_accelerometer_with_its_own_device_id_is_recorded_and_asked_for_never_given_the_gyros() {
    // A driver that numbers the chip's gyro and accelerometer apart: PX4 finds TC_A0 by the
    // accelerometer's id, so the gyro's would leave the accelerometer uncompensated.
    let dir = tempfile::tempdir().unwrap();
    let (ulg, _) = mems_ulog(dir.path(), [2424842, 2424843]);
    let listed = ok(&["inspect", &ulg]);
    assert!(
        listed.contains("device_id 2424842 (0x25000A)")
            && listed.contains("its accelerometer device_id 2424843 (0x25000B)"),
        "{listed}"
    );
    let cal = at(dir.path(), "cal.json");
    ok(&[
        "calibrate",
        &ulg,
        "--accel",
        "--model",
        "px4",
        "--out",
        &cal,
    ]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let instance = json
        .pointer("/source/instance")
        .unwrap_or_else(|| panic!("no source.instance in {json}"));
    assert_eq!(instance["px4_device_id"], 2424842);
    assert_eq!(instance["px4_accel_device_id"], 2424843);
    // The PX4 export of `cal` for the gyro 2424842 and the options `more`: whether it was
    // written, what it said on standard error, and the file.
    let px4 = |more: &[&str]| {
        let mut args = vec![
            "export",
            &cal,
            "--format",
            "px4-params",
            "--device-id",
            "2424842",
        ];
        args.extend_from_slice(more);
        let out = driftlab(&args);
        let said = String::from_utf8_lossy(&out.stderr).into_owned();
        (out.status.success(), said, out.stdout)
    };
    // Given the gyro's id alone, the export asks for the accelerometer's, naming it.
    let (written, said, _) = px4(&[]);
    assert!(!written, "{said}");
    assert!(
        said.contains("has its own device_id 2424843") && said.contains("(--accel-device-id N)"),
        "{said}"
    );
    // The gyro's id given for it is the mistake itself, refused naming the recorded one.
    let (written, said, _) = px4(&["--accel-device-id", "2424842"]);
    assert!(
        !written && said.contains("its accelerometer had its own, 2424843"),
        "{said}"
    );
    let (written, said, text) = px4(&["--accel-device-id", "0x25000B"]);
    assert!(written, "{said}");
    let p = px4_file(&String::from_utf8(text).unwrap());
    assert_eq!(p["TC_G0_ID"], 2424842.0);
    assert_eq!(p["TC_A0_ID"], 2424843.0);
    // The ids recorded given: nothing to say of them.
    assert!(!said.contains("not that of the"), "{said}");
    // Another accelerometer's id is taken (a sensor on another bus or address) but said,
    // naming the recorded one; as is another gyro's.
    let (written, said, _) = px4(&["--accel-device-id", "2424999"]);
    assert!(written, "{said}");
    assert!(
        said.contains(
            "TC_A0_ID is the device_id given, 2424999 (0x2500A7), not that of the \
             accelerometer the calibration was fitted on, 2424843 (0x25000B)"
        ),
        "{said}"
    );
    let out = driftlab(&[
        "export",
        &cal,
        "--format",
        "px4-params",
        "--device-id",
        "1234",
        "--accel-device-id",
        "2424843",
    ]);
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{said}");
    assert!(
        said.contains(
            "TC_G0_ID is the device_id given, 1234 (0x4D2), not that of the gyro the \
             calibration was fitted on, 2424842 (0x25000A)"
        ),
        "{said}"
    );
    // A gyro axis alone has no accelerometer to give an id to.
    let (written, said, _) = px4(&["--axis", "gyro_x", "--accel-device-id", "2424843"]);
    assert!(
        !written && said.contains("has no accelerometer axis to write"),
        "{said}"
    );
}
