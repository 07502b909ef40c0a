//! Turns the subscriptions of a read ULog into gyro instances: each `sensor_gyro` with the
//! accelerometer of the same device and the `vehicle_imu_status` temperatures matched to its
//! samples, then the fused `sensor_combined`. Apart from the reading because it decides what a
//! log offers, not whether its bytes are sound.

use super::subscription::Sub;
use crate::log::formats::device_change;
use crate::log::formats::error::{LIST_AT_MOST, listed};
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

/// An accelerometer's stamps in order, sorted once for every gyro matched against them, with
/// the messages left out because its clock stepped back (how many, and the first's index).
type AccelKeys = OnceCell<Option<(Sorted, Option<(usize, usize)>)>>;

/// Stamps that never come within a gyro's tolerance of a real one: a message left out.
const NEVER: i128 = i128::MIN / 4;

/// The stamps of a stream as they may be matched. A stream whose clock steps back (a message
/// stamped at or before the one before it) is in runs on different clocks, and a stamp of one
/// run says nothing of when the other runs' messages were read: the longest run in order is
/// kept (the first of the longest), and every other message left out (its stamp made
/// [`NEVER`]), as the time-order rules do a log's own rows; a stream written newest first is
/// in order the other way. With how many were left out and the index of the first step back.
fn in_order(stamps: Vec<i128>) -> (Vec<i128>, Option<(usize, usize)>) {
    let n = stamps.len();
    // A log written newest first steps back at every message: its order is the other way, and
    // a break is then a step forward.
    let back = (1..n).filter(|&i| stamps[i] < stamps[i - 1]).count();
    let newest_first = 2 * back > n.saturating_sub(1);
    let breaks = |i: usize| {
        if newest_first {
            stamps[i] >= stamps[i - 1]
        } else {
            stamps[i] <= stamps[i - 1]
        }
    };
    let steps: Vec<usize> = (1..n).filter(|&i| breaks(i)).collect();
    let Some(&first) = steps.first() else {
        return (stamps, None);
    };
    let bounds: Vec<usize> = std::iter::once(0)
        .chain(steps.iter().copied())
        .chain(std::iter::once(n))
        .collect();
    let (keep_from, keep_to) = bounds
        .windows(2)
        .map(|w| (w[0], w[1]))
        .fold((0, 0), |best, run| {
            if run.1 - run.0 > best.1 - best.0 {
                run
            } else {
                best
            }
        });
    let out = stamps
        .into_iter()
        .enumerate()
        .map(|(i, t)| {
            if (keep_from..keep_to).contains(&i) {
                t
            } else {
                NEVER
            }
        })
        .collect();
    (out, Some((n - (keep_to - keep_from), first)))
}

/// Turns the subscriptions into gyro instances.
pub(super) fn assemble(subs: Vec<Sub>, problems: &mut Vec<Problem>) -> Vec<GyroInstance> {
    let mut gyros: Vec<&Sub> = subs.iter().filter(|s| s.topic == "sensor_gyro").collect();
    gyros.sort_by_key(|s| s.multi_id);
    let accels: Vec<(&Sub, AccelKeys)> = subs
        .iter()
        .filter(|s| s.topic == "sensor_accel")
        .map(|s| (s, AccelKeys::new()))
        .collect();
    let statuses: Vec<(&Sub, Keys)> = subs
        .iter()
        .filter(|s| s.topic == "vehicle_imu_status")
        .map(|s| (s, Keys::new()))
        .collect();
    let mut out = Vec::new();
    for g in gyros {
        for (part, label) in by_device(g, problems) {
            let part = part.as_ref().unwrap_or(g);
            match gyro_instance(part, label.clone(), &accels, &statuses, out.len()) {
                Ok(inst) => out.push(inst),
                Err(m) => problems.push(Problem::note(format!("{label}: {m}; left out"))),
            }
        }
    }
    // An accelerometer whose clock stepped back: its messages out of order were matched to no
    // gyro sample (said once, whichever gyros it served).
    for (a, keys) in &accels {
        if let Some(Some((_, Some((left, first))))) = keys.get() {
            problems.push(Problem::note(format!(
                "sensor_accel[{}]: its clock steps back (first at message {}); the {left} \
                 message{} outside its longest run in order left out: their readings are \
                 matched to no gyro sample, whose accelerometer there is NaN",
                a.multi_id,
                first + 1,
                if *left == 1 { "" } else { "s" },
            )));
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

/// A `device_id` as a message names it: decimal, then hexadecimal (bus, address and driver
/// packed), as [`DeviceId`] shows it.
fn device_name(d: u64) -> String {
    let d = d as u32;
    format!("{d} (0x{d:X})")
}

/// The gyros of subscription `g`, each with its label: the subscription itself (`None`) when
/// its `device_id` never changes; else each device's samples as a subscription of their own
/// ([`device_change::parts`]), told in `problems` with the sample where it first changes. A
/// `device_id` that changes is another chip (swapped, or re-enumerated on the bus): its samples
/// have another bias and drift, and filed under the first chip's id they would be calibrated
/// as one gyro.
fn by_device(g: &Sub, problems: &mut Vec<Problem>) -> Vec<(Option<Sub>, String)> {
    let whole = || vec![(None, g.label())];
    let Some(ids) = g.integers("device_id") else {
        return whole();
    };
    let (parts, left_out) = device_change::parts(&ids);
    if parts.len() < 2 {
        return whole();
    }
    let n = parts.len();
    let label = |k: usize| format!("{} device {} of {n}", g.label(), k + 1);
    let at = ids.iter().position(|&d| d != ids[0]).unwrap_or(0);
    let time_s = g
        .integers("timestamp")
        .and_then(|t| t.get(at).copied())
        .map_or(f64::NAN, |t| t as f64 / 1e6);
    let each = parts.iter().enumerate().map(|(k, p)| {
        let n = p.rows.len();
        let s = if n == 1 { "" } else { "s" };
        format!(
            "{} (device_id {}, {n} sample{s})",
            label(k),
            device_name(p.device)
        )
    });
    let mut message = format!(
        "{}; each device's samples are a gyro of their own, never one calibration over two \
         chips: {}",
        device_change::changes(
            &g.label(),
            "device_id",
            (&device_name(ids[0]), &device_name(ids[at])),
            "subscription",
            at + 1,
            time_s
        ),
        listed(each, ", ")
    );
    if left_out > 0 {
        message.push_str(&format!(
            "; {left_out} samples of further devices left out (a gyro of each of the first \
             {LIST_AT_MOST} only)"
        ));
    }
    problems.push(Problem::note(message));
    parts
        .iter()
        .enumerate()
        .map(|(k, p)| (Some(g.with_rows(&p.rows)), label(k)))
        .collect()
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
    label: String,
    accels: &[(&Sub, AccelKeys)],
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
    let key = |s: &Sub| -> Option<(Sorted, Option<(usize, usize)>)> {
        s.integers("timestamp_sample")
            .or_else(|| s.integers("timestamp"))
            .map(|v| {
                let (stamps, left) = in_order(v.into_iter().map(i128::from).collect());
                (Sorted::new(stamps), left)
            })
    };
    let gyro_key: Vec<i128> = sample
        .clone()
        .unwrap_or_else(|| time.clone())
        .into_iter()
        .map(i128::from)
        .collect();
    let step = median_step(&gyro_key).unwrap_or(0);
    let mut accel = None;
    let mut accel_device_id = None;
    let mut alt_temps = Vec::new();
    if let Some((a, keys)) = accel_sub
        && let Some((akey, _)) = keys.get_or_init(|| key(a))
        && ["x", "y", "z"].iter().all(|f| a.is_float(f, 0))
    {
        let pick = akey.nearest_within(&gyro_key, step / 2);
        accel = axes_at(a, &pick);
        accel_device_id = accel
            .as_ref()
            .and(a.first_integer("device_id"))
            .map(|d| d as u32);
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
        label,
        device: device.map(|d| DeviceId::Ulog {
            device_id: d as u32,
        }),
        time: Timestamps::Micros(time),
        time_sample_us: sample,
        log_time_ns: None,
        gyro,
        temp_c,
        accel,
        accel_device_id,
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
        accel_device_id: None,
        alt_temps: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::{NEVER, in_order};

    #[test]
    fn a_stream_whose_clock_steps_back_keeps_its_messages_in_order_only() {
        // Two runs on two clocks: the longer kept, whichever comes first.
        let (stamps, left) = in_order(vec![10, 20, 30, 5, 15, 25, 35, 40]);
        assert_eq!(stamps, [NEVER, NEVER, NEVER, 5, 15, 25, 35, 40]);
        assert_eq!(left, Some((3, 3)));
        let (stamps, left) = in_order(vec![10, 20, 30, 40, 5, 15, 25]);
        assert_eq!(stamps, [10, 20, 30, 40, NEVER, NEVER, NEVER]);
        assert_eq!(left, Some((3, 4)));
        let (stamps, left) = in_order(vec![1, 2, 3]);
        assert_eq!(stamps, [1, 2, 3]);
        assert_eq!(left, None);
        // Written newest first: in order the other way.
        let (stamps, left) = in_order(vec![3, 2, 1]);
        assert_eq!(stamps, [3, 2, 1]);
        assert_eq!(left, None);
    }
}
