//! Why a fit could not be made: each refusal of the models' stages with what and where (the
//! log, the model, the axis, the counts), so that a face can word it its own way.
//!
//! The messages name settings by their recipe names (`plateaus`), never a face's option.

use std::path::PathBuf;

/// A fit the data cannot support, or a model that cannot be applied to a log.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// Fewer samples than any calibration takes.
    #[error("{log}: {count} samples are too few to calibrate (at least {minimum} are needed)")]
    TooFewSamples {
        /// The log.
        log: String,
        /// Samples it has.
        count: usize,
        /// Samples a calibration needs ([`super::MIN_SAMPLES`]).
        minimum: usize,
    },
    /// More samples than one calibration can index.
    #[error("{log}: {count} samples are more than the {maximum} one calibration can take")]
    TooManySamples {
        /// The log.
        log: String,
        /// Samples it has.
        count: usize,
        /// The most a calibration takes.
        maximum: usize,
    },
    /// Fewer usable samples than a regression model needs for its coefficients.
    #[error(
        "{log}: {count} samples with their full history are too few for model {model} \
         ({coefficients} coefficients)"
    )]
    TooFewForModel {
        /// The log.
        log: String,
        /// Samples it has past the warm-up of their rates of T.
        count: usize,
        /// The model.
        model: String,
        /// Coefficients the model has.
        coefficients: usize,
    },
    /// The least-squares solve failed: too few usable samples, or columns that do not differ.
    #[error(
        "{log}: model {model} could not be fitted ({used} usable samples for {coefficients} \
         coefficients)"
    )]
    Unsolvable {
        /// The log.
        log: String,
        /// The model.
        model: String,
        /// Samples the solve could use.
        used: usize,
        /// Coefficients it solved for.
        coefficients: usize,
    },
    /// Columns of the design that are dependent on this log: the least squares cannot tell
    /// their coefficients apart.
    #[error(
        "{log}: model {model}: on this log the terms {} are one effect between them (the \
         design's columns are linearly dependent): a fit cannot tell their coefficients apart, \
         and would state a share for each with standard errors that mean nothing; leave one of \
         them out",
        columns.join(", ")
    )]
    DependentColumns {
        /// The log.
        log: String,
        /// The model.
        model: String,
        /// The columns that take part, by name.
        columns: Vec<String>,
    },
    /// A temperature range too narrow for a model in T.
    #[error(
        "{log}: the temperature spans {}: too little for model {model} (a calibration in T \
         needs at least {minimum_c} °C)",
        span_text(*.span_c)
    )]
    NarrowSpan {
        /// The log.
        log: String,
        /// The model.
        model: String,
        /// The lowest and highest finite temperature, °C; `None` when none is finite.
        span_c: Option<(f64, f64)>,
        /// The span a model needs, °C ([`super::MIN_TEMP_SPAN_C`]).
        minimum_c: f64,
    },
    /// A model with rate terms on a log that never ramps.
    #[error(
        "{log}: the temperature never changes faster than {fastest_c_per_min:.3} °C/min: model \
         {model} has rate terms, which need ramps of at least {minimum_c_per_min} °C/min (try \
         poly-t, a model of T alone)"
    )]
    NoRamps {
        /// The log.
        log: String,
        /// The model.
        model: String,
        /// The fastest |Ṫ| found, °C/min.
        fastest_c_per_min: f64,
        /// The |Ṫ| rate terms need, °C/min ([`super::MIN_RAMP_C_PER_MIN`]).
        minimum_c_per_min: f64,
    },
    /// A fixed delay over half the log: the delayed temperature is the log's first reading
    /// for most of it.
    #[error(
        "{log}: model {model}: a delay of {} s is more than half of the {} s log, which would \
         read its first temperature for most of its samples; a delay is at most half the log",
        crate::number::readable(*delay_s),
        crate::number::readable(*duration_s)
    )]
    DelayBeyondLog {
        /// The log.
        log: String,
        /// The model.
        model: String,
        /// The delay asked for, s.
        delay_s: f64,
        /// The log's duration, s.
        duration_s: f64,
    },
    /// A rate column that holds one value throughout: a gyro disconnected (zeros) or stuck;
    /// or an accelerometer's.
    #[error("{}", frozen(log, axis, *kind, *value_dph))]
    FrozenRate {
        /// The log.
        log: String,
        /// The axis, empty for a log of one.
        axis: String,
        /// What the axis measures.
        kind: crate::log::AxisKind,
        /// The one value, in the kind's unit (°/h for a gyro).
        value_dph: f64,
    },
    /// An axis holding readings no sensor of its kind gives (beyond 10⁴ °/s, or 1000 g), more
    /// of them than the readers drop as glitches.
    #[error("{}", impossible(self))]
    Impossible {
        /// The log.
        log: String,
        /// The axis, empty for a log of one.
        axis: String,
        /// What the axis measures.
        kind: crate::log::AxisKind,
        /// How many readings are beyond.
        count: usize,
        /// How many readings the axis has (not NaN).
        readings: usize,
        /// The one farthest from zero, in the kind's unit (°/h for a gyro).
        worst: f64,
        /// The time of the first and of the last, s.
        first_s: f64,
        last_s: f64,
    },
    /// A gyro axis more than 1 % of whose samples are missing (blank, NaN or infinite cells
    /// the reader kept, since they were the column's own).
    #[error(
        "{log}: the rate of axis {axis} is missing at {count} of its {total} samples ({} %): \
         more than the 1 % whose rows the reader drops, so that axis is neither fitted nor \
         judged; choose the other axes, or fill or cut that column",
        crate::log::impossible::share_percent(*count, *total)
    )]
    MissingSamples {
        /// The log.
        log: String,
        /// The axis.
        axis: String,
        /// How many samples are missing.
        count: usize,
        /// How many the axis has.
        total: usize,
    },
    /// A model that is no static curve in T asked of an accelerometer axis.
    #[error(
        "{log}: accelerometer axis {axis}: model {model} reads more than T (a rate of T, \
         another channel, a delay or a lag), and an accelerometer's bias is a static curve in \
         T: give it {}",
        super::accel::STATIC_MODELS
    )]
    NotStatic {
        /// The log.
        log: String,
        /// The axis.
        axis: String,
        /// The model asked for.
        model: String,
    },
    /// A log none of whose segments (the stretches between its gaps) lasts long enough for
    /// a temperature rate: T's smoothing and derivative steps restart after every gap.
    #[error(
        "{log}: no stretch of the log is long enough for a temperature rate: Ṫ and T̈ need {} s \
         of samples without a gap (the T smoothing and four derivative steps), and the longest \
         stretch lasts {} s; shorten temp_smoothing_s and step_h_s, or record without the gaps",
        crate::number::readable(*needed_s),
        crate::number::readable(*longest_s)
    )]
    NoRateHistory {
        /// The log.
        log: String,
        /// The history a rate needs, s.
        needed_s: f64,
        /// The longest stretch without a gap, s.
        longest_s: f64,
    },
    /// A temperature that does not vary, over which a curve in T cannot be spread.
    #[error("{log}: T does not vary, so model {model} cannot be fitted over it")]
    FlatTemperature {
        /// The log.
        log: String,
        /// The model.
        model: String,
    },
    /// No plateau to take K0's points from.
    #[error(
        "no plateaus: K0(T) needs at least one temperature-stabilisation period; mark them \
         (the recipe's plateaus, as ranges) or loosen the detector"
    )]
    NoK0Plateaus,
    /// Knots placed or values set by hand that the fit could not keep: the points carry only a
    /// simpler curve (fewer knots, a line, a constant, none), on which they cannot stand.
    #[error("{0}")]
    HandKnotsNotKept(Box<HandKnotsNotKept>),
    /// A model fitted on plateaus, on a log that has none.
    #[error("{log}: model {model} is fitted on plateaus and the log has none")]
    NoPlateaus {
        /// The log.
        log: String,
        /// The model.
        model: String,
    },
    /// A channel the model reads is not in the log.
    #[error(
        "{log}: no channel \"{channel}\" (extra channels: {})",
        list(available)
    )]
    MissingChannel {
        /// The log.
        log: String,
        /// The channel asked for.
        channel: String,
        /// The extra channels the log has.
        available: Vec<String>,
    },
    /// A model with ΔT terms on a log without a second temperature sensor.
    #[error("{log}: model {model} needs a second temperature sensor (dT) and the log has none")]
    NoSecondTemperature {
        /// The log.
        log: String,
        /// The model.
        model: String,
    },
    /// A unit calibration asked for no axis.
    #[error("{log}: no axis to calibrate")]
    NoAxes {
        /// The log.
        log: String,
    },
    /// An axis the log does not have.
    #[error("{log}: no gyro axis \"{axis}\" (its axes: {})", available.join(", "))]
    MissingAxis {
        /// The log.
        log: String,
        /// The axis asked for.
        axis: String,
        /// The log's axes.
        available: Vec<String>,
    },
    /// One axis asked for twice.
    #[error("{log}: axis \"{axis}\" is asked for twice")]
    AxisTwice {
        /// The log.
        log: String,
        /// The axis.
        axis: String,
    },
    /// A refusal on one axis of a unit.
    #[error("axis {axis}: {source}")]
    OnAxis {
        /// The axis.
        axis: String,
        /// What went wrong there.
        source: Box<FitError>,
    },
    /// A refusal while a model was applied to a log read from a file.
    #[error("{}: {source}", path.display())]
    OnFile {
        /// The file.
        path: PathBuf,
        /// What went wrong there.
        source: Box<FitError>,
    },
}

impl FitError {
    /// The channel `channel` is not among `log`'s extra channels.
    pub fn missing_channel(log: &crate::log::Log, channel: &str) -> FitError {
        FitError::MissingChannel {
            log: log.source.clone(),
            channel: channel.to_string(),
            available: log.extra.iter().map(|c| c.name.clone()).collect(),
        }
    }

    /// This error, said to have happened on axis `axis` of a unit.
    pub fn on_axis(self, axis: impl Into<String>) -> FitError {
        FitError::OnAxis {
            axis: axis.into(),
            source: Box::new(self),
        }
    }

    /// This error, said to have happened on the log read from `path`.
    pub fn on_file(self, path: impl Into<PathBuf>) -> FitError {
        FitError::OnFile {
            path: path.into(),
            source: Box::new(self),
        }
    }

    /// The error itself, without the axes and files it is said to have happened on.
    pub fn innermost(&self) -> &FitError {
        match self {
            FitError::OnAxis { source, .. } | FitError::OnFile { source, .. } => source.innermost(),
            other => other,
        }
    }
}

/// [`FitError::FrozenRate`]'s message, in the words of the axis's kind.
fn frozen(log: &str, axis: &str, kind: crate::log::AxisKind, value: f64) -> String {
    let value = crate::number::readable(value);
    match kind {
        crate::log::AxisKind::Gyro => format!(
            "{log}: the rate{} never changes (every sample reads {value} °/h): a gyro that is \
             disconnected or stuck has no drift to calibrate; check the rate column",
            if axis.is_empty() {
                String::new()
            } else {
                format!(" of axis {axis}")
            },
        ),
        crate::log::AxisKind::Accel => format!(
            "{log}: accelerometer axis {axis} never changes (every sample reads {value} m/s²): \
             an accelerometer that is disconnected or stuck has no drift to calibrate; check \
             its column"
        ),
    }
}

/// [`FitError::Impossible`]'s message, in the words of the axis's kind.
fn impossible(e: &FitError) -> String {
    let FitError::Impossible {
        log,
        axis,
        kind,
        count,
        readings,
        worst,
        first_s,
        last_s,
    } = e
    else {
        return String::new();
    };
    let r = crate::number::readable;
    let (what, unit, limit) = match kind {
        crate::log::AxisKind::Gyro => (
            if axis.is_empty() {
                "the rate".to_string()
            } else {
                format!("the rate of axis {axis}")
            },
            "°/h",
            crate::log::impossible::RATE_LIMIT_WORDS,
        ),
        crate::log::AxisKind::Accel => (
            format!("accelerometer axis {axis}"),
            "m/s²",
            crate::log::impossible::ACCEL_LIMIT_WORDS,
        ),
    };
    format!(
        "{log}: {what} holds {count} reading{} beyond {limit} ({} {unit}; from {} s to {} s), \
         {} % of its {readings}: more than the {} % taken for glitches, so no fit or figure \
         can take the axis: cut that stretch out of the log, or check its unit",
        if *count == 1 { "" } else { "s" },
        r(*worst),
        r(*first_s),
        r(*last_s),
        crate::log::impossible::share_percent(*count, *readings),
        100.0 * crate::log::impossible::MOST_GLITCH_SHARE,
    )
}

/// A temperature span in a message: its width and ends, or that there is none.
fn span_text(span_c: Option<(f64, f64)>) -> String {
    match span_c {
        Some((lo, hi)) => format!("{:.3} °C ({lo:.3} … {hi:.3} °C)", hi - lo),
        None => "nothing (no finite temperature)".to_string(),
    }
}

/// Names in a message, or "none".
fn list(names: &[String]) -> String {
    if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    }
}

/// A model's setting written as text (a model's name, its terms, how its delay or lag is
/// chosen, which samples it is fitted on) that does not parse.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParseError {
    /// A model name that is no preset.
    #[error("unknown model \"{name}\"; models are {}", known.join(", "))]
    UnknownModel {
        /// The name given.
        name: String,
        /// The presets' names.
        known: Vec<&'static str>,
    },
    /// A delay that is none of the forms.
    #[error("{text:?}: expected none, SECONDS (0 or more), auto or bands:N")]
    Delay {
        /// The text given.
        text: String,
    },
    /// A banded delay with a number of bands out of range.
    #[error("{text:?}: bands:N needs N from 1 to {maximum}")]
    DelayBands {
        /// The text given.
        text: String,
        /// The most bands.
        maximum: usize,
    },
    /// A lag that is none of the forms.
    #[error("{text:?}: expected none, SECONDS (0 or more), auto or auto-t")]
    Lag {
        /// The text given.
        text: String,
    },
    /// Samples to fit on that are none of the choices.
    #[error("{text:?}: expected all, plateaus or staged")]
    FitSamples {
        /// The text given.
        text: String,
    },
    /// A channel term without the channel's name.
    #[error("term \"{term}\" names no channel")]
    TermWithoutChannel {
        /// The term given.
        term: String,
    },
    /// A piecewise-linear term with a number of knots out of range.
    #[error("term \"{term}\": pwlT needs {minimum} to {maximum} knots")]
    PwlKnots {
        /// The term given.
        term: String,
        /// The fewest knots.
        minimum: usize,
        /// The most knots.
        maximum: usize,
    },
    /// A power of `T − Tref`, or a polynomial model's order, out of range.
    #[error("\"{text}\": a polynomial in T takes an order from 1 to {maximum}")]
    PolyOrder {
        /// The term or model name given.
        text: String,
        /// The highest order.
        maximum: u8,
    },
    /// A term that is none of the known ones.
    #[error(
        "unknown term \"{term}\"; terms are 1, T, T^2, T^3, Tdot, Tddot, T*Tdot, |Tdot|, \
         T*Tddot, sgn(Tdot)*Tddot, dT, dT^2, selfheat, ch:NAME, ch^2:NAME, pwlT:N, T-Tref, \
         (T-Tref)^K"
    )]
    UnknownTerm {
        /// The term given.
        term: String,
    },
    /// A list of terms with none in it.
    #[error("a model needs at least one term")]
    NoTerms,
    /// A term given twice: the two equal columns cannot be told apart.
    #[error("term \"{term}\" is given twice: two equal terms cannot be told apart by a fit")]
    RepeatedTerm {
        /// The term given twice.
        term: String,
    },
}

/// Knots placed or values set by hand that a fit could not keep ([`FitError::HandKnotsNotKept`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "{field}: {what} by hand, but {label} could not be fitted as asked ({why}), so they would \
     be dropped; {remedy}"
)]
pub struct HandKnotsNotKept {
    /// The recipe's field (`k0.at`, `k1_plus.values`).
    pub field: String,
    /// What was set by hand (`4 knots placed`, `2 knot values set`).
    pub what: String,
    /// The coefficient (`K0`).
    pub label: &'static str,
    /// What the fit said of its points.
    pub why: String,
    /// What to change.
    pub remedy: &'static str,
}
