//! The IMU an ArduPilot parameter file is written for (`INS_TCALn`): the one asked for, else
//! the one the calibration records it was fitted on (a DataFlash log's `IMU` instance `I`,
//! `n = I + 1`), else the first with a note; axes fitted on different IMUs are refused until
//! one is asked for.

use super::flight_exports::{Curve, DPH_PER_RAD_S, ardupilot_correction, ardupilot_file};
use super::flight_exports::{custom, fit, log_of};
use driftlab::export::flight::FlightError;
use driftlab::export::flight::ardupilot::{ArduPilotTarget, ardupilot_parm};
use driftlab::export::flight::{AxisFit, ImuFits};
use driftlab::log::DroneGyro;
use driftlab::models::DriftModel;

/// The three gyro axes, each fitted on its own curve (rad/s around 35 °C), each recording
/// the DataFlash IMU `imus[k]` it was fitted on.
fn fitted_on(imus: [Option<u8>; 3]) -> (Vec<Curve>, Vec<DriftModel>) {
    let curves = vec![
        Curve([0.01, 1.0e-4, -1.0e-6, 0.0]),
        Curve([-0.02, -2.0e-4, 0.0, 1.0e-8]),
        Curve([0.005, 3.0e-4, 2.0e-6, 0.0]),
    ];
    let models = curves
        .iter()
        .zip(imus)
        .enumerate()
        .map(|(k, (&c, imu))| {
            let mut m = fit(
                &log_of(c, DPH_PER_RAD_S, 0.0005, 40 + k as u64),
                &custom("1,T,T^2,T^3"),
            );
            m.source_mut().instance = imu.map(|i| DroneGyro {
                dataflash_imu: Some(i),
                ..DroneGyro::numbered(usize::from(i))
            });
            m
        })
        .collect();
    (curves, models)
}

fn fits(models: &[DriftModel]) -> ImuFits<'_> {
    ImuFits {
        gyro: ["gyro_x", "gyro_y", "gyro_z"]
            .iter()
            .zip(models)
            .map(|(&axis, model)| AxisFit { axis, model })
            .collect(),
        accel: Vec::new(),
    }
}

/// Models fitted on IMU I=2 are written as `INS_TCAL3` by default, and the firmware's
/// correction of that IMU follows the curves they were fitted on (slope at 35 °C within the
/// noise); nothing of `INS_TCAL1` or `INS_TCAL2` is written.
#[test]
fn the_default_imu_is_the_one_the_models_were_fitted_on() {
    let (curves, models) = fitted_on([Some(2); 3]);
    let file = ardupilot_parm(&fits(&models), &ArduPilotTarget::default()).unwrap();
    let p = ardupilot_file(&file.text);
    assert!(
        p.keys().all(|k| k.starts_with("INS_TCAL3_")),
        "{}",
        file.text
    );
    for (k, axis) in ["X", "Y", "Z"].iter().enumerate() {
        // The change from 34 to 36 °C, against the curve's own.
        let fw = f64::from(ardupilot_correction(&p, 3, "GYR", axis, 36.0, 34.0));
        let truth = curves[k].0[1] * 2.0 + curves[k].0[3] * 2.0;
        assert!((fw - truth).abs() < 5e-6, "{axis}: {fw} for {truth}");
    }
    assert!(
        file.notes
            .iter()
            .any(|n| n
                == "INS_TCAL3: the calibration was fitted on IMU 3 (DataFlash I=2) of its log"),
        "{:?}",
        file.notes
    );
}

/// Axes fitted on different IMUs are refused, naming them, until an IMU is asked for; then
/// written as asked with a note naming both. An IMU past ArduPilot's three is refused.
#[test]
fn axes_of_different_imus_are_refused_unless_an_imu_is_asked_for() {
    let (_, models) = fitted_on([Some(0), Some(1), Some(1)]);
    let err = ardupilot_parm(&fits(&models), &ArduPilotTarget::default()).unwrap_err();
    assert!(matches!(err, FlightError::ImuNumber(_)), "{err:?}");
    let said = err.to_string();
    assert!(
        said.contains("IMU 1 (DataFlash I=0), IMU 2 (DataFlash I=1)"),
        "{said}"
    );
    let file = ardupilot_parm(&fits(&models), &ArduPilotTarget { imu: Some(2) }).unwrap();
    assert!(file.text.contains("INS_TCAL2_GYR1_X "), "{}", file.text);
    assert!(
        file.notes.iter().any(|n| n.contains("as asked")
            && n.contains("IMU 1 (DataFlash I=0) and IMU 2 (DataFlash I=1)")),
        "{:?}",
        file.notes
    );

    let (_, models) = fitted_on([Some(3); 3]);
    let err = ardupilot_parm(&fits(&models), &ArduPilotTarget::default()).unwrap_err();
    assert!(matches!(err, FlightError::ImuNumber(_)), "{err:?}");
    assert!(err.to_string().contains("not 4"), "{err}");
}

/// Models that record no DataFlash IMU are written as `INS_TCAL1`, with a note saying the
/// calibration does not say which IMU; one asked for is written without a note.
#[test]
fn models_without_an_imu_are_written_as_the_first_with_a_note() {
    let (_, models) = fitted_on([None; 3]);
    let file = ardupilot_parm(&fits(&models), &ArduPilotTarget::default()).unwrap();
    assert!(file.text.contains("INS_TCAL1_ENABLE 1"), "{}", file.text);
    assert!(
        file.notes
            .iter()
            .any(|n| n.starts_with("INS_TCAL1, the first IMU: the calibration records no")),
        "{:?}",
        file.notes
    );
    let file = ardupilot_parm(&fits(&models), &ArduPilotTarget { imu: Some(3) }).unwrap();
    assert!(file.text.contains("INS_TCAL3_ENABLE 1"), "{}", file.text);
    assert!(
        !file.notes.iter().any(|n| n.contains("INS_TCAL1")),
        "{:?}",
        file.notes
    );
}
