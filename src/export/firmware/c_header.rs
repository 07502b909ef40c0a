//! A calibration as one self-contained C99 header: constants, the curve evaluator and the
//! streaming corrector, all `static const` or `static inline`; one writer, [`c_header`], for a
//! single axis and for every gyro axis of a unit.
//!
//! Why `static inline` and not an implementation block behind a macro: the header can be
//! included from any number of C files without choosing which one holds the code, nothing has to
//! be linked, and a compiler drops whatever is unused. The cost is a copy of the (small) tables in
//! each file that includes it.
//!
//! The code is driftlab's C runtime (`runtime.c`, [`super::c_runtime`]): the curve evaluator,
//! the regimes and the temperature's history, one source for every header. Around it the writer
//! puts what is generated for the calibration: the preamble, each axis's constants and model
//! functions, the state and the push. The C repeats driftlab's arithmetic operation for
//! operation, so that it agrees bit for bit:
//!
//! - [`crate::models::approx::Approx::eval`]: non-finite argument → 0; clamp to the fitted range unless
//!   the curve extrapolates; polynomials by the same Horner sum (padded with zeros to 4
//!   coefficients as driftlab pads them); knot curves by the same edge lines outside their knots
//!   and the same per-segment cubics in `u` inside (the cubics are exported, not recomputed);
//! - [`crate::models::vakhrameev::Calibration::predict`]: regime from the sign of `Ṫ·T̈`, then
//!   `K0 + K1·Ṫ + K2·T̈` summed left to right;
//! - [`crate::models::vakhrameev::correct::StreamCorrector`]: the causal running mean of T, the 3-point backward
//!   differences with `2H` as one constant, the first `2s` (`4s`) samples without Ṫ (T̈).
//!
//! A regression model has its own part ([`super::c_regression`], [`super::c_corrector`]): its
//! terms as an array of codes evaluated by one `switch`, and a port of
//! [`crate::models::regression::RegressionCorrector::push`] (lag, smoothing, differences, τd(T), the
//! delayed read, clamping, the row and the dot product from −0, as `f64::sum` starts).
//!
//! One axis or a unit: a single-axis calibration (one unnamed axis, not
//! [`UnitCalibration::is_unit`]) is written as driftlab has always written it, its names
//! `driftlab_k0`, `driftlab_push` taking one rate, the temperature's history inside the state. A
//! unit of named axes gets one state and one push taking the time, the temperature and every
//! axis's rate. The axes share the housing's temperature, so the header smooths and
//! differentiates T once for all of its Vakhrameev axes (their T settings are one, as
//! [`UnitCalibration::validate`] checks); each axis has its own curves, dead-bands,
//! `driftlab_<axis>_predict` and `driftlab_<axis>_is_outside`. A regression axis keeps its own
//! corrector inside the same state: the single-axis part with every `driftlab_` / `DRIFTLAB_`
//! name put under the axis's (`driftlab_gz_`), so it is the same code, operation for operation.
//! Another kind of axis (an accelerometer's) is one more part in [`axis_part`] and one more
//! case of the push's loop over the axes, its rate's unit its own; the layout stays as it is.
//!
//! One difference of form: driftlab counts samples without bound, the C keeps the ring slot
//! and a count that stops at `4s`, so a processor running for years never wraps a counter.
//!
//! Bit-for-bit agreement holds where C doubles are IEEE-754 binary64 evaluated at their own
//! precision (`FLT_EVAL_METHOD == 0`: x86-64, AArch64, ARM and RISC-V with a double FPU) and
//! `a*b + c` is not fused into one rounding (GCC: `-ffp-contract=off`, the default with
//! `-std=c99`; other compilers: the `FP_CONTRACT` pragma the header sets).

use super::c_corrector::regression_corrector;
use super::c_names;
use super::c_regression::{regression_constants, regression_preamble};
use super::c_runtime::{TemperatureHistory, section, section_in_state};
use super::c_vakhrameev::{ModelNames, is_outside_fn, model_constants, predict_fn};
use super::{AxisOfUnit, ExportError, comment_text, sha_text};
use crate::models::fitted::DriftModel;
use crate::models::unit::UnitCalibration;
use crate::models::vakhrameev::{Calibration, SourceInfo};

/// How a header is laid out, chosen at the edge from the unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Layout {
    /// One unnamed axis: the single-axis header driftlab has always written.
    Single,
    /// Named axes: one state and one push for all of them.
    Unit,
}

/// One axis of the header: its model and the names of its C identifiers.
struct Axis<'a> {
    /// The axis's name in the calibration (`gx`), empty for a single axis.
    name: &'a str,
    /// Its identifiers' part (`gx`): the name as a C identifier.
    ident: String,
    /// What its identifiers start with (`driftlab_gx`, or `driftlab` for a single axis).
    names: ModelNames,
    model: &'a DriftModel,
    /// What the axis measures: the unit of its rate's slot and coefficients.
    kind: crate::log::AxisKind,
}

/// The header for `unit`: a single axis as driftlab has always written it, a unit of named axes
/// with one push for all of them.
///
/// # Errors
/// A number a processor cannot use; Vakhrameev axes made at different sampling periods or with
/// different T settings (they cannot share one temperature history); a regression axis of a unit
/// that reads a second temperature sensor or extra channels (the unit's push takes one
/// temperature: export that axis alone); a unit that does not hold together.
pub fn c_header(unit: &UnitCalibration) -> Result<String, ExportError> {
    let layout = if unit.is_unit() {
        unit.validate()?;
        Layout::Unit
    } else {
        Layout::Single
    };
    // Written first with every axis's identifiers under a placeholder, which gives the
    // identifiers the header has of its own: each name's part is then one that makes none of
    // them (c_names).
    let placeholders: Vec<String> = (0..unit.axes.len()).map(c_names::fallback).collect();
    let probe = write_header(unit, layout, &placeholders, None)?;
    if layout == Layout::Single {
        return Ok(probe);
    }
    let parts = c_names::axis_idents(&probe, &unit.axis_names());
    write_header(unit, layout, &parts, None)
}

/// The header of one axis of a unit exported alone: the single-axis header of its `model` (one
/// rate per push), its comment block naming the axis and its unit, and `DRIFTLAB_AXIS` the
/// axis's name, so a header cannot be taken for another axis's.
///
/// # Errors
/// As [`c_header`] for the single-axis calibration of `model`.
pub(super) fn c_header_of_axis(
    model: &DriftModel,
    of: &AxisOfUnit<'_>,
) -> Result<String, ExportError> {
    let single = UnitCalibration::single(model.clone());
    write_header(&single, Layout::Single, &[c_names::fallback(0)], Some(of))
}

/// What a single-axis header says of the axis it corrects: nothing for a calibration that
/// names none; for one axis of a unit exported alone, a comment line (after the gyro id) and
/// the `DRIFTLAB_AXIS` macro (after `DRIFTLAB_CREATED`).
pub(super) fn axis_lines(of: Option<&AxisOfUnit<'_>>) -> (String, String) {
    match of {
        None => (String::new(), String::new()),
        Some(of) => (
            format!(" *   axis:      {}\n", of.describe()),
            format!("#define DRIFTLAB_AXIS {}\n", c_string(of.name)),
        ),
    }
}

/// The header of `unit` laid out as `layout`, each axis's identifiers under its part in
/// `parts` (a unit's; a single axis has the single-axis names).
fn write_header(
    unit: &UnitCalibration,
    layout: Layout,
    parts: &[String],
    of: Option<&AxisOfUnit<'_>>,
) -> Result<String, ExportError> {
    let mut axes = header_axes(unit, layout, parts)?;
    // One axis of a unit exported alone keeps its kind in the single-axis header.
    if let (Some(of), [one]) = (of, axes.as_mut_slice()) {
        one.kind = of.kind;
    }
    let history = temperature_history(&axes)?;
    for a in &axes {
        if let DriftModel::Regression(r) = a.model {
            r.model.validate()?;
            if layout == Layout::Unit {
                one_temperature(a.name, &r.model)?;
            }
        }
    }
    let mut h = String::new();
    match (layout, axes[0].model) {
        (Layout::Single, DriftModel::Vakhrameev(cal)) => preamble(&mut h, cal, "vakhrameev", of),
        (Layout::Single, DriftModel::Regression(r)) => regression_preamble(&mut h, r, of)?,
        (Layout::Unit, _) => unit_preamble(&mut h, unit, &axes, history.is_some()),
    }
    if history.is_some() {
        h.push_str(&section("curves"));
        h.push_str(&section("regimes"));
        if layout == Layout::Unit {
            h.push_str(&section("regime_fn"));
            h.push_str(&section("beyond_fn"));
        }
    }
    for a in &axes {
        axis_part(&mut h, a, layout)?;
    }
    match (layout, history) {
        (Layout::Single, Some(t)) => corrector(&mut h, t)?,
        (Layout::Single, None) => {}
        (Layout::Unit, history) => unit_corrector(&mut h, &axes, history)?,
    }
    h.push_str("\n#endif /* DRIFTLAB_CALIBRATION_H */\n");
    Ok(h)
}

/// The axes of `unit` with their identifiers: the single-axis names for a single axis, each
/// axis's own under a unit's, its part from `parts`.
fn header_axes<'a>(
    unit: &'a UnitCalibration,
    layout: Layout,
    parts: &[String],
) -> Result<Vec<Axis<'a>>, ExportError> {
    if unit.axes.is_empty() {
        return Err(ExportError::NoAxes);
    }
    Ok(unit
        .axes
        .iter()
        .zip(parts)
        .map(|(a, ident)| Axis {
            name: &a.name,
            ident: ident.clone(),
            names: match layout {
                Layout::Single => ModelNames::single(),
                Layout::Unit => ModelNames::axis(&a.name, ident),
            },
            model: &a.model,
            kind: a.kind,
        })
        .collect())
}

/// The one temperature history of the Vakhrameev axes, `None` when there are none.
fn temperature_history(axes: &[Axis<'_>]) -> Result<Option<TemperatureHistory>, ExportError> {
    let mut shared: Option<(TemperatureHistory, &str)> = None;
    for a in axes {
        let DriftModel::Vakhrameev(cal) = a.model else {
            continue;
        };
        let this = TemperatureHistory::of(cal, a.name)?;
        match shared {
            None => shared = Some((this, a.name)),
            Some((first, first_name)) if first != this => {
                return Err(ExportError::TemperatureHistories {
                    first: first_name.to_string(),
                    second: a.name.to_string(),
                    first_history: (first.dt_s, first.smooth, first.step),
                    second_history: (this.dt_s, this.smooth, this.step),
                });
            }
            Some(_) => {}
        }
    }
    Ok(shared.map(|(s, _)| s))
}

/// Refuses a regression axis of a unit that reads more than the unit's one temperature.
fn one_temperature(
    axis: &str,
    m: &crate::models::regression::RegressionModel,
) -> Result<(), ExportError> {
    let mut reads: Vec<String> = m
        .temp2
        .iter()
        .map(|t| format!("the second temperature {t}"))
        .collect();
    reads.extend(m.channel_names().iter().map(|c| format!("the channel {c}")));
    if reads.is_empty() {
        Ok(())
    } else {
        Err(ExportError::MoreThanOneTemperature {
            axis: axis.to_string(),
            reads,
        })
    }
}

/// One axis's model: a Vakhrameev axis's dead-bands, curves, predict and is_outside under its
/// names; a regression axis's constants and corrector under its names. A unit's axis starts
/// with a banner naming it; a single axis's Vakhrameev model keeps the runtime's regime and
/// range functions beside its own, where its header has always had them.
fn axis_part(h: &mut String, a: &Axis<'_>, layout: Layout) -> Result<(), ExportError> {
    if layout == Layout::Unit {
        let kind = match a.kind {
            crate::log::AxisKind::Gyro => String::new(),
            crate::log::AxisKind::Accel => ", accelerometer, m/s^2".to_string(),
        };
        h.push_str(&format!(
            "\n/* ==== Axis {} ({}{kind}) {} */\n",
            comment_text(a.name),
            a.model.tag(),
            "=".repeat(60usize.saturating_sub(a.name.len() + kind.len()))
        ));
    }
    match a.model {
        DriftModel::Vakhrameev(cal) => {
            model_constants(h, cal, &a.names)?;
            if layout == Layout::Single {
                h.push_str(&section("regime_fn"));
            }
            predict_fn(h, &a.names);
            if layout == Layout::Single {
                h.push_str(&section("beyond_fn"));
            }
            is_outside_fn(h, &a.names);
        }
        DriftModel::Regression(r) => {
            let mut part = String::new();
            regression_constants(&mut part, &r.model, a.kind.unit_ascii())?;
            regression_corrector(&mut part, &r.model)?;
            h.push_str(&a.names.rename_all(&part));
        }
    }
    Ok(())
}

/// The comment block naming gyro, source log and units, the include guard and the includes.
fn preamble(h: &mut String, cal: &Calibration, model: &str, of: Option<&AxisOfUnit<'_>>) {
    let u = &cal.units;
    let (axis_doc, axis_define) = axis_lines(of);
    h.push_str(&format!(
        r#"/*
 * Thermal-drift calibration of gyro {gyro}, for the gyro's processor.
 * Written by driftlab {version} (`driftlab export --format c-header`); do not edit by hand:
 * export again from the calibration file instead.
 *
 *   model:     {model}
 *   gyro id:   {gyro}
{axis_doc}{source_doc} *
 * Units: time {ut}, rate {ur}, temperature {utemp}, Tdot {utd}, Tddot {utdd},
 *        K1 {uk1}, K2 {uk2}.
 *
 * Correction, sample by sample, using only past samples:
 *     Omega_cor = Omega_raw - Omega_pred
 *     Omega_pred = K0(T) + K1(Tdot)*Tdot + K2(Tddot)*Tddot
 * with K1+, K2+ where Tdot*Tddot > 0, K1-, K2- where Tdot*Tddot < 0 and K0 alone where
 * Tdot*Tddot = 0 (also while the first 2*step (4*step) samples give no Tdot (Tddot) yet).
 * Tdot and Tddot are 3-point backward differences of T after a causal moving average.
 *
 * Use: call driftlab_init once, then driftlab_push for every sample, at the sampling period
 * DRIFTLAB_DT_S; call driftlab_reset after a gap, a power cycle or an invalid temperature.
 * driftlab_push_at takes each sample's time too and restarts by itself after a dropout.
 *
 *     #include "this_header.h"
 *     static driftlab_state gyro;
 *     driftlab_init(&gyro);
 *     ... every DRIFTLAB_DT_S seconds:
 *     double omega_cor_dph = driftlab_push(&gyro, omega_raw_dph, temp_c);
 *
 * Everything below is static const or static inline: include this header from any number of C
 * files, nothing to link. C99, doubles, no malloc; the only library call is the isfinite macro
 * of <math.h>. The state is one struct of sizeof(driftlab_state) bytes, sized at compile time.
 *
{bit_for_bit} */
{guard}
#define DRIFTLAB_GYRO_ID {gyro_c}
#define DRIFTLAB_CREATED {created_c}
{axis_define}"#,
        gyro = comment_text(&cal.gyro_id),
        version = env!("CARGO_PKG_VERSION"),
        source_doc = source_doc(&cal.source, &cal.created),
        ut = comment_text(&u.time),
        ur = comment_text(&u.rate),
        utemp = comment_text(&u.temperature),
        utd = comment_text(&u.tdot),
        utdd = comment_text(&u.tddot),
        uk1 = comment_text(&u.k1),
        uk2 = comment_text(&u.k2),
        gyro_c = c_string(&cal.gyro_id),
        created_c = c_string(&cal.created),
        bit_for_bit = BIT_FOR_BIT_DOC,
        guard = guard("isfinite (a macro: no libm function is called)"),
    ));
}

/// The comment lines naming the log a calibration was made from (its name, length and SHA-256)
/// and when it was made.
pub(super) fn source_doc(src: &SourceInfo, created: &str) -> String {
    format!(
        " *   source:    {} ({} samples, {} s)\n *   sha256:    {}\n *   created:   {}\n",
        comment_text(&src.name),
        src.samples,
        src.duration_s,
        sha_text(src),
        comment_text(created)
    )
}

/// What a single-axis header's comment block says its bit-for-bit agreement rests on.
pub(super) const BIT_FOR_BIT_DOC: &str = concat!(
    " * This code repeats driftlab's arithmetic operation for operation, so it corrects a log bit for\n",
    " * bit as driftlab does where doubles are IEEE-754 binary64 computed at their own precision\n",
    " * (FLT_EVAL_METHOD 0: x86-64, AArch64, ARM or RISC-V with a double FPU) and a*b + c is not\n",
    " * fused (GCC: -ffp-contract=off, the default with -std=c99; other compilers: the pragma below).\n",
);

/// The include guard, the includes and the pragma that keeps `a*b + c` unfused, which follow
/// every header's comment block; `math_doc` says what the header takes from `<math.h>`.
pub(super) fn guard(math_doc: &str) -> String {
    format!(
        "#ifndef DRIFTLAB_CALIBRATION_H\n#define DRIFTLAB_CALIBRATION_H\n\n\
         #include <math.h>   /* {math_doc} */\n#include <stddef.h> /* size_t, NULL */\n\n\
         #if defined(__clang__) || !defined(__GNUC__)\n#pragma STDC FP_CONTRACT OFF\n#endif\n"
    )
}

/// The single-axis header's corrector: the temperature's history (the runtime's) inside the
/// state, calling the model's `driftlab_predict` and `driftlab_is_outside`.
fn corrector(h: &mut String, t: TemperatureHistory) -> Result<(), ExportError> {
    h.push_str(
        "\n/* ---- The streaming corrector ----------------------------------------------------------- */\n",
    );
    t.constants(h, "driftlab_push_at: a longer step is a dropout")?;
    h.push_str("\n/* Everything the corrector remembers. */\ntypedef struct {\n");
    h.push_str(&section("temperature_fields"));
    h.push_str(
        r#"    double last_time_s;                         /* driftlab_push_at: the last sample's time, s */
    int has_time;                               /* driftlab_push_at: 0 until the first sample */
} driftlab_state;

/* One corrected sample, in full. */
typedef struct {
    double omega_cor_dph;  /* corrected rate, deg/h */
    double omega_pred_dph; /* predicted thermal drift, deg/h */
    double tdot_c_s;       /* Tdot used, degC/s (0 while not yet known) */
    double tddot_c_s2;     /* Tddot used, degC/s^2 (0 while not yet known) */
    int regime;            /* DRIFTLAB_REGIME_* */
    int outside;           /* 1: beyond the calibrated ranges (edge values held) */
} driftlab_sample;

/* Starts with no history. */
static inline void driftlab_init(driftlab_state *st)
{
"#,
    );
    h.push_str(&section_in_state("temperature_init"));
    h.push_str(
        r#"    st->last_time_s = 0.0;
    st->has_time = 0;
}

/* Forgets all history (after a power cycle, a gap in the data or an invalid temperature). */
static inline void driftlab_reset(driftlab_state *st)
{
    driftlab_init(st);
}

/* Feeds one sample (rate in deg/h, temperature in degC) and returns the corrected rate, deg/h;
 * the details go to *out when out is not NULL. */
static inline double driftlab_push_detail(driftlab_state *st, double omega_dph, double temp_c,
                                          driftlab_sample *out)
{
"#,
    );
    h.push_str(&section_in_state("temperature_rings"));
    h.push_str("    double ts, tdot, tddot, pred;\n    int regime;\n\n");
    h.push_str(&section_in_state("temperature_push"));
    h.push_str(
        r#"
    /* The model takes the raw temperature for K0, and the rates. */
    pred = driftlab_predict(temp_c, tdot, tddot, &regime);
    if (out != NULL) {
        out->omega_cor_dph = omega_dph - pred;
        out->omega_pred_dph = pred;
        out->tdot_c_s = tdot;
        out->tddot_c_s2 = tddot;
        out->regime = regime;
        out->outside = driftlab_is_outside(temp_c, tdot, tddot, regime);
    }
    return omega_dph - pred;
}

/* Feeds one sample (rate in deg/h, temperature in degC) and returns the corrected rate, deg/h. */
static inline double driftlab_push(driftlab_state *st, double omega_dph, double temp_c)
{
    return driftlab_push_detail(st, omega_dph, temp_c, NULL);
}

/* As driftlab_push_detail, for samples with their time (s): a step of more than
 * DRIFTLAB_GAP_FACTOR periods since the last sample is a dropout, after which the history
 * starts afresh from this sample, as driftlab restarts each segment of a log. */
static inline double driftlab_push_at_detail(driftlab_state *st, double time_s, double omega_dph,
                                             double temp_c, driftlab_sample *out)
{
    if (st->has_time && time_s - st->last_time_s > DRIFTLAB_GAP_FACTOR * DRIFTLAB_DT_S) {
        driftlab_reset(st);
    }
    st->last_time_s = time_s;
    st->has_time = 1;
    return driftlab_push_detail(st, omega_dph, temp_c, out);
}

/* As driftlab_push, for samples with their time (s); see driftlab_push_at_detail. */
static inline double driftlab_push_at(driftlab_state *st, double time_s, double omega_dph,
                                      double temp_c)
{
    return driftlab_push_at_detail(st, time_s, omega_dph, temp_c, NULL);
}
"#,
    );
    Ok(())
}

/// The comment block naming every axis, the include guard, the includes and the axis indices.
fn unit_preamble(h: &mut String, unit: &UnitCalibration, axes: &[Axis<'_>], shared: bool) {
    let first = axes[0].model;
    let src = first.source();
    let mut list = String::new();
    for (k, a) in axes.iter().enumerate() {
        let model = match a.model {
            DriftModel::Vakhrameev(_) => "vakhrameev (the shared T history)".to_string(),
            DriftModel::Regression(r) => format!(
                "regression \"{}\" (its own corrector, driftlab_{}_state)",
                comment_text(&r.model.spec.name),
                a.ident
            ),
        };
        let gyro = if a.model.gyro_id().is_empty() {
            String::new()
        } else {
            format!(", gyro {}", comment_text(a.model.gyro_id()))
        };
        let kind = match a.kind {
            crate::log::AxisKind::Gyro => "",
            crate::log::AxisKind::Accel => " (accelerometer, m/s^2: its slot of the rate arrays)",
        };
        list.push_str(&format!(
            " *   [{k}] {name}{kind}: {model}{gyro}\n",
            name = comment_text(a.name)
        ));
    }
    let t_doc = if shared {
        concat!(
            " * The Vakhrameev axes share the housing's temperature: T is smoothed and differentiated\n",
            " * once for all of them (a causal moving average, then 3-point backward differences), and\n",
            " * each axis predicts\n",
            " *     Omega_pred = K0(T) + K1(Tdot)*Tdot + K2(Tddot)*Tddot\n",
            " * from its own curves, named by the axis (driftlab_<axis>_k0, ...). A step of more than\n",
            " * DRIFTLAB_GAP_FACTOR periods in time_s is a dropout: the T history restarts from that\n",
            " * sample, as driftlab restarts each segment of a log.\n",
        )
    } else {
        ""
    };
    let u = match first {
        DriftModel::Vakhrameev(c) => format!(
            " * Units: time {}, rate {}, temperature {}.\n",
            comment_text(&c.units.time),
            comment_text(&c.units.rate),
            comment_text(&c.units.temperature)
        ),
        DriftModel::Regression(_) => " * Units: time s, rate deg/h, temperature degC.\n".into(),
    };
    let created = match first {
        DriftModel::Vakhrameev(c) => &c.created,
        DriftModel::Regression(r) => &r.created,
    };
    let names: Vec<String> = axes.iter().map(|a| c_string(a.name)).collect();
    let indices: String = axes
        .iter()
        .enumerate()
        .map(|(k, a)| {
            format!(
                "#define DRIFTLAB_AXIS_{} {k}\n",
                a.ident.to_ascii_uppercase()
            )
        })
        .collect();
    h.push_str(&format!(
        r#"/*
 * Thermal-drift calibration of a unit of {n} {what} ({axis_list}), for the unit's processor.
 * Written by driftlab {version} (`driftlab export --format c-header`); do not edit by hand:
 * export again from the calibration file instead.
 *
 * Axes, in the order of the arrays driftlab_push reads and writes:
{list} *
{source_doc} *
{u} *
 * Correction, sample by sample, using only past samples, of every axis at once:
 *     Omega_cor[k] = Omega_raw[k] - Omega_pred[k]
{t_doc} * A regression axis keeps its own corrector inside the state (the same code as that axis's
 * own header, its names under the axis's).
 *
 * Use: call driftlab_init once, then driftlab_push for every sample with its time, at the
 * sampling period the calibration was made at; call driftlab_reset after a power cycle.
 *
 *     #include "this_header.h"
 *     static driftlab_state unit;
 *     double omega_raw_dph[DRIFTLAB_N_AXES], omega_cor_dph[DRIFTLAB_N_AXES];
 *     driftlab_init(&unit);
 *     ... every sample:
 *     driftlab_push(&unit, time_s, omega_raw_dph, temp_c, omega_cor_dph);
 *
 * Everything below is static const or static inline: include this header from any number of C
 * files, nothing to link (but libm for a regression axis with a selfheat term or a
 * temperature-dependent lag). C99, doubles, no malloc. The state is one struct of
 * sizeof(driftlab_state) bytes, sized at compile time.
 *
 * This code repeats driftlab's arithmetic operation for operation, so it corrects every axis
 * bit for bit as driftlab does where doubles are IEEE-754 binary64 computed at their own
 * precision (FLT_EVAL_METHOD 0: x86-64, AArch64, ARM or RISC-V with a double FPU) and a*b + c
 * is not fused (GCC: -ffp-contract=off, the default with -std=c99; other compilers: the pragma
 * below).
 */
{guard}
#define DRIFTLAB_CREATED {created_c}

/* The axes: how many, their names, and each one's index in the rate arrays. */
#define DRIFTLAB_N_AXES {n}
#define DRIFTLAB_AXIS_NAMES {{ {names} }}
{indices}"#,
        n = unit.axes.len(),
        what = match unit
            .axes
            .iter()
            .filter(|a| a.kind == crate::log::AxisKind::Accel)
            .count()
        {
            0 => "gyro axes".to_string(),
            accel => format!(
                "axes, {} of a gyro and {accel} of an accelerometer,",
                unit.axes.len() - accel
            ),
        },
        axis_list = comment_text(&unit.axis_names().join(", ")),
        version = env!("CARGO_PKG_VERSION"),
        source_doc = source_doc(src, created),
        created_c = c_string(created),
        names = names.join(", "),
        guard = guard("isfinite (a macro), and what a regression axis calls"),
    ));
}

/// The shared temperature history, the unit's state and its push.
fn unit_corrector(
    h: &mut String,
    axes: &[Axis<'_>],
    shared: Option<TemperatureHistory>,
) -> Result<(), ExportError> {
    h.push_str(
        "\n/* ---- The unit's streaming corrector --------------------------------------------- */\n",
    );
    if let Some(t) = shared {
        t.constants(h, "a longer step is a dropout")?;
        h.push_str(&section("temperature"));
    }
    // The state.
    let mut members = String::new();
    if shared.is_some() {
        members.push_str(
            "    driftlab_temperature temperature; /* T's history, shared by the Vakhrameev axes */\n    \
             double last_time_s;               /* the last sample's time, s */\n    \
             int has_time;                     /* 0 until the first sample */\n",
        );
    }
    let mut init = String::new();
    if shared.is_some() {
        init.push_str(
            "    driftlab_temperature_init(&st->temperature);\n    st->last_time_s = 0.0;\n    \
             st->has_time = 0;\n",
        );
    }
    let mut body = String::new();
    for (k, a) in axes.iter().enumerate() {
        let id = &a.ident;
        match a.model {
            DriftModel::Vakhrameev(_) => body.push_str(&format!(
                r#"
    /* Axis {name}: its curves at the shared T and rates. */
    pred = driftlab_{id}_predict(temp_c, tdot, tddot, &regime);
    omega_cor_dph[{k}] = omega_dph[{k}] - pred;
    if (out != NULL) {{
        out[{k}].omega_cor_dph = omega_dph[{k}] - pred;
        out[{k}].omega_pred_dph = pred;
        out[{k}].tdot_c_s = tdot;
        out[{k}].tddot_c_s2 = tddot;
        out[{k}].regime = regime;
        out[{k}].outside = driftlab_{id}_is_outside(temp_c, tdot, tddot, regime);
    }}
"#,
                name = comment_text(a.name),
            )),
            DriftModel::Regression(_) => {
                members.push_str(&format!(
                    "    driftlab_{id}_state driftlab_{id};   /* axis {}: its own corrector */\n",
                    comment_text(a.name)
                ));
                init.push_str(&format!("    driftlab_{id}_init(&st->driftlab_{id});\n"));
                body.push_str(&format!(
                    r#"
    /* Axis {name}: its own corrector (it reads no second sensor and no channel). */
    {{
        driftlab_{id}_sample s;
        omega_cor_dph[{k}] =
            driftlab_{id}_push_detail(&st->driftlab_{id}, time_s, omega_dph[{k}], temp_c, 0.0, NULL, &s);
        if (out != NULL) {{
            out[{k}].omega_cor_dph = s.omega_cor_dph;
            out[{k}].omega_pred_dph = s.omega_pred_dph;
            out[{k}].tdot_c_s = s.tdot_c_s;
            out[{k}].tddot_c_s2 = s.tddot_c_s2;
            out[{k}].regime = s.regime;
            out[{k}].outside = s.outside;
        }}
    }}
"#,
                    name = comment_text(a.name),
                ));
            }
        }
    }
    let shared_push = if shared.is_some() {
        r#"    double tdot, tddot, pred;
    int regime;

    /* A step of more than DRIFTLAB_GAP_FACTOR periods is a dropout: T's history starts afresh
     * from this sample, as driftlab restarts each segment of a log. */
    if (st->has_time && time_s - st->last_time_s > DRIFTLAB_GAP_FACTOR * DRIFTLAB_DT_S) {
        driftlab_temperature_init(&st->temperature);
    }
    st->last_time_s = time_s;
    st->has_time = 1;
    driftlab_temperature_push(&st->temperature, temp_c, &tdot, &tddot);
"#
    } else {
        ""
    };
    h.push_str(&format!(
        r#"
/* Every axis's corrected sample, in full. */
typedef struct {{
    double omega_cor_dph;  /* corrected rate, deg/h */
    double omega_pred_dph; /* predicted thermal drift, deg/h */
    double tdot_c_s;       /* Tdot used, degC/s (0 while not yet known) */
    double tddot_c_s2;     /* Tddot used, degC/s^2 (0 while not yet known) */
    int regime;            /* DRIFTLAB_REGIME_* */
    int outside;           /* 1: beyond the axis's calibrated ranges (edge values held) */
}} driftlab_sample;

/* Everything the unit's corrector remembers. */
typedef struct {{
{members}}} driftlab_state;

/* Starts with no history. */
static inline void driftlab_init(driftlab_state *st)
{{
{init}}}

/* Forgets all history (after a power cycle). */
static inline void driftlab_reset(driftlab_state *st)
{{
    driftlab_init(st);
}}

/* Feeds one sample: its time (s), every axis's rate (deg/h, in the order of DRIFTLAB_AXIS_*)
 * and the temperature (degC); writes every axis's corrected rate (deg/h) to omega_cor_dph, and
 * the details to out[0 .. DRIFTLAB_N_AXES - 1] when out is not NULL. */
static inline void driftlab_push_detail(driftlab_state *st, double time_s,
                                        const double omega_dph[DRIFTLAB_N_AXES], double temp_c,
                                        double omega_cor_dph[DRIFTLAB_N_AXES],
                                        driftlab_sample *out)
{{
{shared_push}{body}}}

/* As driftlab_push_detail, without the details. */
static inline void driftlab_push(driftlab_state *st, double time_s,
                                 const double omega_dph[DRIFTLAB_N_AXES], double temp_c,
                                 double omega_cor_dph[DRIFTLAB_N_AXES])
{{
    driftlab_push_detail(st, time_s, omega_dph, temp_c, omega_cor_dph, NULL);
}}
"#
    ));
    Ok(())
}

/// A string as a C string literal: printable ASCII as is, `\`, `"` and `?` (trigraphs) escaped,
/// every other byte in octal; at most 200 bytes of the input.
pub(super) fn c_string(s: &str) -> String {
    let mut out = String::from("\"");
    for &b in s.as_bytes().iter().take(200) {
        match b {
            b'\\' | b'"' | b'?' => {
                out.push('\\');
                out.push(b as char);
            }
            0x20..=0x7e => out.push(b as char),
            _ => out.push_str(&format!("\\{b:03o}")),
        }
    }
    out.push('"');
    out
}
