//! Which gyro a command works on (`--gyro N`) and which temperature it uses (`--temp-from`).
//!
//! By default: the first instance whose own temperature has a finite value, with a note saying
//! which. A temperature that is not the gyro's own (its accelerometer's, PX4's
//! `vehicle_imu_status`) is used only when asked for: it may lag the gyro's die by degrees,
//! so a calibration fitted on it should be a choice, not a fallback. Without one, the choice
//! is refused with the alternatives named.

use super::error::{SelectionError, listed, quoted};
use super::recording::{GyroInstance, ImuRecording, TempFrom, Values};

/// The chosen instance and temperature, with a sentence saying what was chosen.
#[derive(Debug, Clone)]
pub struct Selected<'a> {
    /// The log's source, for messages.
    pub source: &'a str,
    /// The chosen gyro.
    pub instance: &'a GyroInstance,
    /// Where its temperature comes from.
    pub temp_from: TempFrom,
    /// The temperature used, one value per sample.
    pub temp_c: Values,
    /// What was chosen and why (for the user, on standard error or in the workbench).
    pub note: String,
}

/// One instance as plain float64 columns in driftlab's units for these logs (time s, gyro
/// rad/s, temperature °C, accelerometer m/s²).
#[derive(Debug, Clone, PartialEq)]
pub struct Columns {
    /// The format's own time stamp, s.
    pub time_s: Vec<f64>,
    /// Angular rate x, y, z, rad/s.
    pub gyro_rad_s: [Vec<f64>; 3],
    /// The chosen temperature, °C (NaN where absent).
    pub temp_c: Vec<f64>,
    /// Acceleration x, y, z, m/s², when the instance has an accelerometer.
    pub accel_m_s2: Option<[Vec<f64>; 3]>,
}

impl Selected<'_> {
    /// The instance as plain columns.
    pub fn columns(&self) -> Columns {
        let i = self.instance;
        Columns {
            time_s: i.time.all_seconds(),
            gyro_rad_s: i.gyro.xyz.clone().map(|v| v.to_f64()),
            temp_c: self.temp_c.to_f64(),
            accel_m_s2: i.accel.as_ref().map(|a| a.xyz.clone().map(|v| v.to_f64())),
        }
    }
}

/// `gyro N (label, device)`, names quoted to a readable length.
fn describe(i: &GyroInstance) -> String {
    match &i.device {
        Some(d) => format!("gyro {} ({}, {d})", i.index, quoted(&i.label)),
        None => format!("gyro {} ({})", i.index, quoted(&i.label)),
    }
}

fn range(v: &Values) -> String {
    match v.range() {
        Some((a, b)) => format!("{a:.2} .. {b:.2} degC"),
        None => "n/a: no finite value".into(),
    }
}

/// The temperatures that could stand in for `i`'s own, each with its option, as one
/// sentence.
fn alternatives(i: &GyroInstance) -> String {
    let mut alts: Vec<String> = i
        .alt_temps
        .iter()
        .filter(|a| a.values.has_numbers())
        .map(|a| format!("temp_from {} ({}, {})", a.from, a.field, range(&a.values)))
        .collect();
    if i.temp_c.has_numbers() {
        alts.insert(0, format!("temp_from own ({})", range(&i.temp_c)));
    }
    if alts.is_empty() {
        format!("{} has no other temperature", describe(i))
    } else {
        format!("{} could use {}", describe(i), alts.join(" or "))
    }
}

/// The temperatures of the log no gyro takes (a ROS log's Temperature topics off every
/// gyro's frame), and why no setting picks one, as a clause ending in `; `; empty when there
/// are none. Without it a gyro refused for want of a temperature would read as if the log had
/// none.
fn untied(rec: &ImuRecording) -> String {
    let n = rec.untied_temps.len();
    if n == 0 {
        return String::new();
    }
    format!(
        "the log's Temperature topic{} {} {} taken as no gyro's temperature (a ROS gyro's own \
         is the Temperature topic on its frame_id, or a log's only one beside its only Imu \
         topic), and no setting picks one: to use one, cut the log to the gyro's topic and \
         that Temperature topic (e.g. rosbag filter or mcap filter); ",
        if n == 1 { "" } else { "s" },
        listed(rec.untied_temps.iter().cloned(), ", "),
        if n == 1 { "is" } else { "are" }
    )
}

/// What every gyro could use instead, the first few named (a log of 20 000 topics gives
/// one readable line).
fn every_alternative(rec: &ImuRecording) -> String {
    format!(
        "{}; {}temp_from none writes temp_c as NaN (enough for noise analysis, not for a \
         thermal calibration)",
        listed(rec.instances.iter().map(alternatives), "; "),
        untied(rec)
    )
}

/// The values of `from` for `i`, when the log has them with at least one number.
fn temperature(i: &GyroInstance, from: TempFrom) -> Option<(Values, String)> {
    match from {
        TempFrom::Own => i
            .temp_c
            .has_numbers()
            .then(|| (i.temp_c.clone(), "its own temperature".to_string())),
        TempFrom::None => Some((
            Values::F64(vec![f64::NAN; i.len()]),
            "no temperature (temp_c is NaN)".to_string(),
        )),
        other => i
            .alt_temp(other)
            .filter(|a| a.values.has_numbers())
            .map(|a| (a.values.clone(), format!("the temperature of {}", a.field))),
    }
}

/// Picks the gyro (`gyro`, default: the first with a temperature of `temp_from`'s kind) and
/// its temperature (`temp_from`, default: its own).
///
/// # Errors
/// `gyro` past the last instance; no temperature of the asked kind for the gyro (or for any
/// gyro when none was named), with the alternatives named.
pub fn select(
    rec: &ImuRecording,
    gyro: Option<usize>,
    temp_from: Option<TempFrom>,
) -> Result<Selected<'_>, SelectionError> {
    let from = temp_from.unwrap_or(TempFrom::Own);
    let listing = || listed(rec.instances.iter().map(describe), ", ");
    let found = |i: &GyroInstance| temperature(i, from);
    let (inst, (temp_c, what), how) = match gyro {
        Some(n) => {
            let inst = rec
                .instances
                .get(n)
                .ok_or_else(|| SelectionError::NoSuchInstance {
                    source_name: rec.source.clone(),
                    asked: n,
                    count: rec.instances.len(),
                    listing: listing(),
                })?;
            let t = found(inst).ok_or_else(|| SelectionError::NoTemperature {
                source_name: rec.source.clone(),
                what: match from {
                    TempFrom::Own => format!("{} has no temperature of its own", describe(inst)),
                    f => format!("{} has no {f} temperature", describe(inst)),
                },
                alternatives: format!(
                    "{}; {}temp_from none writes temp_c as NaN",
                    alternatives(inst),
                    if from == TempFrom::Own {
                        untied(rec)
                    } else {
                        String::new()
                    }
                ),
            })?;
            (inst, t, "as asked".to_string())
        }
        None => {
            let hit = rec.instances.iter().find_map(|i| found(i).map(|t| (i, t)));
            let (inst, t) = hit.ok_or_else(|| SelectionError::NoTemperature {
                source_name: rec.source.clone(),
                what: match from {
                    TempFrom::Own => "no gyro in the log has a temperature of its own".into(),
                    f => {
                        let f = f.to_string();
                        format!("no gyro in the log has {} {f} temperature", article(&f))
                    }
                },
                alternatives: every_alternative(rec),
            })?;
            let how = if rec.instances.len() == 1 {
                "the log's only gyro".to_string()
            } else if from == TempFrom::None {
                format!("the first of {}; gyro N picks another", rec.instances.len())
            } else if from == TempFrom::Own {
                format!(
                    "the first of {} with a finite temperature; gyro N picks another",
                    rec.instances.len()
                )
            } else {
                format!(
                    "the first of {} with {} {from} temperature; gyro N picks another",
                    rec.instances.len(),
                    article(&from.to_string())
                )
            };
            (inst, t, how)
        }
    };
    let mut note = format!(
        "{}: {} chosen ({how}), with {what}",
        rec.source,
        describe(inst)
    );
    if from != TempFrom::Own && from != TempFrom::None {
        note.push_str(": not the gyro's own sensor, so it may lag the gyro's temperature");
    }
    Ok(Selected {
        source: &rec.source,
        instance: inst,
        temp_from: from,
        temp_c,
        note,
    })
}

/// The article before `word`: "an" before a vowel ("an accel temperature"), else "a".
fn article(word: &str) -> &'static str {
    if word.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    }
}
