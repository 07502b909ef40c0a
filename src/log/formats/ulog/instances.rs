//! Turns the subscriptions of a read ULog into gyro instances: each `sensor_gyro` with the
//! accelerometer of the same device and the `vehicle_imu_status` temperatures matched to its
//! samples, then the fused `sensor_combined`. Apart from the reading because it decides what a
//! log offers, not whether its bytes are sound.

use super::subscription::Sub;
use crate::log::formats::recording::{
    AltTemperature, Axes, DeviceId, GyroInstance, Problem, TempFrom, Timestamps, Values,
    median_step, nearest_within,
};

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

/// Turns the subscriptions into gyro instances.
pub(super) fn assemble(subs: Vec<Sub>, problems: &mut Vec<Problem>) -> Vec<GyroInstance> {
    let mut gyros: Vec<&Sub> = subs.iter().filter(|s| s.topic == "sensor_gyro").collect();
    gyros.sort_by_key(|s| s.multi_id);
    let accels: Vec<&Sub> = subs.iter().filter(|s| s.topic == "sensor_accel").collect();
    let statuses: Vec<&Sub> = subs
        .iter()
        .filter(|s| s.topic == "vehicle_imu_status")
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

fn gyro_instance(
    g: &Sub,
    accels: &[&Sub],
    statuses: &[&Sub],
    index: usize,
) -> Result<GyroInstance, Missing> {
    let n = g.count();
    let time = g.integers("timestamp").ok_or(Missing::Timestamp)?;
    let sample = g.integers("timestamp_sample");
    let device = g.integers("device_id").and_then(|v| v.first().copied());
    let gyro = axes(g, [("x", 0), ("y", 0), ("z", 0)])?;
    let temp_c = g
        .values("temperature", 0)
        .unwrap_or_else(|| Values::nan_f32(n));
    // The accelerometer of the same chip: same device_id, else the same multi_id.
    let accel_sub = accels
        .iter()
        .find(|a| {
            device.is_some() && a.integers("device_id").and_then(|v| v.first().copied()) == device
        })
        .or_else(|| accels.iter().find(|a| a.multi_id == g.multi_id));
    let key = |s: &Sub| -> Option<Vec<i128>> {
        s.integers("timestamp_sample")
            .or_else(|| s.integers("timestamp"))
            .map(|v| v.into_iter().map(i128::from).collect())
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
    if let Some(a) = accel_sub
        && let Some(akey) = key(a)
        && let Ok(ax) = axes(a, [("x", 0), ("y", 0), ("z", 0)])
    {
        let pick = nearest_within(&gyro_key, &akey, step / 2);
        accel = Some(Axes {
            xyz: ax.xyz.map(|v| pick_values(&v, &pick)),
        });
        if let Some(t) = a.values("temperature", 0) {
            alt_temps.push(AltTemperature {
                from: TempFrom::Accel,
                field: format!("sensor_accel[{}].temperature", a.multi_id),
                values: pick_values(&t, &pick),
            });
        }
    }
    // vehicle_imu_status of this gyro (newer firmware logs its temperatures).
    if let Some(st) = statuses.iter().find(|s| {
        device.is_some()
            && s.integers("gyro_device_id")
                .and_then(|v| v.first().copied())
                == device
    }) {
        let field = ["temperature_gyro", "temperature_accel"]
            .into_iter()
            .find_map(|f| st.values(f, 0).map(|v| (f, v)));
        if let Some((f, v)) = field
            && let Some(skey) = st.integers("timestamp")
        {
            let skey: Vec<i128> = skey.into_iter().map(i128::from).collect();
            let gtime: Vec<i128> = time.iter().map(|&t| i128::from(t)).collect();
            let tol = median_step(&skey).unwrap_or(0).max(step);
            let pick = nearest_within(&gtime, &skey, tol);
            alt_temps.push(AltTemperature {
                from: TempFrom::ImuStatus,
                field: format!("vehicle_imu_status[{}].{f}", st.multi_id),
                values: pick_values(&v, &pick),
            });
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

/// The values at `pick` (NaN where nothing was near).
fn pick_values(v: &Values, pick: &[Option<usize>]) -> Values {
    match v {
        Values::F32(x) => Values::F32(pick.iter().map(|p| p.map_or(f32::NAN, |i| x[i])).collect()),
        Values::F64(x) => Values::F64(pick.iter().map(|p| p.map_or(f64::NAN, |i| x[i])).collect()),
    }
}
