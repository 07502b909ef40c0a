//! Axes and scales shared by the figures: data ranges with margins and legend headroom, tick
//! labels for linear and logarithmic axes, the time axis's unit. Apart because every figure
//! uses them and they are pure functions, tested without drawing.

use super::DrawError;

/// A finite, non-empty range around `[lo, hi]` with a margin; `[-1, 1]` when nothing is known.
pub(super) fn padded(lo: f64, hi: f64, frac: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) || lo > hi {
        return (-1.0, 1.0);
    }
    let span = hi - lo;
    if span <= f64::EPSILON * lo.abs().max(hi.abs()).max(1e-300) {
        let d = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
        return (lo - d, hi + d);
    }
    (lo - span * frac, hi + span * frac)
}

/// The largest magnitude a figure's axis may reach. Beyond it the numbers are not a gyro's
/// (10¹⁰⁰ °/h, °C or s) but a file's nonsense, and the plotting library's search for tick
/// spacings, which divides the span by ten until the ticks fit, would run without end on an
/// infinite span (a calibration whose K0 reaches 1e308, its range ±1e308).
pub(super) const MAX_AXIS: f64 = 1e100;

/// `range` if an axis can be drawn over it: finite bounds within ±[`MAX_AXIS`] and a positive
/// span (positive bounds within [1/MAX_AXIS, MAX_AXIS] on a logarithmic axis); else the reason,
/// naming the axis, so that a figure of absurd data is refused before it is drawn.
pub(super) fn drawable(axis: &str, range: (f64, f64), log: bool) -> Result<(f64, f64), DrawError> {
    let (lo, hi) = range;
    let fits = |v: f64| {
        if log {
            (1.0 / MAX_AXIS..=MAX_AXIS).contains(&v)
        } else {
            v.abs() <= MAX_AXIS
        }
    };
    if !(fits(lo) && fits(hi)) {
        return Err(DrawError::AxisBeyond {
            axis: axis.to_string(),
            value: if fits(lo) { hi } else { lo },
            log,
        });
    }
    // Not greater: equal, reversed, or not numbers.
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return Err(DrawError::AxisWithoutSpan {
            axis: axis.to_string(),
            lo,
            hi,
        });
    }
    Ok(range)
}

/// `[lo, hi]` of the y data with headroom on top for the legend (about a quarter of the plot).
pub(super) fn with_legend_room(lo: f64, hi: f64, entries: usize) -> (f64, f64) {
    let (lo, hi) = padded(lo, hi, 0.04);
    let share = (0.07 * entries as f64 + 0.04).min(0.45);
    (lo, hi + (hi - lo) * share / (1.0 - share))
}

/// Tick labels readable at any magnitude: fixed decimals from the tick spacing, or a
/// mantissa-exponent form for very small and very large numbers.
pub(super) fn tick_label(v: f64, span: f64) -> String {
    let step = (span / 8.0).abs();
    let big = v.abs().max(span.abs());
    if v == 0.0 {
        return "0".into();
    }
    if !(1e-3..1e6).contains(&big) {
        return format!("{v:.1e}");
    }
    let mut decimals = if step > 0.0 && step.is_finite() {
        (-(step.log10().floor()) as i32).clamp(0, 6) as usize
    } else {
        2
    };
    // A tick at 0.25 keeps its second decimal even when the spacing suggests one.
    let exact = |d: usize| {
        let s = format!("{v:.d$}");
        s.parse::<f64>()
            .is_ok_and(|r| (r - v).abs() <= 1e-6 * span.abs())
    };
    let limit = decimals + 2;
    while decimals < limit && !exact(decimals) {
        decimals += 1;
    }
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-')
        .trim_matches(['0', '.'])
        .is_empty()
    {
        "0".into()
    } else {
        s
    }
}

/// Tick labels of a logarithmic axis: 0.02, 0.5, 200 as a reader writes them, powers of ten
/// beyond.
pub(super) fn log_label(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return String::new();
    }
    if !(1e-4..1e6).contains(&v) {
        return format!("{v:.0e}");
    }
    // Three significant digits, trailing zeros dropped.
    let decimals = (2 - v.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The time axis: hours for long logs, minutes for shorter ones.
#[derive(Debug, Clone, Copy)]
pub(super) struct TimeAxis {
    pub(super) div: f64,
    pub(super) name: &'static str,
}

impl TimeAxis {
    pub(super) fn for_span(span_s: f64) -> TimeAxis {
        if span_s >= 3.0 * 3600.0 {
            TimeAxis {
                div: 3600.0,
                name: "time, h",
            }
        } else if span_s >= 600.0 {
            TimeAxis {
                div: 60.0,
                name: "time, min",
            }
        } else {
            TimeAxis {
                div: 1.0,
                name: "time, s",
            }
        }
    }
}

pub(super) fn finite_range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    (lo <= hi).then_some((lo, hi))
}

pub(super) fn union(a: Option<(f64, f64)>, b: Option<(f64, f64)>) -> Option<(f64, f64)> {
    match (a, b) {
        (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
        (a, None) => a,
        (None, b) => b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_follow_the_spacing() {
        assert_eq!(tick_label(0.0, 1.0), "0");
        assert_eq!(tick_label(12.0, 80.0), "12");
        assert_eq!(tick_label(0.25, 1.0), "0.25");
        assert_eq!(tick_label(2e-5, 1e-4), "2.0e-5");
    }

    #[test]
    fn log_labels_read_as_written() {
        assert_eq!(log_label(0.02), "0.02");
        assert_eq!(log_label(200.0), "200");
        assert_eq!(log_label(1.0), "1");
        assert_eq!(log_label(1e7), "1e7");
    }

    #[test]
    fn absurd_axes_are_refused_before_drawing() {
        assert_eq!(drawable("x", (-1.0, 2.0), false), Ok((-1.0, 2.0)));
        assert_eq!(drawable("x", (1e-3, 1e3), true), Ok((1e-3, 1e3)));
        for (range, log) in [
            ((-1e308, 1e308), false),
            ((f64::NEG_INFINITY, 0.0), false),
            ((0.0, f64::NAN), false),
            ((1.0, 1.0), false),
            ((0.0, 1.0), true),
            ((1.0, f64::INFINITY), true),
        ] {
            assert!(drawable("y", range, log).is_err(), "{range:?}");
        }
        // What `padded` makes of a range whose span overflows is refused too.
        assert!(drawable("y", padded(-1e308, 1e308, 0.05), false).is_err());
    }

    #[test]
    fn padded_ranges_are_never_empty() {
        for (a, b) in [
            (0.0, 0.0),
            (5.0, 5.0),
            (f64::NAN, 1.0),
            (3.0, 1.0),
            (1e-9, 1e-9),
        ] {
            let (lo, hi) = padded(a, b, 0.05);
            assert!(
                lo.is_finite() && hi.is_finite() && hi > lo,
                "{a} {b} -> {lo} {hi}"
            );
        }
    }
}
