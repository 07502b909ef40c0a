//! The checks an accelerometer's readings get once they are axes: a stretch of readings no
//! accelerometer gives (dropped while they are glitches, else kept and told), readings missing
//! from a column, and a mean vector no IMU in gravity reads (a unit off by ten or a thousand).
//! Apart from [`super::take`], which makes the axes, because each is a rule of its own with its
//! own bounds and words.

use super::*;

/// The lengths, in g, the mean vector of accelerometers in their units may have: wide enough
/// for a unit handled or shaken while logging (a real robot's IMU reads 0.63 g on average),
/// narrow enough to catch a unit off by the factor of ten between g and m/s², or of a
/// thousand between g and mg.
const GRAVITY_BOUNDS: (f64, f64) = (0.5, 1.5);

/// Refuses accelerometers whose units make them no IMU in gravity: the mean vector of the
/// columns, in m/s², longer than gravity allows (a part of the three axes reads at most 1 g),
/// or, for three axes or more, much shorter (a mislabelled column, g read as m/s², or m/s² as
/// g, would give every coefficient ten times too large or too small). The channels `kept`
/// hold a stretch of readings no accelerometer gives ([`unread_glitches`]), told already and
/// refused by every fit: their means leave those out, so that 10³⁸ is not blamed on a unit.
pub(super) fn check_gravity(
    log: &Log,
    picked: &[usize],
    units: &[Option<AccelUnit>],
    kept: &[usize],
) -> Result<(), AccelError> {
    use crate::log::impossible::MAX_PLAUSIBLE_ACCEL_M_S2;
    let squares: f64 = picked
        .iter()
        .zip(units)
        .map(|(&k, u)| {
            let factor = u.unwrap_or_default().to_m_s2();
            let values = &log.extra[k].values;
            let mean = if kept.contains(&k) {
                mean_within(values, MAX_PLAUSIBLE_ACCEL_M_S2 / factor)
            } else {
                finite_mean(values)
            };
            mean * factor
        })
        .map(|m| m * m)
        .sum();
    let magnitude_m_s2 = squares.sqrt();
    let ratio = magnitude_m_s2 / STANDARD_GRAVITY_M_S2;
    let too_long = ratio > GRAVITY_BOUNDS.1;
    let too_short = picked.len() >= 3 && ratio < GRAVITY_BOUNDS.0;
    if too_long || too_short || !ratio.is_finite() {
        return Err(AccelError::NotGravity {
            log: log.source.clone(),
            columns: picked
                .iter()
                .zip(units)
                .map(|(&k, u)| format!("{} in {}", log.extra[k].name, u.unwrap_or_default()))
                .collect(),
            magnitude_m_s2,
        });
    }
    Ok(())
}

/// Makes NaN the readings of the accelerometer channels `picked` (in `units`) that no
/// accelerometer gives ([`crate::log::impossible`]) while they are glitches, each channel's
/// told as a problem of the log: an accelerometer axis keeps its samples where its gyro has
/// them, and its fits and means pass over NaN. More of them than glitches are kept and told
/// (every fit refuses the axis, [`crate::models::check_axis_readings`]); the channels holding
/// such a stretch are returned. Most of a channel beyond is its unit's doing, which
/// [`check_gravity`] tells.
pub(super) fn unread_glitches(
    log: &mut Log,
    picked: &[usize],
    units: &[Option<AccelUnit>],
) -> Vec<usize> {
    use crate::log::impossible::{ACCEL_LIMIT_WORDS, MAX_PLAUSIBLE_ACCEL_M_S2, Verdict, beyond};
    let mut kept = Vec::new();
    for &k in picked {
        missing_readings(log, k);
    }
    for (&k, u) in picked.iter().zip(units) {
        let bound = MAX_PLAUSIBLE_ACCEL_M_S2 / u.unwrap_or_default().to_m_s2();
        let column = column_number(log, &log.extra[k].name);
        let c = &mut log.extra[k];
        let Some(b) = beyond(c.values.iter().copied(), bound) else {
            continue;
        };
        let first = b.samples[0] + 1;
        let message = match b.verdict() {
            Verdict::Glitches => {
                for &i in &b.samples {
                    c.values[i] = f64::NAN;
                }
                b.message(
                    &c.name,
                    ACCEL_LIMIT_WORDS,
                    &format!("sample {first}"),
                    "accelerometer",
                    false,
                )
            }
            Verdict::TooMany => {
                kept.push(k);
                b.too_many_message(
                    &c.name,
                    ACCEL_LIMIT_WORDS,
                    (
                        &format!("sample {first}"),
                        &format!("sample {}", b.samples[b.samples.len() - 1] + 1),
                    ),
                    "accelerometer",
                )
            }
            Verdict::Column => continue,
        };
        log.info.problems.push(crate::log::Problem {
            line: 0,
            column,
            kind: ProblemKind::Implausible,
            count: b.samples.len(),
            message,
        });
    }
    kept
}

/// Tells the samples of the accelerometer channel `k` of `log` that hold no reading (a blank,
/// NaN or unreadable cell: an accelerometer logged at a lower rate than its gyro, or not at
/// all for a while): none of them is a sample of its fit or figures, and the engineer hears
/// how many, their share and the first.
pub(super) fn missing_readings(log: &mut Log, k: usize) {
    let c = &log.extra[k];
    let n = c.values.len();
    let Some(first) = c.values.iter().position(|v| v.is_nan()) else {
        return;
    };
    let count = c.values.iter().filter(|v| v.is_nan()).count();
    let message = format!(
        "{count} reading{} of \"{}\" blank, NaN or unreadable ({} % of its {n} samples, the \
         first at sample {}): no sample of that axis there; its fit and figures take the {} \
         others",
        if count == 1 { "" } else { "s" },
        crate::text::escaped(&c.name, false),
        crate::log::impossible::share_percent(count, n),
        first + 1,
        n - count
    );
    let column = column_number(log, &c.name);
    log.info.problems.push(crate::log::Problem {
        line: 0,
        column,
        kind: ProblemKind::MissingValue,
        count,
        message,
    });
}

/// The 1-based number of the column named `name` in the file, for a problem about it.
pub(super) fn column_number(log: &Log, name: &str) -> Option<usize> {
    log.info
        .columns
        .iter()
        .find(|ci| ci.name == name)
        .map(|ci| ci.index)
}

/// The mean of the values within `bound` in magnitude (0 when there are none).
pub(crate) fn mean_within(values: &[f64], bound: f64) -> f64 {
    let (sum, n) = values
        .iter()
        .filter(|v| v.abs() <= bound)
        .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// The mean of the finite values (0 when there are none).
pub(crate) fn finite_mean(values: &[f64]) -> f64 {
    let (sum, n) = values
        .iter()
        .filter(|v| v.is_finite())
        .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if n == 0 { 0.0 } else { sum / n as f64 }
}
