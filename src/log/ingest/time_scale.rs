//! Whether the time column, in the unit it was read in, counts a gyro log's time. Its step must
//! be no shorter than the shortest sampling interval driftlab takes anywhere (a gigahertz's,
//! the bound of `sample_rate_hz` and of the Allan τ0), and its span a number driftlab can hold:
//! a step of 1e-300 s or a span past the largest double is refused, naming the column and the
//! line. A span longer than any chamber run ([`MAX_WINDOW_S`], the bound of every window) or a
//! step longer than a day is read, and told with the unit the numbers fit: a time in ms read as
//! s makes an 11-hour run 465 days long and every temperature ramp 1000 times slower, and
//! without a word the first thing said would be a fit's false reason ("the temperature never
//! changes faster than 0.001 °C/min").
//!
//! The unit is not inferred from the numbers: the same steps of 1000 and span of 4e7 fit ms
//! (steps of 1 s over 11 h) and µs (steps of 1 ms over 40 s) alike, so the reader names the unit
//! that changes the least and asks for it.

use super::Fail;
use super::columns::UnitFrom;
use super::units::TimeUnit;
use crate::judge::allan::{MAX_TAU0_S, MIN_TAU0_S};
use crate::log::temp_rate::FASTEST_SUSTAINED_C_PER_S;
use crate::log::{Problem, ProblemKind};
use crate::models::recipe::MAX_WINDOW_S;

/// The longest span, s, of a time in a unit its name or a setting states that is not told: a
/// year (a time in ms under `time_s` makes an 11-hour run 465 days long). Longer, the reader
/// says the log is "longer than any chamber run", and a calibration's record of a campaign's
/// run refuses such a span ([`crate::models::campaign::validate_runs`]).
pub const STATED_UNIT_LONGEST_S: f64 = 365.25 * 86_400.0;

/// The time column as it was read, for the messages.
pub(super) struct TimeColumn<'a> {
    pub(super) name: &'a str,
    /// 1-based index in the file.
    pub(super) index: usize,
    pub(super) unit: TimeUnit,
    pub(super) from: UnitFrom,
}

impl TimeColumn<'_> {
    /// `the time column "time", read in s (the default: its name states no unit)`.
    fn read_as(&self) -> String {
        let how = match self.from {
            UnitFrom::Setting => "as time_unit says",
            UnitFrom::Name => "as its name says",
            UnitFrom::Default => "the default: its name states no unit",
        };
        format!(
            "the time column \"{}\", read in {} ({how})",
            self.name, self.unit
        )
    }
}

/// The refusal of a time column whose stamps `time_s` (in s, increasing, as kept) cannot be a
/// log's time: a span past the largest number, or a nominal step `step_s` shorter than
/// [`MIN_TAU0_S`]. `line_of` gives the file line of a kept sample.
pub(super) fn unreadable(
    col: &TimeColumn,
    time_s: &[f64],
    step_s: f64,
    line_of: impl Fn(usize) -> usize,
) -> Option<Fail> {
    let n = time_s.len();
    if n < 2 {
        return None;
    }
    let r = crate::number::readable;
    let first = time_s[0];
    if !(time_s[n - 1] - first).is_finite() {
        let k = time_s
            .iter()
            .position(|t| !(t - first).is_finite())
            .unwrap_or(n - 1);
        return Some(Fail::new(
            line_of(k),
            col.index,
            format!(
                "{}, goes from {} s at line {} to {} s at line {}: a span past the largest \
                 number driftlab holds, which no log lasts; check the time column's unit \
                 (time_unit) or choose another column (time_col)",
                col.read_as(),
                r(first),
                line_of(0),
                r(time_s[k]),
                line_of(k)
            ),
        ));
    }
    // Within the rounding of a mean step of stamps written at exactly a gigahertz.
    if step_s >= MIN_TAU0_S * (1.0 - 1e-6) {
        return None;
    }
    let span = time_s[n - 1] - first;
    let fit = match fitting_unit(col.unit, step_s, span) {
        Some((u, step, span)) => format!(
            "the numbers fit {u} (steps of {} over {}): if its values are in {u}, give \
             time_unit {u}",
            lasting(step),
            lasting(span)
        ),
        None => "check the time column's unit (time_unit) or choose another column (time_col)"
            .to_string(),
    };
    Some(Fail::new(
        line_of(1),
        col.index,
        format!(
            "{}, steps by {} s (lines {} to {}): shorter than the {} s of the fastest \
             sampling driftlab reads (a gigahertz, as for sample_rate_hz); {fit}",
            col.read_as(),
            r(step_s),
            line_of(0),
            line_of(n - 1),
            r(MIN_TAU0_S)
        ),
    ))
}

/// The problem of a time column whose stamps `time_s` (in s, increasing, as kept, every step at
/// least [`MIN_TAU0_S`] and the span finite) span longer than any chamber run or step by more
/// than a day, with the unit the numbers fit. `None` for a time that counts samples: its step
/// is the one the sample rate gives.
pub(super) fn implausible(col: &TimeColumn, time_s: &[f64], step_s: f64) -> Option<Problem> {
    let n = time_s.len();
    if n < 2 || col.unit == TimeUnit::Samples {
        return None;
    }
    let span = time_s[n - 1] - time_s[0];
    // A long run in a unit the name or a setting states is real (a static Allan run of two
    // weeks at a minute a sample): only a span past a year tells of a wrong unit there, while
    // a time whose unit was taken by default is told past any chamber run.
    let longest = match col.from {
        UnitFrom::Default => MAX_WINDOW_S,
        UnitFrom::Name | UnitFrom::Setting => STATED_UNIT_LONGEST_S,
    };
    let (long_span, long_step) = (span > longest, step_s > MAX_TAU0_S);
    let what = match (long_span, long_step) {
        (false, false) => return None,
        (true, false) => format!("longer than any chamber run ({} at most)", lasting(longest)),
        (false, true) => "a step longer than a day, slower than any gyro is sampled".to_string(),
        (true, true) => format!(
            "longer than any chamber run ({} at most), at a step longer than a day, slower \
             than any gyro is sampled",
            lasting(longest)
        ),
    };
    let advice = match fitting_unit(col.unit, step_s, span) {
        Some((u, step, run)) => format!(
            "the steps of {} and the span of {} fit {} (steps of {} over {}): if its values are \
             in {u}, give time_unit {u}",
            lasting(step_s),
            lasting(span),
            spelt(u),
            lasting(step),
            lasting(run)
        ),
        None => "check the time column's unit (time_unit)".to_string(),
    };
    Some(Problem {
        line: 0,
        column: Some(col.index),
        kind: ProblemKind::Implausible,
        count: 1,
        message: format!(
            "{}, spans {} at steps of {}: {what}; {advice}",
            col.read_as(),
            lasting(span),
            lasting(step_s)
        ),
    })
}

/// What the user is to check of a log whose temperature moves faster than any chamber moves a
/// gyro's, at up to `fastest_c_per_s` (`col` the time column as read, `None` when the sample
/// rate gives the time; `time_s` its stamps as kept, at a nominal step of `step_s`). A time
/// column whose unit was taken by default is named with the unit in which its numbers make the
/// rate a chamber's and the log a chamber run (a chamber controller's minutes read as
/// seconds); else the unit as stated, the rows' order and the temperature column are to be
/// checked. The unit is not taken: rows out of order give the same rates.
pub(super) fn fast_temperature_advice(
    col: Option<&TimeColumn>,
    time_s: &[f64],
    step_s: f64,
    fastest_c_per_s: f64,
) -> String {
    let rest = "the rows' order and that the temperature column is the gyro's, temp_col";
    let Some(col) = col.filter(|c| c.unit != TimeUnit::Samples) else {
        return format!("check the sample rate (sample_rate_hz), {rest}");
    };
    let span = match (time_s.first(), time_s.last()) {
        (Some(a), Some(b)) => b - a,
        _ => 0.0,
    };
    let slower = (col.from == UnitFrom::Default)
        .then(|| slower_unit(col.unit, fastest_c_per_s, step_s, span))
        .flatten();
    match slower {
        Some((u, k)) => {
            let units = spelt(u);
            format!(
                "{}, may count {units}: in {units} the run lasts {} at steps of {} and the \
             temperature moves at up to {} °C/min; if so, give time_unit {u} (else check \
             {rest})",
                col.read_as(),
                lasting(span * k),
                lasting(step_s * k),
                crate::number::significant(60.0 * fastest_c_per_s / k, 3),
            )
        }
        None => format!("{}: check its unit (time_unit), {rest}", col.read_as()),
    }
}

/// The unit slower than `read` (its factor to `read`, above 1) nearest it in which a
/// temperature moving at up to `fastest_c_per_s` moves as a chamber moves a gyro's
/// ([`FASTEST_SUSTAINED_C_PER_S`]) and the step of `step_s` and span of `span_s` make a chamber
/// run, as [`fitting_unit`] judges them.
fn slower_unit(
    read: TimeUnit,
    fastest_c_per_s: f64,
    step_s: f64,
    span_s: f64,
) -> Option<(TimeUnit, f64)> {
    let per_read = read.to_s_factor()?;
    [
        TimeUnit::Centis,
        TimeUnit::Decis,
        TimeUnit::Seconds,
        TimeUnit::Minutes,
        TimeUnit::Hours,
        TimeUnit::Days,
    ]
    .into_iter()
    .filter_map(|u| Some((u, u.to_s_factor()? / per_read)))
    .filter(|&(_, k)| {
        k > 1.0
            && fastest_c_per_s / k <= FASTEST_SUSTAINED_C_PER_S
            && (MIN_TAU0_S..=MAX_TAU0_S).contains(&(step_s * k))
            && span_s * k <= MAX_WINDOW_S
    })
    .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The unit, other than `read`, in which the numbers read as a step of `step_s` and a span of
/// `span_s` make a chamber run (a step within [`MIN_TAU0_S`] … [`MAX_TAU0_S`], a span within
/// [`MAX_WINDOW_S`]), the one nearest `read`; with the step and span, s, it gives.
fn fitting_unit(read: TimeUnit, step_s: f64, span_s: f64) -> Option<(TimeUnit, f64, f64)> {
    let per_read = read.to_s_factor()?;
    [
        TimeUnit::Hours,
        TimeUnit::Minutes,
        TimeUnit::Seconds,
        TimeUnit::Millis,
        TimeUnit::Micros,
        TimeUnit::Nanos,
    ]
    .into_iter()
    .filter(|&u| u != read)
    .filter_map(|u| {
        let k = u.to_s_factor()? / per_read;
        let (step, span) = (step_s * k, span_s * k);
        ((MIN_TAU0_S..=MAX_TAU0_S).contains(&step) && span <= MAX_WINDOW_S)
            .then_some((u, k, step, span))
    })
    .min_by(|a, b| a.1.ln().abs().total_cmp(&b.1.ln().abs()))
    .map(|(u, _, step, span)| (u, step, span))
}

/// A time unit in words, for a sentence: `milliseconds`.
fn spelt(u: TimeUnit) -> &'static str {
    match u {
        TimeUnit::Seconds => "seconds",
        TimeUnit::Millis => "milliseconds",
        TimeUnit::Micros => "microseconds",
        TimeUnit::Nanos => "nanoseconds",
        TimeUnit::Minutes => "minutes",
        TimeUnit::Hours => "hours",
        TimeUnit::Days => "days",
        TimeUnit::Centis => "centiseconds",
        TimeUnit::Decis => "deciseconds",
        TimeUnit::Samples => "samples",
    }
}

/// A length of time for a person, three significant digits: `1000 s`, `11.2 h`, `465 days`,
/// `1.27e6 years`.
fn lasting(s: f64) -> String {
    const DAY: f64 = 86_400.0;
    const YEAR: f64 = 365.25 * DAY;
    let r = |v: f64| {
        if v >= 1e4 {
            format!("{v:.2e}")
        } else {
            crate::number::significant(v, 3)
        }
    };
    if s >= 2.0 * YEAR {
        format!("{} years", r(s / YEAR))
    } else if s >= 2.0 * DAY {
        format!("{} days", r(s / DAY))
    } else if s >= 2.0 * 3600.0 {
        format!("{} h", r(s / 3600.0))
    } else {
        format!("{} s", r(s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mildest_unit_that_makes_a_chamber_run_is_named() {
        // An 11-hour run at 1 s in ms read as s: ms (µs would fit too, farther away).
        let (u, step, span) = fitting_unit(TimeUnit::Seconds, 1000.0, 4.02e7).unwrap();
        assert_eq!(u, TimeUnit::Millis);
        assert!((step - 1.0).abs() < 1e-12 && (span - 4.02e4).abs() < 1e-6);
        // The same in ns.
        let (u, _, _) = fitting_unit(TimeUnit::Seconds, 1e9, 4.02e13).unwrap();
        assert_eq!(u, TimeUnit::Nanos);
        // Nothing makes 1e-300 s a step.
        assert_eq!(fitting_unit(TimeUnit::Seconds, 1e-300, 2e-297), None);
        assert_eq!(lasting(4.02e7), "465 days");
        assert_eq!(lasting(1000.0), "1000 s");
        assert_eq!(lasting(4.02e4), "11.2 h");
        assert_eq!(lasting(4.02e13), "1.27e6 years");
    }

    #[test]
    fn minutes_read_as_seconds_are_named_by_the_rate_they_make() {
        // An 11-hour run at 1 s with its time in minutes read as s: 1 °C/min ramps at 1 °C/s.
        let (step, span) = (1.0 / 60.0, 40_200.0 / 60.0);
        assert_eq!(
            slower_unit(TimeUnit::Seconds, 1.0, step, span),
            Some((TimeUnit::Minutes, 60.0))
        );
        // 60 °C/s is a chamber's in hours only, but 670 h is no chamber run.
        assert_eq!(slower_unit(TimeUnit::Seconds, 60.0, step, span), None);
        // A 1-Hz log read so spans 28 days in minutes: no unit makes it a run.
        assert_eq!(slower_unit(TimeUnit::Seconds, 1.0, 1.0, 40_200.0), None);
    }
}
