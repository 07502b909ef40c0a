//! Whether the options of the figures of merit make sense on a log, checked before they are
//! computed: a filter longer than the log averages more than every sample, a filter or window
//! beyond any chamber run (1e9 s, inf) is a typing slip. A window longer than the log leaves
//! the windowed figures `n/a`, with the reason, as the figures of merit say.

use crate::error::Invalid;
use crate::judge::metrics::MeritOptions;
use crate::log::Log;
use crate::number::readable;

/// The time a log covers: its first to its last sample, and the last sample's own step.
pub fn log_span_s(log: &Log) -> f64 {
    span_with_step(log, log.nominal_dt_s())
}

/// [`log_span_s`] with the log's nominal step already found (finding it walks the log).
pub fn span_with_step(log: &Log, dt_s: f64) -> f64 {
    if log.is_empty() {
        return 0.0;
    }
    log.duration_s() + dt_s
}

/// Checks `opts` on `log`: a filter and a window that are positive seconds no longer than
/// any chamber run, and a filter that fits in the log. Gives
/// what to tell: a filter shorter than a sample, taken as one ([`one_sample`]); the log's
/// step is found once for both.
///
/// # Errors
/// `filter_s` or `window_s`, with the value and the log's span.
pub fn check_merit(opts: &MeritOptions, log: &Log) -> Result<Option<Invalid>, Invalid> {
    let dt = log.nominal_dt_s();
    let span = span_with_step(log, dt);
    for (field, v, why) in [
        (
            "filter_s",
            opts.filter_s,
            "a moving average longer than the log averages more than every sample",
        ),
        (
            "window_s",
            opts.window_s,
            "not one whole window fits in it, so no windowed figure can be computed",
        ),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Invalid::new(
                field,
                format!("must be a positive number of seconds, got {}", readable(v)),
            ));
        }
        if v > crate::models::recipe::MAX_WINDOW_S {
            return Err(Invalid::new(
                field,
                format!(
                    "{} s is longer than any chamber run: at most {} s (11.6 days)",
                    readable(v),
                    readable(crate::models::recipe::MAX_WINDOW_S)
                ),
            ));
        }
        if v < crate::models::recipe::MIN_WINDOW_S {
            return Err(crate::models::recipe::too_short(field, v));
        }
        // A window shorter than a sample is not refused here either: its figures are `n/a`,
        // with the reason ([`crate::judge::metrics::Unavailable::WindowShorterThanSample`]),
        // so that a slow held-out log judged with the default window keeps its other
        // figures. A window the engineer asked for is refused ([`check_window_asked`]).
        // A window longer than the log is not refused: its figures are `n/a`, with the reason
        // (a short log judged with the default 10-min window is still judged on the rest).
        if field == "filter_s" && v > span {
            return Err(Invalid::new(
                field,
                format!(
                    "{} s is longer than the log {} ({} s): {why}",
                    readable(v),
                    log.source,
                    readable(span)
                ),
            ));
        }
    }
    // A filter that short is none, taken as one sample: said, not refused.
    Ok(one_sample("filter_s", opts.filter_s, dt, &log.source))
}

/// Refuses a window the engineer asked for (not a default) that is shorter than the sampling
/// interval of `log`: it would be one sample labelled with a length it does not have, and
/// the figures asked for could not be given.
///
/// # Errors
/// `window_s`, with the value and the log's step.
pub fn check_window_asked(window_s: f64, log: &Log) -> Result<(), Invalid> {
    let dt = log.nominal_dt_s();
    if shorter_than_a_sample(window_s, dt) {
        return Err(Invalid::new(
            "window_s",
            format!(
                "{} s is shorter than the sampling interval of {} ({} s): a window of one \
                 sample would be labelled with a length it does not have",
                readable(window_s),
                log.source,
                readable(dt)
            ),
        ));
    }
    Ok(())
}

/// Whether `v` seconds is shorter than one sampling interval `dt_s` (with 1 % to spare for a
/// jittered clock, whose nominal step is a little off its true one).
fn shorter_than_a_sample(v: f64, dt_s: f64) -> bool {
    dt_s.is_finite() && dt_s > 0.0 && v < 0.99 * dt_s
}

/// A window of `v` seconds, named `field`, that is shorter than the sampling interval `dt_s`
/// of the log `log_name`: it is taken as one sample, longer than asked. `None` when it is not.
pub fn one_sample(field: &str, v: f64, dt_s: f64, log_name: &str) -> Option<Invalid> {
    shorter_than_a_sample(v, dt_s).then(|| {
        Invalid::new(
            field,
            format!(
                "{} s is shorter than the sampling interval of {log_name} ({} s): one sample \
                 ({} s) is used",
                readable(v),
                readable(dt_s),
                readable(dt_s)
            ),
        )
    })
}

/// How a window of `seconds` is named in a table's labels: `10-min`, `90-s`.
pub fn window_label(seconds: f64) -> String {
    if seconds >= 60.0 && (seconds / 60.0).fract() == 0.0 {
        format!("{}-min", readable(seconds / 60.0))
    } else {
        format!("{}-s", readable(seconds))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filters_and_windows_must_fit_in_the_log() {
        let n = 1000;
        let log = Log::from_columns(
            "run.csv",
            (0..n).map(|i| i as f64).collect(),
            vec![0.0; n],
            vec![20.0; n],
        );
        let ok = MeritOptions {
            filter_s: 100.0,
            window_s: 1000.0,
        };
        assert_eq!(check_merit(&ok, &log), Ok(None));
        // Longer than the log: the windowed figures are n/a, the rest is judged.
        let long = MeritOptions {
            filter_s: 100.0,
            window_s: 1001.0,
        };
        assert_eq!(check_merit(&long, &log), Ok(None));
        for (filter_s, window_s, field) in [
            (f64::INFINITY, 600.0, "filter_s"),
            (1e12, 600.0, "filter_s"),
            (0.0, 600.0, "filter_s"),
            (100.0, f64::INFINITY, "window_s"),
            (100.0, 2e6, "window_s"),
            (100.0, f64::NAN, "window_s"),
        ] {
            let e = check_merit(&MeritOptions { filter_s, window_s }, &log).unwrap_err();
            assert_eq!(e.field, field, "{filter_s} {window_s}: {e}");
        }
        assert_eq!(window_label(600.0), "10-min");
        assert_eq!(window_label(90.0), "90-s");
        assert_eq!(window_label(3600.0), "60-min");
    }
}
