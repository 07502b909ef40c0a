//! Turns the subscriptions of a read ULog into gyro instances: each `sensor_gyro` with the
//! accelerometer of the same device and the `vehicle_imu_status` temperatures matched to its
//! samples, then the fused `sensor_combined`. Apart from the reading because it decides what a
//! log offers, not whether its bytes are sound.

use super::subscription::Sub;
use crate::log::formats::recording::{
    AltTemperature, Axes, DeviceId, GyroInstance, Problem, Sorted, TempFrom, Timestamps, Values,
    median_step,
};
use std::cell::OnceCell;

/// Why a subscription gives no gyro instance: a field it lacks. The reader notes it after the
/// subscription's name and leaves the instance out.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
enum Missing {
    /// No integer `timestamp`.
    #[error("it has no integer timestamp")]
    Timestamp,
    /// No float field of that name.
    #[error("it has no float field {0}")]
    Float(String),
}

/// An accelerometer's or status's stamps, sorted once for every gyro matched against them.
type Keys = OnceCell<Option<Sorted>>;

/// Turns the subscriptions into gyro instances.
pub(super) fn assemble(subs: Vec<Sub>, problems: &mut Vec<Problem>) -> Vec<GyroInstance> {
    let mut gyros: Vec<&Sub> = subs.iter().filter(|s| s.topic == "sensor_gyro").collect();
    gyros.sort_by_key(|s| s.multi_id);
    let accels: Vec<(&Sub, Keys)> = subs
        .iter()
        .filter(|s| s.topic == "sensor_accel")
        .map(|s| (s, Keys::new()))
        .collect();
    let statuses: Vec<(&Sub, Keys)> = subs
        .iter()
        .filter(|s| s.topic == "vehicle_imu_status")
        .map(|s| (s, Keys::new()))
        .collect();
    let mut out = Vec::new();
    for g in gyros {
        match gyro_instance(g, &accels, &statuses, out.len()) {
            Ok(inst) => out.push(inst),
            Err(m) => problems.push(Problem::note(format!("{}: {m}; left out", g.label()))),
        }
    }
    for c in subs.iter().filter(|s| s.topic == "sensor_combined") {
        match combined_instance(c, out.len()) {
            Ok(inst) => out.push(inst),
            Err(m) => problems.push(Problem::note(format!("{}: {m}; left out", c.label()))),
        }
    }
    out
}

fn axes(s: &Sub, names: [(&str, usize); 3]) -> Result<Axes, Missing> {
    let get = |(n, k): (&str, usize)| s.values(n, k).ok_or_else(|| Missing::Float(n.to_string()));
    Ok(Axes {
        xyz: [get(names[0])?, get(names[1])?, get(names[2])?],
    })
}

/// The x, y, z of `s` at the rows `pick` names, when it has all three as floats.
fn axes_at(s: &Sub, pick: &[Option<usize>]) -> Option<Axes> {
    Some(Axes {
        xyz: [
            s.values_at("x", 0, pick)?,
            s.values_at("y", 0, pick)?,
            s.values_at("z", 0, pick)?,
        ],
    })
}

fn gyro_instance(
    g: &Sub,
    accels: &[(&Sub, Keys)],
    statuses: &[(&Sub, Keys)],
    index: usize,
) -> Result<GyroInstance, Missing> {
    let n = g.count();
    let time = g.integers("timestamp").ok_or(Missing::Timestamp)?;
    let sample = g.integers("timestamp_sample");
    let device = g.first_integer("device_id");
    let gyro = axes(g, [("x", 0), ("y", 0), ("z", 0)])?;
    let temp_c = g
        .values("temperature", 0)
        .unwrap_or_else(|| Values::nan_f32(n));
    // The accelerometer of the same chip: same device_id, else the same multi_id.
    let accel_sub = accels
        .iter()
        .find(|(a, _)| device.is_some() && a.first_integer("device_id") == device)
        .or_else(|| accels.iter().find(|(a, _)| a.multi_id == g.multi_id));
    let key = |s: &Sub| -> Option<Sorted> {
        s.integers("timestamp_sample")
            .or_else(|| s.integers("timestamp"))
            .map(|v| Sorted::new(v.into_iter().map(i128::from).collect()))
    };
    let gyro_key: Vec<i128> = sample
        .clone()
        .unwrap_or_else(|| time.clone())
        .into_iter()
        .map(i128::from)
        .collect();
    let step = median_step(&gyro_key).unwrap_or(0);
    let mut accel = None;
    let mut alt_temps = Vec::new();
    if let Some((a, keys)) = accel_sub
        && let Some(akey) = keys.get_or_init(|| key(a))
        && ["x", "y", "z"].iter().all(|f| a.is_float(f, 0))
    {
        let pick = akey.nearest_within(&gyro_key, step / 2);
        accel = axes_at(a, &pick);
        if let Some(t) = a.values_at("temperature", 0, &pick) {
            alt_temps.push(AltTemperature {
                from: TempFrom::Accel,
                field: format!("sensor_accel[{}].temperature", a.multi_id),
                values: t,
            });
        }
    }
    // vehicle_imu_status of this gyro (newer firmware logs its temperatures).
    if let Some((st, keys)) = statuses
        .iter()
        .find(|(s, _)| device.is_some() && s.first_integer("gyro_device_id") == device)
    {
        let field = ["temperature_gyro", "temperature_accel"]
            .into_iter()
            .find(|f| st.is_float(f, 0));
        let skey = keys.get_or_init(|| {
            st.integers("timestamp")
                .map(|v| Sorted::new(v.into_iter().map(i128::from).collect()))
        });
        if let Some(f) = field
            && let Some(skey) = skey
        {
            let gtime: Vec<i128> = time.iter().map(|&t| i128::from(t)).collect();
            let tol = median_step(skey.candidates()).unwrap_or(0).max(step);
            let pick = skey.nearest_within(&gtime, tol);
            if let Some(values) = st.values_at(f, 0, &pick) {
                alt_temps.push(AltTemperature {
                    from: TempFrom::ImuStatus,
                    field: format!("vehicle_imu_status[{}].{f}", st.multi_id),
                    values,
                });
            }
        }
    }
    Ok(GyroInstance {
        index,
        label: g.label(),
        device: device.map(|d| DeviceId::Ulog {
            device_id: d as u32,
        }),
        time: Timestamps::Micros(time),
        time_sample_us: sample,
        log_time_ns: None,
        gyro,
        temp_c,
        accel,
        alt_temps,
    })
}

fn combined_instance(c: &Sub, index: usize) -> Result<GyroInstance, Missing> {
    let n = c.count();
    let time = c.integers("timestamp").ok_or(Missing::Timestamp)?;
    let gyro = axes(c, [("gyro_rad", 0), ("gyro_rad", 1), ("gyro_rad", 2)])?;
    let accel = axes(
        c,
        [
            ("accelerometer_m_s2", 0),
            ("accelerometer_m_s2", 1),
            ("accelerometer_m_s2", 2),
        ],
    )
    .ok();
    Ok(GyroInstance {
        index,
        label: format!(
            "sensor_combined multi_id {} (the primary IMU; no temperature)",
            c.multi_id
        ),
        device: None,
        time: Timestamps::Micros(time),
        time_sample_us: None,
        log_time_ns: None,
        gyro,
        temp_c: Values::nan_f32(n),
        accel,
        alt_temps: Vec::new(),
    })
}
