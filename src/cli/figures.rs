//! Figures of merit as the command line shows them: numbers a person reads (short, `n/a` for
//! what could not be computed), raw → corrected cells, the table of one evaluation, and the
//! check of the merit options on a log. Apart from `common.rs` because every command that
//! judges a correction prints them and none needs the option plumbing to do so.

use super::common::{CliError, in_option_words, with_option};
use driftlab::Log;

/// `v` with `decimals` decimals for a table, as long as that stays short
/// ([`driftlab::number::fixed`]).
pub fn fixed(v: f64, decimals: usize) -> String {
    driftlab::number::fixed(v, decimals)
}

/// A number in running text: at most six significant digits (`0.3`, not
/// `0.30000000000000004`; `1e-300`, not three hundred digits).
pub fn num(v: f64) -> String {
    driftlab::number::readable(v)
}

/// Formats a ratio raw ÷ corrected for tables: `n/a` when it cannot be computed, and marked
/// `worse` below 1, where the correction made the figure worse than raw (in significant digits
/// below 0.01, which two decimals would show as 0.00).
pub fn ratio(r: f64) -> String {
    if !r.is_finite() {
        "n/a".into()
    } else if r < 0.01 {
        // Two decimals would read 0.00: the ratio in significant digits (2.7e-10x worse).
        format!("{}x worse", num(r))
    } else if r < 1.0 {
        format!("{}x worse", fixed(r, 2))
    } else {
        format!("{}x", fixed(r, 2))
    }
}

/// Formats a figure in °/h for tables: `n/a` when it could not be computed.
pub fn figure(v: f64) -> String {
    if v.is_finite() {
        fixed(v, 4)
    } else {
        "n/a".into()
    }
}

/// A figure of an axis of kind `kind`: a gyro's to 0.0001 °/h, an accelerometer's to 10⁻⁶
/// m/s² (its corrected figures are thousandths of its raw ones, a few 10⁻⁴ m/s²).
pub fn figure_in(v: f64, kind: driftlab::log::AxisKind) -> String {
    match kind {
        driftlab::log::AxisKind::Accel if v.is_finite() => fixed(v, 6),
        _ => figure(v),
    }
}

/// A table's cell for one figure of a summary of an axis of kind `kind`: `raw -> corrected
/// ratio`, its figures as [`figure_in`] writes them.
pub fn raw_to_corrected_in(
    raw: f64,
    corrected: f64,
    ratio_raw_cor: f64,
    kind: driftlab::log::AxisKind,
) -> String {
    format!(
        "{} -> {} {}",
        figure_in(raw, kind),
        figure_in(corrected, kind),
        ratio(ratio_raw_cor)
    )
}

/// The cells of the figures a summary shows for raw against corrected of an axis of kind
/// `kind`, as [`raw_to_corrected_in`] writes each: peak-to-peak, standard deviation and the
/// largest |window mean|.
pub fn comparison_cells_in(c: &driftlab::Comparison, kind: driftlab::log::AxisKind) -> [String; 3] {
    [
        raw_to_corrected_in(c.raw.p2p_dph, c.corrected.p2p_dph, c.p2p_ratio, kind),
        raw_to_corrected_in(c.raw.std_dph, c.corrected.std_dph, c.std_ratio, kind),
        raw_to_corrected_in(
            c.raw.win_mean_max_abs_dph,
            c.corrected.win_mean_max_abs_dph,
            c.win_mean_ratio,
            kind,
        ),
    ]
}

/// Refuses figures of merit whose filter or window does not fit in `log`, and a window the
/// engineer asked for (`window_asked`) that is not a whole number of at least two samples of
/// it; the default's window figures are then n/a (one sample), with the reason, or told (a
/// length the step does not make).
pub fn check_merit(
    merit: &driftlab::MeritOptions,
    window_asked: bool,
    log: &Log,
) -> Result<(), CliError> {
    checked_merit(
        merit,
        window_asked,
        log,
        driftlab::judge::options::check_window_asked,
    )
}

/// [`check_merit`] before a saved calibration is judged ([`driftlab::judge::verify::judge`]),
/// which checks that the window fits in the samples its correction leaves after the warm-up:
/// here only that it is whole samples, so that the bound named is the one that works.
pub fn check_merit_to_judge(
    merit: &driftlab::MeritOptions,
    window_asked: bool,
    log: &Log,
) -> Result<(), CliError> {
    checked_merit(
        merit,
        window_asked,
        log,
        driftlab::judge::options::check_window_whole,
    )
}

fn checked_merit(
    merit: &driftlab::MeritOptions,
    window_asked: bool,
    log: &Log,
    check_window: fn(f64, &Log) -> Result<(), driftlab::error::Invalid>,
) -> Result<(), CliError> {
    let told = driftlab::judge::options::check_merit(merit, log).map_err(with_option)?;
    let not_whole = if window_asked {
        check_window(merit.window_s, log).map_err(with_option)?;
        None
    } else {
        driftlab::judge::options::default_window_not_whole(merit.window_s, log)
    };
    for n in told.iter().chain(&not_whole) {
        note!("warning: {}", in_option_words(n));
    }
    Ok(())
}

/// Prints an evaluation as a small table of raw, corrected and ratio; the windowed figures are
/// labelled with the window they were computed over.
pub fn print_evaluation(
    e: &driftlab::judge::metrics::Evaluation,
    window_s: f64,
) -> Result<(), CliError> {
    print_evaluation_in(e, window_s, driftlab::log::AxisKind::Gyro)
}

/// [`print_evaluation`] of an axis of kind `kind`, its figures in its unit (deg/h, m/s^2).
pub fn print_evaluation_in(
    e: &driftlab::judge::metrics::Evaluation,
    window_s: f64,
    kind: driftlab::log::AxisKind,
) -> Result<(), CliError> {
    let c = &e.comparison;
    let w = driftlab::judge::options::window_label(window_s);
    let (mean_label, rms_label) = (format!("max |{w} mean|"), format!("mean {w} RMS"));
    out!(
        "  {:<34} {:>11} {:>11} {:>12}",
        format!("figure ({})", kind.unit_ascii()),
        "raw",
        "corrected",
        "raw/cor"
    )?;
    let rows = [
        (
            "peak-to-peak of filtered drift",
            c.raw.p2p_dph,
            c.corrected.p2p_dph,
            c.p2p_ratio,
        ),
        (
            "std of filtered drift",
            c.raw.std_dph,
            c.corrected.std_dph,
            c.std_ratio,
        ),
        (
            mean_label.as_str(),
            c.raw.win_mean_max_abs_dph,
            c.corrected.win_mean_max_abs_dph,
            c.win_mean_ratio,
        ),
        (
            rms_label.as_str(),
            c.raw.win_rms_mean_dph,
            c.corrected.win_rms_mean_dph,
            c.win_rms_ratio,
        ),
    ];
    for (name, raw, cor, r) in rows {
        out!(
            "  {name:<34} {:>11} {:>11} {:>12}",
            figure_in(raw, kind),
            figure_in(cor, kind),
            ratio(r)
        )?;
    }
    for (what, why) in c.unavailable() {
        out!("  {what} n/a: {why}")?;
    }
    if c.worse_than_raw.any() {
        out!(
            "  worse than raw: {} (ratio below 1)",
            c.worse_than_raw.names().join(", ")
        )?;
    }
    out!(
        "  {} samples ({} warm-up samples left out), {} windows; {}",
        c.raw.samples,
        e.warmup_samples,
        c.raw.windows,
        e.outside_text()
    )
}

#[cfg(test)]
mod tests {
    use super::ratio;

    #[test]
    fn a_ratio_far_below_one_is_not_shown_as_zero() {
        assert_eq!(ratio(2.5), "2.50x");
        assert_eq!(ratio(0.5), "0.50x worse");
        // 3.7e9 times worse than raw.
        let r = 1.0 / 3.7e9;
        assert_eq!(
            ratio(r),
            format!("{}x worse", driftlab::number::readable(r))
        );
        assert!(!ratio(r).starts_with("0.00"));
        assert_eq!(ratio(f64::NAN), "n/a");
    }
}
