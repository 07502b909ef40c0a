//! The C99 header of a regression calibration: its terms as codes, its constants, and a port
//! of the regression model's streaming corrector (see the module doc of `c_header` for what
//! bit-for-bit agreement rests on).

use super::c_header::{array, c_string};
use super::{ExportError, MAX_RING_SAMPLES, comment_text, number};
use crate::regression::{RegressionCalibration, RegressionModel, Term};

/// The header for a regression calibration: a port of
/// [`crate::regression::RegressionCorrector::push`] that repeats its arithmetic operation for
/// operation (lag, causal mean, backward differences, τd(T), the delayed read with linear
/// interpolation, clamping, the design row, the dot product summed from −0 left to right), with
/// the lag's α computed here as driftlab computes it and printed to round-trip precision.
///
/// The only libm function it calls is `exp`, for a `selfheat` term: bit-for-bit agreement then
/// also needs the C library's `exp` to give what Rust's `f64::exp` gives (on Linux both call the
/// platform's libm; the tests compile the header and compare).
pub fn regression(cal: &RegressionCalibration) -> Result<String, ExportError> {
    let m = &cal.model;
    m.validate().map_err(ExportError::Calibration)?;
    let mut h = String::new();
    regression_preamble(&mut h, cal)?;
    regression_constants(&mut h, m)?;
    regression_corrector(&mut h, m)?;
    h.push_str("\n#endif /* DRIFTLAB_CALIBRATION_H */\n");
    Ok(h)
}

/// C code of a term: its `DRIFTLAB_TERM_*` macro.
fn term_macro(t: &Term) -> &'static str {
    match t {
        Term::One => "DRIFTLAB_TERM_ONE",
        Term::T => "DRIFTLAB_TERM_T",
        Term::T2 => "DRIFTLAB_TERM_T2",
        Term::T3 => "DRIFTLAB_TERM_T3",
        Term::Tdot => "DRIFTLAB_TERM_TDOT",
        Term::Tddot => "DRIFTLAB_TERM_TDDOT",
        Term::TTdot => "DRIFTLAB_TERM_T_TDOT",
        Term::AbsTdot => "DRIFTLAB_TERM_ABS_TDOT",
        Term::SgnTdotTddot => "DRIFTLAB_TERM_SGN_TDOT_TDDOT",
        Term::TTddot => "DRIFTLAB_TERM_T_TDDOT",
        Term::Dt => "DRIFTLAB_TERM_DT",
        Term::Dt2 => "DRIFTLAB_TERM_DT2",
        Term::SelfHeating => "DRIFTLAB_TERM_SELFHEAT",
        Term::Channel { power: 2, .. } => "DRIFTLAB_TERM_CHANNEL_SQUARED",
        Term::Channel { .. } => "DRIFTLAB_TERM_CHANNEL",
        Term::PwlT { .. } => "DRIFTLAB_TERM_PWL_T",
    }
}

fn regression_preamble(h: &mut String, cal: &RegressionCalibration) -> Result<(), ExportError> {
    let m = &cal.model;
    let src = &cal.source;
    let gyro = if cal.gyro_id.is_empty() {
        "(no gyro id)".to_string()
    } else {
        comment_text(&cal.gyro_id)
    };
    let sha = if src.sha256.is_empty() {
        "(not recorded)".to_string()
    } else {
        comment_text(&src.sha256)
    };
    let terms: Vec<String> = m.spec.terms.iter().map(ToString::to_string).collect();
    let channels = m.channel_names();
    let channel_doc = if channels.is_empty() {
        " *     none: pass NULL.\n".to_string()
    } else {
        channels
            .iter()
            .enumerate()
            .map(|(k, n)| format!(" *     channels[{k}] = {}\n", comment_text(n)))
            .collect()
    };
    let temp2_doc = match &m.temp2 {
        Some(n) => format!(
            "the second temperature sensor, column {}, degC",
            comment_text(n)
        ),
        None => "unused by this model (pass anything, e.g. 0.0)".to_string(),
    };
    let exp_doc = if m.spec.terms.contains(&Term::SelfHeating) {
        concat!(
            " * The selfheat term calls the C library's exp (link with -lm): bit for bit driftlab's\n",
            " * where that exp rounds as the one driftlab runs with (on Linux both call the platform's\n",
            " * libm: the tests compare). With another libm, exp may differ in its last bit: require\n",
            " * agreement within 1e-12 relative there.\n",
        )
    } else {
        " * This model calls no libm function (isfinite, fabs and NAN are macros or builtins).\n"
    };
    h.push_str(&format!(
        r#"/*
 * Thermal-drift calibration of gyro {gyro}, for the gyro's processor.
 * Written by driftlab {version} (`driftlab export --format c-header`); do not edit by hand:
 * export again from the calibration file instead.
 *
 *   model:     regression "{name}"
 *   terms:     {terms}
 *   gyro id:   {gyro}
 *   source:    {source} ({samples} samples, {duration} s)
 *   sha256:    {sha}
 *   created:   {created}
 *
 * Units: time s, rate deg/h, temperatures degC, Tdot degC/s, Tddot degC/s^2; each coefficient
 * in deg/h per unit of its term.
 *
 * Correction, sample by sample, using only past samples:
 *     Omega_cor = Omega_raw - Omega_pred,   Omega_pred = sum_k coeff[k] * term_k
 * T is read through a first-order lag when DRIFTLAB_HAS_LAG, Tdot and Tddot are 3-point
 * backward differences of that T after a causal moving average, and T, Tdot, Tddot and the
 * second sensor are read tau_d(T) seconds back (linear interpolation between samples). T, dT
 * and the channels are clamped to the ranges of the fit; Tdot and Tddot are only flagged.
 *
 * Use: call driftlab_init once, then driftlab_push for every sample, at the sampling period
 * DRIFTLAB_DT_S; call driftlab_reset after a gap or a power cycle (the self-heating clock
 * restarts at the first sample after it).
 *
 *     #include "this_header.h"
 *     static driftlab_state gyro;
 *     driftlab_init(&gyro);
 *     ... every DRIFTLAB_DT_S seconds:
 *     double omega_cor_dph = driftlab_push(&gyro, time_s, omega_raw_dph, temp_c, temp2_c,
 *                                          channels);
 *
 * temp2_c is {temp2_doc}.
 * channels points to the DRIFTLAB_N_CHANNELS extra channels the model reads, in this order:
{channel_doc} *
 * Everything below is static const or static inline: include this header from any number of C
 * files, nothing to link but libm. C99, doubles, no malloc. The state is one struct sized at
 * compile time; its sample counter is 64-bit (it does not wrap in any gyro's lifetime).
 *
 * This code repeats driftlab's arithmetic operation for operation, so it corrects a log bit for
 * bit as driftlab does where doubles are IEEE-754 binary64 computed at their own precision
 * (FLT_EVAL_METHOD 0: x86-64, AArch64, ARM or RISC-V with a double FPU) and a*b + c is not
 * fused (GCC: -ffp-contract=off, the default with -std=c99; other compilers: the pragma below).
{exp_doc} */
#ifndef DRIFTLAB_CALIBRATION_H
#define DRIFTLAB_CALIBRATION_H

#include <math.h>   /* isfinite, fabs, NAN, exp */
#include <stddef.h> /* size_t, NULL */

#if defined(__clang__) || !defined(__GNUC__)
#pragma STDC FP_CONTRACT OFF
#endif

#define DRIFTLAB_GYRO_ID {gyro_c}
#define DRIFTLAB_CREATED {created_c}
#define DRIFTLAB_MODEL {name_c}
"#,
        gyro = gyro,
        version = env!("CARGO_PKG_VERSION"),
        name = comment_text(&m.spec.name),
        terms = comment_text(&terms.join(" + ")),
        source = comment_text(&src.name),
        samples = src.samples,
        duration = src.duration_s,
        created = comment_text(&cal.created),
        gyro_c = c_string(&cal.gyro_id),
        created_c = c_string(&cal.created),
        name_c = c_string(&m.spec.name),
    ));
    Ok(())
}

/// Terms, coefficients, ranges, knots, delay points and lag of the model.
fn regression_constants(h: &mut String, m: &RegressionModel) -> Result<(), ExportError> {
    let terms = &m.spec.terms;
    let n_ch = m.channel_names().len();
    h.push_str(&format!(
        r#"
/* ---- The model ------------------------------------------------------------------------- */

/* What each term is (one coefficient each, a PWL_T term one per knot). */
#define DRIFTLAB_TERM_ONE 0              /* 1 */
#define DRIFTLAB_TERM_T 1                /* T */
#define DRIFTLAB_TERM_T2 2               /* T^2 */
#define DRIFTLAB_TERM_T3 3               /* T^3 */
#define DRIFTLAB_TERM_TDOT 4             /* Tdot */
#define DRIFTLAB_TERM_TDDOT 5            /* Tddot */
#define DRIFTLAB_TERM_T_TDOT 6           /* T*Tdot */
#define DRIFTLAB_TERM_ABS_TDOT 7         /* |Tdot| */
#define DRIFTLAB_TERM_SGN_TDOT_TDDOT 8   /* sgn(Tdot)*Tddot */
#define DRIFTLAB_TERM_T_TDDOT 9          /* T*Tddot */
#define DRIFTLAB_TERM_DT 10              /* dT = T - T2 */
#define DRIFTLAB_TERM_DT2 11             /* dT^2 */
#define DRIFTLAB_TERM_SELFHEAT 12        /* 1 - exp(-t/lambda), t from the first sample */
#define DRIFTLAB_TERM_CHANNEL 13         /* an extra channel */
#define DRIFTLAB_TERM_CHANNEL_SQUARED 14 /* an extra channel squared */
#define DRIFTLAB_TERM_PWL_T 15           /* hat functions of T over DRIFTLAB_N_KNOTS knots */

#define DRIFTLAB_N_TERMS {n_terms}
#define DRIFTLAB_N_COEFFS {n_coeffs}
#define DRIFTLAB_N_CHANNELS {n_ch}
"#,
        n_terms = terms.len(),
        n_coeffs = m.coefficients.len(),
    ));
    let codes: Vec<String> = terms.iter().map(|t| term_macro(t).to_string()).collect();
    h.push_str(&format!(
        "\n/* The terms, in the order of the coefficients: {} */\nstatic const int driftlab_terms[DRIFTLAB_N_TERMS] = {{\n",
        comment_text(
            &terms
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        )
    ));
    for chunk in codes.chunks(3) {
        h.push_str(&format!("    {},\n", chunk.join(", ")));
    }
    h.push_str("};\n");
    h.push_str(
        "\n/* Coefficients, deg/h per unit of their term (one a line: name, standard error). */\n\
         static const double driftlab_coeffs[DRIFTLAB_N_COEFFS] = {\n",
    );
    for ((name, c), se) in m.names.iter().zip(&m.coefficients).zip(&m.std_errors) {
        h.push_str(&format!(
            "    {}, /* {} +- {:e} */\n",
            number(*c, &format!("coefficient {name}"))?,
            comment_text(name),
            se
        ));
    }
    h.push_str("};\n");

    let lambda = m.lambda();
    h.push_str(&format!(
        "\n/* Self-heating time constant lambda, s (1 when the model has no selfheat term). */\n\
         #define DRIFTLAB_LAMBDA_S {}\n",
        number(lambda, "lambda")?
    ));
    let knots = m.t_knots.len();
    h.push_str(&format!(
        "\n/* Knots of the piecewise-linear term in T, degC (0 when there is none). */\n\
         #define DRIFTLAB_N_KNOTS {knots}\n"
    ));
    if knots > 0 {
        array(h, "driftlab_t_knots", &m.t_knots, "a pwlT knot")?;
    }
    let d = &m.delay.points;
    h.push_str(&format!(
        "\n/* tau_d(T): piecewise-linear through (degC, s) points ascending in T, held at the end\n   \
         values; no points: no delay. */\n#define DRIFTLAB_N_DELAY_POINTS {}\n",
        d.len()
    ));
    if !d.is_empty() {
        h.push_str(&format!(
            "static const double driftlab_delay_points[{}][2] = {{\n",
            d.len()
        ));
        for p in d {
            h.push_str(&format!(
                "    {{ {}, {} }},\n",
                number(p[0], "a delay point's temperature")?,
                number(p[1], "a delay")?
            ));
        }
        h.push_str("};\n");
    }
    // As regression::Lag::new: α = 1 − e^(−dt/τ), 1 for no lag.
    let tau = m.lag_s.unwrap_or(0.0);
    let has_lag = m.lag_s.is_some_and(|l| l > 0.0);
    let alpha = if tau > 0.0 {
        1.0 - (-m.dt_s / tau).exp()
    } else {
        1.0
    };
    h.push_str(&format!(
        "\n/* First-order lag of T, dy/dt = (T - y)/tau, stepped as y += alpha*(T - y) with\n   \
         alpha = 1 - exp(-dt/tau). With DRIFTLAB_LAG_PER_C = 0, tau = {tau} s and alpha is\n   \
         computed by driftlab; otherwise tau = DRIFTLAB_LAG_TAU_S / max(1 + DRIFTLAB_LAG_PER_C\n   \
         * (T - DRIFTLAB_LAG_REF_C), 0.2) at each sample's T (the coil follows faster when\n   \
         warm) and alpha needs libm's exp. */\n\
         #define DRIFTLAB_HAS_LAG {}\n#define DRIFTLAB_LAG_ALPHA {}\n\
         #define DRIFTLAB_LAG_TAU_S {tau}\n#define DRIFTLAB_LAG_PER_C {}\n\
         #define DRIFTLAB_LAG_REF_C {}\n",
        u8::from(has_lag),
        number(alpha, "the lag's alpha")?,
        number(m.lag_per_c, "the lag's slope")?,
        number(
            crate::regression::LAG_REF_C,
            "the lag's reference temperature"
        )?,
        tau = number(tau, "the lag")?,
    ));
    let r = &m.ranges;
    h.push_str(
        "\n/* Input ranges of the fit, { min, max }: T, dT and the channels are clamped to them,\n   \
         Tdot and Tddot only flagged. */\n",
    );
    for (name, range, unit) in [
        ("temp", r.temp, "degC"),
        ("tdot", r.tdot, "degC/s"),
        ("tddot", r.tddot, "degC/s^2"),
        ("dt", r.dt, "degC"),
    ] {
        match range {
            Some([lo, hi]) => h.push_str(&format!(
                "#define DRIFTLAB_HAS_RANGE_{up} 1\nstatic const double driftlab_range_{name}[2] = {{ {}, {} }}; /* {unit} */\n",
                number(lo, &format!("the {name} range"))?,
                number(hi, &format!("the {name} range"))?,
                up = name.to_ascii_uppercase(),
            )),
            None => h.push_str(&format!(
                "#define DRIFTLAB_HAS_RANGE_{} 0 /* not read by the model */\n",
                name.to_ascii_uppercase()
            )),
        }
    }
    if n_ch > 0 {
        h.push_str("static const double driftlab_range_channels[DRIFTLAB_N_CHANNELS][2] = {\n");
        for (name, c) in m.channel_names().iter().zip(&r.channels) {
            h.push_str(&format!(
                "    {{ {}, {} }}, /* {} */\n",
                number(c[0], &format!("the range of {name}"))?,
                number(c[1], &format!("the range of {name}"))?,
                comment_text(name)
            ));
        }
        h.push_str("};\n");
    }
    Ok(())
}

/// The state, init/reset and the push functions.
fn regression_corrector(h: &mut String, m: &RegressionModel) -> Result<(), ExportError> {
    let dt = m.dt_s;
    let steps = m.steps_for(dt);
    let (smooth, step) = (steps.smooth.max(1), steps.step.max(1));
    // As RegressionCorrector::new.
    let back_f = (m.delay.max_s() / dt).ceil();
    if !(back_f.is_finite() && back_f + 2.0 <= MAX_RING_SAMPLES as f64)
        || smooth > MAX_RING_SAMPLES
        || step > MAX_RING_SAMPLES
    {
        return Err(ExportError::Calibration(format!(
            "a smoothing window of {smooth} samples, a derivative step of {step} samples and a \
             delay of {back_f} samples: more than the {MAX_RING_SAMPLES} samples a ring buffer \
             is sized for"
        )));
    }
    let back = back_f as usize + 2;
    let two_h = 2.0 * step as f64 * dt;
    let n_ch = m.channel_names().len();
    h.push_str(&format!(
        r#"
/* ---- The streaming corrector ----------------------------------------------------------- */

#define DRIFTLAB_DT_S {dt}             /* the sampling period it expects, s */
#define DRIFTLAB_SMOOTH_SAMPLES {smooth}    /* causal moving average of T, samples */
#define DRIFTLAB_STEP_SAMPLES {step}      /* derivative step s, samples (H = s * DRIFTLAB_DT_S) */
#define DRIFTLAB_TWO_H_S {two_h}         /* 2H, s: divisor of the backward differences */
#define DRIFTLAB_DELAY_SAMPLES {back}     /* history the longest delay reads: ceil(max tau_d / dt) + 2 */
#define DRIFTLAB_SMOOTHED_RING (2 * DRIFTLAB_STEP_SAMPLES + 1)
#define DRIFTLAB_TDOT_RING (DRIFTLAB_DELAY_SAMPLES > DRIFTLAB_SMOOTHED_RING ? DRIFTLAB_DELAY_SAMPLES : DRIFTLAB_SMOOTHED_RING)

/* Regimes, from the sign of Tdot*Tddot (for the record: the model does not switch on them). */
#define DRIFTLAB_REGIME_STATIC 0
#define DRIFTLAB_REGIME_PLUS 1
#define DRIFTLAB_REGIME_MINUS 2

/* Everything the corrector remembers. */
typedef struct {{
    double lag_y;                                  /* lagged T, degC */
    int lag_started;                               /* 0 until the first sample */
    double smooth_buf[DRIFTLAB_SMOOTH_SAMPLES];    /* the last temperatures, degC */
    double smooth_sum;                             /* their running sum */
    size_t smooth_next;                            /* slot of the next temperature */
    size_t smooth_filled;                          /* temperatures in the window */
    double smoothed[DRIFTLAB_SMOOTHED_RING];       /* smoothed T, degC */
    double temp[DRIFTLAB_DELAY_SAMPLES];           /* T (after the lag), degC */
    double tdot[DRIFTLAB_TDOT_RING];               /* Tdot, degC/s */
    double tddot[DRIFTLAB_DELAY_SAMPLES];          /* Tddot, degC/s^2 */
    double temp2[DRIFTLAB_DELAY_SAMPLES];          /* second sensor, degC */
    unsigned long long count;                      /* samples since init/reset */
    double t0_s;                                   /* time of the first sample, s */
}} driftlab_state;

/* One corrected sample, in full. */
typedef struct {{
    double omega_cor_dph;  /* corrected rate, deg/h */
    double omega_pred_dph; /* predicted thermal drift, deg/h */
    double tdot_c_s;       /* Tdot of this sample, degC/s (0 while not yet known) */
    double tddot_c_s2;     /* Tddot of this sample, degC/s^2 (0 while not yet known) */
    int regime;            /* DRIFTLAB_REGIME_* */
    int outside;           /* 1: an input beyond the fitted ranges (T, dT, channels held) */
}} driftlab_sample;

/* Starts with no history. */
static inline void driftlab_init(driftlab_state *st)
{{
    size_t k;
    for (k = 0; k < DRIFTLAB_SMOOTH_SAMPLES; k++) {{
        st->smooth_buf[k] = 0.0;
    }}
    for (k = 0; k < DRIFTLAB_SMOOTHED_RING; k++) {{
        st->smoothed[k] = 0.0;
    }}
    for (k = 0; k < DRIFTLAB_TDOT_RING; k++) {{
        st->tdot[k] = 0.0;
    }}
    for (k = 0; k < DRIFTLAB_DELAY_SAMPLES; k++) {{
        st->temp[k] = 0.0;
        st->tddot[k] = 0.0;
        st->temp2[k] = 0.0;
    }}
    st->lag_y = 0.0;
    st->lag_started = 0;
    st->smooth_sum = 0.0;
    st->smooth_next = 0;
    st->smooth_filled = 0;
    st->count = 0;
    st->t0_s = 0.0;
}}

/* Forgets all history (after a power cycle or a gap in the data). */
static inline void driftlab_reset(driftlab_state *st)
{{
    driftlab_init(st);
}}

/* The value of a ring at fractional sample index f (f <= the newest sample, still held). */
static inline double driftlab_ring_at(const double *ring, size_t len, double f)
{{
    unsigned long long j = (unsigned long long)f; /* f >= 0: floor */
    double w = f - (double)j;
    double a = ring[(size_t)(j % len)];
    if (w == 0.0) {{
        return a;
    }}
    return a + (ring[(size_t)((j + 1) % len)] - a) * w;
}}

/* tau_d at temperature temp_c, s. */
static inline double driftlab_delay_at(double temp_c)
{{
{delay_body}}}

/* Clamps *v to range (when hold) and says whether it was outside. */
static inline int driftlab_check(double *v, const double range[2], int hold)
{{
    if (*v < range[0]) {{
        if (hold) {{
            *v = range[0];
        }}
        return 1;
    }}
    if (*v > range[1]) {{
        if (hold) {{
            *v = range[1];
        }}
        return 1;
    }}
    return 0;
}}
"#,
        dt = number(dt, "the sampling period")?,
        two_h = number(two_h, "2H")?,
        delay_body = delay_body(m.delay.points.len()),
    ));
    h.push_str(&row_fn(m.t_knots.len()));
    // The push function.
    let mut clamp = String::new();
    for (name, range, hold) in [
        ("temp", m.ranges.temp, 1),
        ("tdot", m.ranges.tdot, 0),
        ("tddot", m.ranges.tddot, 0),
        ("dt", m.ranges.dt, 1),
    ] {
        if range.is_some() {
            clamp.push_str(&format!(
                "    outside |= driftlab_check(&x_{name}, driftlab_range_{name}, {hold});\n"
            ));
        }
    }
    let (ch_decl, ch_read) = if n_ch > 0 {
        (
            "    double ch[DRIFTLAB_N_CHANNELS];\n",
            "    for (k = 0; k < DRIFTLAB_N_CHANNELS; k++) {\n        \
             ch[k] = channels != NULL ? channels[k] : NAN;\n    }\n",
        )
    } else {
        ("    double *ch = NULL;\n", "    (void)channels;\n")
    };
    if n_ch > 0 {
        clamp.push_str(
            "    for (k = 0; k < DRIFTLAB_N_CHANNELS; k++) {\n        \
             outside |= driftlab_check(&ch[k], driftlab_range_channels[k], 1);\n    }\n",
        );
    }
    let lag = if m.lag_s.is_some_and(|l| l > 0.0) && m.lag_per_c != 0.0 {
        // As regression::Lag::push with a slope: τ at this sample's T, then α.
        "    /* T as the model reads it: through the lag, whose tau depends on T. */\n    \
         if (st->lag_started && isfinite(st->lag_y)) {\n        \
         double d = 1.0 + DRIFTLAB_LAG_PER_C * (temp_c - DRIFTLAB_LAG_REF_C);\n        \
         double alpha;\n        \
         if (!(d >= 0.2)) {\n            d = 0.2;\n        }\n        \
         alpha = 1.0 - exp(-DRIFTLAB_DT_S / (DRIFTLAB_LAG_TAU_S / d));\n        \
         temp_c = st->lag_y + alpha * (temp_c - st->lag_y);\n    }\n    \
         st->lag_y = temp_c;\n    st->lag_started = 1;\n"
    } else if m.lag_s.is_some_and(|l| l > 0.0) {
        "    /* T as the model reads it: through the lag. */\n    \
         if (st->lag_started && isfinite(st->lag_y)) {\n        \
         temp_c = st->lag_y + DRIFTLAB_LAG_ALPHA * (temp_c - st->lag_y);\n    }\n    \
         st->lag_y = temp_c;\n    st->lag_started = 1;\n"
    } else {
        ""
    };
    let dt_read = if m.temp2.is_some() {
        "    x_dt = x_temp - driftlab_ring_at(st->temp2, DRIFTLAB_DELAY_SAMPLES, f);\n"
    } else {
        "    x_dt = 0.0;\n"
    };
    h.push_str(&format!(
        r#"
/* Feeds one sample: time (s), raw rate (deg/h), temperature and second sensor (degC), and the
 * DRIFTLAB_N_CHANNELS extra channels in the order the comment at the top lists (NULL when there
 * are none). Returns the corrected rate, deg/h; the details go to *out when out is not NULL. */
static inline double driftlab_push_detail(driftlab_state *st, double time_s, double omega_dph,
                                          double temp_c, double temp2_c,
                                          const double *channels, driftlab_sample *out)
{{
    const unsigned long long i = st->count, s = DRIFTLAB_STEP_SAMPLES;
    const size_t sr = DRIFTLAB_SMOOTHED_RING, tr = DRIFTLAB_TDOT_RING;
    const size_t dr = DRIFTLAB_DELAY_SAMPLES;
    double ts, tdot, tddot, f, delay, x_temp, x_tdot, x_tddot, x_dt, pred, p;
    double row[DRIFTLAB_N_COEFFS];
{ch_decl}    int outside = 0;
    size_t k;

    if (i == 0) {{
        st->t0_s = time_s;
    }}
{lag}
    /* Causal moving average of T over the last DRIFTLAB_SMOOTH_SAMPLES samples. */
    if (st->smooth_filled == DRIFTLAB_SMOOTH_SAMPLES) {{
        st->smooth_sum -= st->smooth_buf[st->smooth_next];
    }} else {{
        st->smooth_filled++;
    }}
    st->smooth_sum += temp_c;
    st->smooth_buf[st->smooth_next] = temp_c;
    st->smooth_next = st->smooth_next + 1 == DRIFTLAB_SMOOTH_SAMPLES ? 0 : st->smooth_next + 1;
    ts = st->smooth_sum / (double)st->smooth_filled;
    st->smoothed[(size_t)(i % sr)] = ts;

    /* Backward differences (3x_i - 4x_(i-s) + x_(i-2s)) / (2H) of smoothed T, then of Tdot. */
    tdot = i < 2 * s ? 0.0
                     : (3.0 * ts - 4.0 * st->smoothed[(size_t)((i - s) % sr)] +
                        st->smoothed[(size_t)((i - 2 * s) % sr)]) /
                           DRIFTLAB_TWO_H_S;
    st->tdot[(size_t)(i % tr)] = tdot;
    tddot = i < 4 * s ? 0.0
                      : (3.0 * tdot - 4.0 * st->tdot[(size_t)((i - s) % tr)] +
                         st->tdot[(size_t)((i - 2 * s) % tr)]) /
                            DRIFTLAB_TWO_H_S;
    st->tddot[(size_t)(i % dr)] = tddot;
    st->temp[(size_t)(i % dr)] = temp_c;
    st->temp2[(size_t)(i % dr)] = temp2_c;
    st->count = i + 1;

    /* The inputs tau_d(T) seconds back, interpolated between samples. */
    delay = driftlab_delay_at(temp_c);
    f = (double)i;
    if (delay > 0.0) {{
        f = (double)i - delay / DRIFTLAB_DT_S;
        f = f > 0.0 ? f : 0.0;
    }}
    x_temp = driftlab_ring_at(st->temp, dr, f);
    x_tdot = driftlab_ring_at(st->tdot, tr, f);
    x_tddot = driftlab_ring_at(st->tddot, dr, f);
{dt_read}{ch_read}
    /* Clamp T, dT and the channels to the fitted ranges; flag Tdot and Tddot. */
{clamp}
    /* The design row, then its dot product with the coefficients, left to right. */
    driftlab_row(time_s - st->t0_s, x_temp, x_tdot, x_tddot, x_dt, ch, row);
    pred = -0.0;
    for (k = 0; k < DRIFTLAB_N_COEFFS; k++) {{
        pred = pred + row[k] * driftlab_coeffs[k];
    }}
    if (out != NULL) {{
        p = tdot * tddot;
        out->omega_cor_dph = omega_dph - pred;
        out->omega_pred_dph = pred;
        out->tdot_c_s = tdot;
        out->tddot_c_s2 = tddot;
        out->regime = p > 0.0 ? DRIFTLAB_REGIME_PLUS
                              : (p < 0.0 ? DRIFTLAB_REGIME_MINUS : DRIFTLAB_REGIME_STATIC);
        out->outside = outside;
    }}
    return omega_dph - pred;
}}

/* Feeds one sample and returns the corrected rate, deg/h (see driftlab_push_detail). */
static inline double driftlab_push(driftlab_state *st, double time_s, double omega_dph,
                                   double temp_c, double temp2_c, const double *channels)
{{
    return driftlab_push_detail(st, time_s, omega_dph, temp_c, temp2_c, channels, NULL);
}}
"#
    ));
    Ok(())
}

/// The body of `driftlab_delay_at` for `n` delay points (as [`crate::regression::Delay::at`]).
fn delay_body(n: usize) -> String {
    match n {
        0 => "    (void)temp_c;\n    return 0.0;\n".into(),
        1 => "    (void)temp_c;\n    return driftlab_delay_points[0][1];\n".into(),
        _ => r#"    const double (*p)[2] = driftlab_delay_points;
    const size_t n = DRIFTLAB_N_DELAY_POINTS;
    size_t j = 0;
    double w;
    if (temp_c <= p[0][0] || isnan(temp_c)) {
        return p[0][1];
    }
    if (temp_c >= p[n - 1][0]) {
        return p[n - 1][1];
    }
    while (j + 2 < n && p[j + 1][0] <= temp_c) {
        j++;
    }
    w = (temp_c - p[j][0]) / (p[j + 1][0] - p[j][0]);
    return p[j][1] + w * (p[j + 1][1] - p[j][1]);
"#
        .into(),
    }
}

/// The hat functions of the `pwlT` term (when there is one) and the design row (as
/// [`crate::regression::terms::row`]).
fn row_fn(knots: usize) -> String {
    let mut out = String::new();
    let pwl_case = if knots > 0 {
        out.push_str(
            r#"
/* Hat-function weights of T over the knots, written into out[0 .. DRIFTLAB_N_KNOTS - 1] (zeroed
 * by the caller); outside the knots the edge knot takes it all. */
static inline void driftlab_hats(double x, double *out)
{
    const size_t m = DRIFTLAB_N_KNOTS;
    const double *kn = driftlab_t_knots;
    size_t j = 0;
    double w;
    if (x <= kn[0] || isnan(x)) {
        out[0] = 1.0;
        return;
    }
    if (x >= kn[m - 1]) {
        out[m - 1] = 1.0;
        return;
    }
    while (j + 2 < m && kn[j + 1] <= x) {
        j++;
    }
    w = (x - kn[j]) / (kn[j + 1] - kn[j]);
    out[j] = 1.0 - w;
    out[j + 1] = w;
}
"#,
        );
        r#"        case DRIFTLAB_TERM_PWL_T: /* one hat function a knot */
            for (k = 0; k < DRIFTLAB_N_KNOTS; k++) {
                row[col + k] = 0.0;
            }
            driftlab_hats(temp, row + col);
            col += DRIFTLAB_N_KNOTS;
            break;
"#
    } else {
        ""
    };
    out.push_str(&format!(
        r#"
/* The design row of one sample: the value of each term, in coefficient order. */
static inline void driftlab_row(double t_s, double temp, double tdot, double tddot, double dt,
                                const double *ch, double row[DRIFTLAB_N_COEFFS])
{{
    size_t term, col = 0, c = 0{k_decl};
    double v;
    (void)t_s;
    (void)ch;
    for (term = 0; term < DRIFTLAB_N_TERMS; term++) {{
        switch (driftlab_terms[term]) {{
        case DRIFTLAB_TERM_ONE: row[col++] = 1.0; break;
        case DRIFTLAB_TERM_T: row[col++] = temp; break;
        case DRIFTLAB_TERM_T2: row[col++] = temp * temp; break;
        case DRIFTLAB_TERM_T3: row[col++] = temp * temp * temp; break;
        case DRIFTLAB_TERM_TDOT: row[col++] = tdot; break;
        case DRIFTLAB_TERM_TDDOT: row[col++] = tddot; break;
        case DRIFTLAB_TERM_T_TDOT: row[col++] = temp * tdot; break;
        case DRIFTLAB_TERM_ABS_TDOT: row[col++] = fabs(tdot); break;
        case DRIFTLAB_TERM_SGN_TDOT_TDDOT:
            row[col++] = tdot > 0.0 ? tddot : (tdot < 0.0 ? -tddot : 0.0);
            break;
        case DRIFTLAB_TERM_T_TDDOT: row[col++] = temp * tddot; break;
        case DRIFTLAB_TERM_DT: row[col++] = dt; break;
        case DRIFTLAB_TERM_DT2: row[col++] = dt * dt; break;
        case DRIFTLAB_TERM_SELFHEAT: row[col++] = 1.0 - exp(-t_s / DRIFTLAB_LAMBDA_S); break;
        case DRIFTLAB_TERM_CHANNEL:
        case DRIFTLAB_TERM_CHANNEL_SQUARED:
            v = ch != NULL ? ch[c] : 0.0;
            c++;
            row[col++] = driftlab_terms[term] == DRIFTLAB_TERM_CHANNEL_SQUARED ? v * v : v;
            break;
{pwl_case}        default:
            break;
        }}
    }}
}}
"#,
        k_decl = if knots > 0 { ", k" } else { "" },
    ));
    out
}
