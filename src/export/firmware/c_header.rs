//! The calibration as one self-contained C99 header: constants, a curve evaluator and the
//! streaming corrector, all `static const` or `static inline`.
//!
//! Why `static inline` and not an implementation block behind a macro: the header can be
//! included from any number of C files without choosing which one holds the code, nothing has to
//! be linked, and a compiler drops whatever is unused. The cost is a copy of the (small) tables in
//! each file that includes it.
//!
//! The C repeats driftlab's arithmetic operation for operation, so that it agrees bit for bit:
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
//! A regression model gets its own header ([`super::c_regression`]): a preamble of the same shape,
//! its terms as an array of codes evaluated by one `switch`, and a port of
//! [`crate::models::regression::RegressionCorrector::push`] (lag, smoothing, differences, τd(T), the
//! delayed read, clamping, the row and the dot product from −0, as `f64::sum` starts).
//!
//! One difference of form: driftlab counts samples without bound, the C keeps the ring slot
//! and a count that stops at `4s`, so a processor running for years never wraps a counter.
//!
//! Bit-for-bit agreement holds where C doubles are IEEE-754 binary64 evaluated at their own
//! precision (`FLT_EVAL_METHOD == 0`: x86-64, AArch64, ARM and RISC-V with a double FPU) and
//! `a*b + c` is not fused into one rounding (GCC: `-ffp-contract=off`, the default with
//! `-std=c99`; other compilers: the `FP_CONTRACT` pragma the header sets).

pub(super) use super::c_curves::{array, curve, curve_evaluator};
use super::{ExportError, MAX_RING_SAMPLES, comment_text, number};
use crate::models::vakhrameev::Calibration;

/// The header for `cal`, sampled at the calibration log's step.
pub fn c_header(cal: &Calibration) -> Result<String, ExportError> {
    let mut h = String::new();
    preamble(&mut h, cal, "vakhrameev");
    curve_evaluator(&mut h);
    vakhrameev(&mut h, cal)?;
    corrector(&mut h, cal)?;
    h.push_str("\n#endif /* DRIFTLAB_CALIBRATION_H */\n");
    Ok(h)
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

/// The comment block naming gyro, source log and units, the include guard and the includes.
fn preamble(h: &mut String, cal: &Calibration, model: &str) {
    let src = &cal.source;
    let sha = if src.sha256.is_empty() {
        "(not recorded)".to_string()
    } else {
        comment_text(&src.sha256)
    };
    let u = &cal.units;
    h.push_str(&format!(
        r#"/*
 * Thermal-drift calibration of gyro {gyro}, for the gyro's processor.
 * Written by driftlab {version} (`driftlab export --format c-header`); do not edit by hand:
 * export again from the calibration file instead.
 *
 *   model:     {model}
 *   gyro id:   {gyro}
 *   source:    {source} ({samples} samples, {duration} s)
 *   sha256:    {sha}
 *   created:   {created}
 *
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
 * This code repeats driftlab's arithmetic operation for operation, so it corrects a log bit for
 * bit as driftlab does where doubles are IEEE-754 binary64 computed at their own precision
 * (FLT_EVAL_METHOD 0: x86-64, AArch64, ARM or RISC-V with a double FPU) and a*b + c is not
 * fused (GCC: -ffp-contract=off, the default with -std=c99; other compilers: the pragma below).
 */
#ifndef DRIFTLAB_CALIBRATION_H
#define DRIFTLAB_CALIBRATION_H

#include <math.h>   /* isfinite (a macro: no libm function is called) */
#include <stddef.h> /* size_t, NULL */

#if defined(__clang__) || !defined(__GNUC__)
#pragma STDC FP_CONTRACT OFF
#endif

#define DRIFTLAB_GYRO_ID {gyro_c}
#define DRIFTLAB_CREATED {created_c}
"#,
        gyro = comment_text(&cal.gyro_id),
        version = env!("CARGO_PKG_VERSION"),
        source = comment_text(&src.name),
        samples = src.samples,
        duration = src.duration_s,
        created = comment_text(&cal.created),
        ut = comment_text(&u.time),
        ur = comment_text(&u.rate),
        utemp = comment_text(&u.temperature),
        utd = comment_text(&u.tdot),
        utdd = comment_text(&u.tddot),
        uk1 = comment_text(&u.k1),
        uk2 = comment_text(&u.k2),
        gyro_c = c_string(&cal.gyro_id),
        created_c = c_string(&cal.created),
    ));
}

/// The Vakhrameev model (docs/method.md §1): its five curves, dead-bands, and the two functions
/// every model provides to the corrector, `driftlab_predict` and `driftlab_is_outside`.
///
/// A regression model has a header of its own ([`super::c_regression`]) with its own preamble,
/// constants and corrector; only the number formatting and the ring limits are shared.
pub fn vakhrameev(h: &mut String, cal: &Calibration) -> Result<(), ExportError> {
    let names = ModelNames::single();
    regimes(h);
    model_constants(h, cal, &names)?;
    regime_fn(h);
    predict_fn(h, &names);
    beyond_fn(h);
    is_outside_fn(h, &names);
    Ok(())
}

/// What the identifiers of one Vakhrameev model start with: `driftlab` and `DRIFTLAB` for the
/// model of a single-axis header, `driftlab_gx` and `DRIFTLAB_GX` for axis `gx` of a unit's
/// header, where every axis has its own curves beside the others'.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct ModelNames {
    /// Prefix of the curves and functions (`driftlab_gx`).
    pub lower: String,
    /// Prefix of the macros (`DRIFTLAB_GX`).
    pub upper: String,
    /// What the curves' comments and error messages start with (`axis gx: `), empty for a
    /// single axis.
    pub title: String,
}

impl ModelNames {
    /// The names of a single-axis header.
    pub fn single() -> ModelNames {
        ModelNames {
            lower: "driftlab".into(),
            upper: "DRIFTLAB".into(),
            title: String::new(),
        }
    }

    /// `text` with the single-axis header's names of this model's curves and functions put
    /// under this prefix (the identity for [`ModelNames::single`]).
    fn rename(&self, text: &str, names: &[&str]) -> String {
        let mut out = text.to_string();
        for n in names {
            out = out.replace(&format!("driftlab_{n}"), &format!("{}_{n}", self.lower));
        }
        out
    }
}

/// The section's title and the regime codes, shared by every Vakhrameev model of a header.
pub(super) fn regimes(h: &mut String) {
    h.push_str(
        r#"
/* ---- The Vakhrameev model: Omega_pred = K0(T) + K1(Tdot)*Tdot + K2(Tddot)*Tddot ---------- */

/* Regimes, from the sign of Tdot*Tddot. */
#define DRIFTLAB_REGIME_STATIC 0 /* Tdot*Tddot = 0: K0 only */
#define DRIFTLAB_REGIME_PLUS 1   /* Tdot*Tddot > 0, thermal acceleration: K1+, K2+ */
#define DRIFTLAB_REGIME_MINUS 2  /* Tdot*Tddot < 0, thermal deceleration: K1-, K2- */
"#,
    );
}

/// One model's dead-bands and five curves, under `names`.
pub(super) fn model_constants(
    h: &mut String,
    cal: &Calibration,
    names: &ModelNames,
) -> Result<(), ExportError> {
    let r = &cal.resolved;
    let u = &cal.units;
    let upper = &names.upper;
    h.push_str(&format!(
        r#"
/* {title_dead}ead-bands of the fit, for the record: points with |Tdot| (|Tddot|) below them were left out
 * of the K1 (K2) fits. The correction does not use them. */
#define {upper}_DEADBAND_TDOT {db1}   /* {utd} */
#define {upper}_DEADBAND_TDDOT {db2} /* {utdd} */
"#,
        title_dead = if names.title.is_empty() {
            "D".to_string()
        } else {
            format!("{}d", comment_text(&names.title))
        },
        db1 = number(r.deadband_tdot, &format!("{}the Tdot dead-band", names.title))?,
        db2 = number(r.deadband_tddot, &format!("{}the Tddot dead-band", names.title))?,
        utd = comment_text(&u.tdot),
        utdd = comment_text(&u.tddot),
    ));
    let (temp, tdot, tddot) = (
        ("T", comment_text(&u.temperature)),
        ("Tdot", comment_text(&u.tdot)),
        ("Tddot", comment_text(&u.tddot)),
    );
    let (k0u, k1u, k2u) = (
        comment_text(&u.rate),
        comment_text(&u.k1),
        comment_text(&u.k2),
    );
    let curves = [
        ("k0", "K0(T)", (temp.0, &temp.1), &k0u, &cal.k0),
        (
            "k1_plus",
            "K1+(Tdot)",
            (tdot.0, &tdot.1),
            &k1u,
            &cal.k1_plus,
        ),
        (
            "k1_minus",
            "K1-(Tdot)",
            (tdot.0, &tdot.1),
            &k1u,
            &cal.k1_minus,
        ),
        (
            "k2_plus",
            "K2+(Tddot)",
            (tddot.0, &tddot.1),
            &k2u,
            &cal.k2_plus,
        ),
        (
            "k2_minus",
            "K2-(Tddot)",
            (tddot.0, &tddot.1),
            &k2u,
            &cal.k2_minus,
        ),
    ];
    for (name, title, (arg, arg_unit), unit, a) in curves {
        let name = format!("{}_{name}", names.lower);
        let title = format!("{}{title}", comment_text(&names.title));
        curve(h, &name, &title, (arg, arg_unit.as_str()), unit, a)?;
    }
    Ok(())
}

/// `driftlab_regime`, shared by every Vakhrameev model of a header.
pub(super) fn regime_fn(h: &mut String) {
    h.push_str(
        r#"
/* The regime of a sample with these rates. */
static inline int driftlab_regime(double tdot_c_s, double tddot_c_s2)
{
    double p = tdot_c_s * tddot_c_s2;
    if (p > 0.0) {
        return DRIFTLAB_REGIME_PLUS;
    }
    if (p < 0.0) {
        return DRIFTLAB_REGIME_MINUS;
    }
    return DRIFTLAB_REGIME_STATIC;
}
"#,
    );
}

/// One model's `driftlab_predict`, under `names`.
pub(super) fn predict_fn(h: &mut String, names: &ModelNames) {
    let text = r#"
/* Predicted thermal drift, deg/h, of a sample at temperature temp_c with these rates; its regime
 * goes to *regime when regime is not NULL. */
static inline double driftlab_predict(double temp_c, double tdot_c_s, double tddot_c_s2,
                                      int *regime)
{
    int r = driftlab_regime(tdot_c_s, tddot_c_s2);
    double k0 = driftlab_curve_eval(&driftlab_k0, temp_c);
    double pred = k0;
    if (r == DRIFTLAB_REGIME_PLUS) {
        pred = k0 + driftlab_curve_eval(&driftlab_k1_plus, tdot_c_s) * tdot_c_s +
               driftlab_curve_eval(&driftlab_k2_plus, tddot_c_s2) * tddot_c_s2;
    } else if (r == DRIFTLAB_REGIME_MINUS) {
        pred = k0 + driftlab_curve_eval(&driftlab_k1_minus, tdot_c_s) * tdot_c_s +
               driftlab_curve_eval(&driftlab_k2_minus, tddot_c_s2) * tddot_c_s2;
    }
    if (regime != NULL) {
        *regime = r;
    }
    return pred;
}
"#;
    h.push_str(&names.rename(text, &["predict", "k0", "k1_", "k2_"]));
}

/// `driftlab_beyond`, shared by every Vakhrameev model of a header.
pub(super) fn beyond_fn(h: &mut String) {
    h.push_str(
        r#"
static inline int driftlab_beyond(const driftlab_curve *c, double x)
{
    return x < c->x_min || x > c->x_max;
}
"#,
    );
}

/// One model's `driftlab_is_outside`, under `names`.
pub(super) fn is_outside_fn(h: &mut String, names: &ModelNames) {
    let text = r#"
/* 1 when a sample lies beyond what the calibration saw: T outside K0's range, or a rate
 * outside the range of a curve its regime uses (the curve's edge value was held there). */
static inline int driftlab_is_outside(double temp_c, double tdot_c_s, double tddot_c_s2,
                                      int regime)
{
    if (driftlab_beyond(&driftlab_k0, temp_c)) {
        return 1;
    }
    if (regime == DRIFTLAB_REGIME_PLUS) {
        return driftlab_beyond(&driftlab_k1_plus, tdot_c_s) ||
               driftlab_beyond(&driftlab_k2_plus, tddot_c_s2);
    }
    if (regime == DRIFTLAB_REGIME_MINUS) {
        return driftlab_beyond(&driftlab_k1_minus, tdot_c_s) ||
               driftlab_beyond(&driftlab_k2_minus, tddot_c_s2);
    }
    return 0;
}
"#;
    h.push_str(&names.rename(text, &["is_outside", "k0", "k1_", "k2_"]));
}

/// The streaming corrector: T smoothing, the backward differences and the state, calling the
/// model's `driftlab_predict` and `driftlab_is_outside`.
fn corrector(h: &mut String, cal: &Calibration) -> Result<(), ExportError> {
    let dt = cal.resolved.dt_s;
    let steps = cal.steps_for(dt);
    // As StreamCorrector::new: a window or step of 0 is taken as 1.
    let (smooth, step) = (steps.smooth.max(1), steps.step.max(1));
    if smooth > MAX_RING_SAMPLES || step > MAX_RING_SAMPLES {
        return Err(ExportError::Calibration(format!(
            "a smoothing window of {smooth} samples and a derivative step of {step} samples: \
             more than the {MAX_RING_SAMPLES} samples a ring buffer is sized for"
        )));
    }
    let two_h = 2.0 * step as f64 * dt;
    h.push_str(&format!(
        r#"
/* ---- The streaming corrector ----------------------------------------------------------- */

#define DRIFTLAB_DT_S {dt}          /* the sampling period it expects, s */
#define DRIFTLAB_GAP_FACTOR {gap}    /* driftlab_push_at: a longer step is a dropout */
#define DRIFTLAB_SMOOTH_SAMPLES {smooth} /* causal moving average of T, samples */
#define DRIFTLAB_STEP_SAMPLES {step}   /* derivative step s, samples (H = s * DRIFTLAB_DT_S) */
#define DRIFTLAB_RING_SAMPLES (2 * DRIFTLAB_STEP_SAMPLES + 1)
#define DRIFTLAB_TWO_H_S {two_h}      /* 2H, s: divisor of the backward differences */
"#,
        dt = number(dt, "the sampling period")?,
        two_h = number(two_h, "2H")?,
        gap = number(crate::signal::timing::GAP_FACTOR, "the dropout factor")?,
    ));
    h.push_str(
        r#"
/* Everything the corrector remembers. */
typedef struct {
    double smooth_buf[DRIFTLAB_SMOOTH_SAMPLES]; /* the last raw temperatures, degC */
    double smooth_sum;                          /* their running sum */
    size_t smooth_next;                         /* slot of the next temperature */
    size_t smooth_filled;                       /* temperatures in the window */
    double temp_ring[DRIFTLAB_RING_SAMPLES];    /* smoothed T, degC */
    double tdot_ring[DRIFTLAB_RING_SAMPLES];    /* Tdot, degC/s */
    size_t slot;                                /* ring slot of the next sample */
    size_t history;                             /* samples seen, counted up to 4 * step */
    double last_time_s;                         /* driftlab_push_at: the last sample's time, s */
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
    size_t k;
    for (k = 0; k < DRIFTLAB_SMOOTH_SAMPLES; k++) {
        st->smooth_buf[k] = 0.0;
    }
    for (k = 0; k < DRIFTLAB_RING_SAMPLES; k++) {
        st->temp_ring[k] = 0.0;
        st->tdot_ring[k] = 0.0;
    }
    st->smooth_sum = 0.0;
    st->smooth_next = 0;
    st->smooth_filled = 0;
    st->slot = 0;
    st->history = 0;
    st->last_time_s = 0.0;
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
    const size_t s = DRIFTLAB_STEP_SAMPLES, len = DRIFTLAB_RING_SAMPLES;
    const size_t slot = st->slot;
    const size_t back1 = slot >= s ? slot - s : slot + len - s;
    const size_t back2 = slot >= 2 * s ? slot - 2 * s : slot + len - 2 * s;
    double ts, tdot, tddot, pred;
    int regime;

    /* Causal moving average of T over the last DRIFTLAB_SMOOTH_SAMPLES samples. */
    if (st->smooth_filled == DRIFTLAB_SMOOTH_SAMPLES) {
        st->smooth_sum -= st->smooth_buf[st->smooth_next];
    } else {
        st->smooth_filled++;
    }
    st->smooth_sum += temp_c;
    st->smooth_buf[st->smooth_next] = temp_c;
    st->smooth_next = st->smooth_next + 1 == DRIFTLAB_SMOOTH_SAMPLES ? 0 : st->smooth_next + 1;
    ts = st->smooth_sum / (double)st->smooth_filled;

    /* Backward differences (3x_i - 4x_{i-s} + x_{i-2s}) / (2H) of smoothed T, then of Tdot. */
    st->temp_ring[slot] = ts;
    tdot = st->history < 2 * s
               ? 0.0
               : (3.0 * ts - 4.0 * st->temp_ring[back1] + st->temp_ring[back2]) / DRIFTLAB_TWO_H_S;
    st->tdot_ring[slot] = tdot;
    tddot = st->history < 4 * s
                ? 0.0
                : (3.0 * tdot - 4.0 * st->tdot_ring[back1] + st->tdot_ring[back2]) /
                      DRIFTLAB_TWO_H_S;
    if (st->history < 4 * s) {
        st->history++;
    }
    st->slot = slot + 1 == len ? 0 : slot + 1;

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
