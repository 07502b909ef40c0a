//! The streaming corrector of a regression calibration's C header: its state, init and reset,
//! the delayed read of dT/dt, the design row and the push functions, a port of
//! [`crate::models::regression::RegressionCorrector::push`] operation for operation. Apart from the
//! header's preamble and constants because it is code for the processor rather than data. Its
//! moving average of T is the runtime's (`runtime.c`); its differences read rings indexed by a
//! sample count that restarts after a dropout, so they are its own.

use super::c_regression::has_centred_terms;
use super::c_runtime::section_in_state;
use super::{ExportError, MAX_RING_SAMPLES, number};
use crate::models::regression::RegressionModel;

/// The state, init/reset and the push functions.
pub(super) fn regression_corrector(h: &mut String, m: &RegressionModel) -> Result<(), ExportError> {
    let dt = m.dt_s;
    let steps = m.steps_for(dt);
    let (smooth, step) = (steps.smooth.max(1), steps.step.max(1));
    // As RegressionCorrector::new.
    let back_f = (m.delay.max_s() / dt).ceil();
    if !(back_f.is_finite() && back_f + 2.0 <= MAX_RING_SAMPLES as f64)
        || smooth > MAX_RING_SAMPLES
        || step > MAX_RING_SAMPLES
    {
        return Err(ExportError::RingTooLong {
            axis: String::new(),
            smooth,
            step,
            delay: Some(back_f),
        });
    }
    let back = back_f as usize + 2;
    let two_h = 2.0 * step as f64 * dt;
    let n_ch = m.channel_names().len();
    h.push_str(&format!(
        r#"
/* ---- The streaming corrector ----------------------------------------------------------- */

#define DRIFTLAB_DT_S {dt}             /* the sampling period it expects, s */
#define DRIFTLAB_GAP_FACTOR {gap}        /* a step of more than this many periods is a dropout */
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
    double last_time_s;                            /* time of the last sample, s */
    int has_time;                                  /* 0 until the first sample */
    unsigned long long segment_start;              /* count at the last dropout */
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
    st->last_time_s = 0.0;
    st->has_time = 0;
    st->segment_start = 0;
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
        gap = number(crate::signal::timing::GAP_FACTOR, "the dropout factor")?,
        delay_body = delay_body(m.delay.points.len()),
    ));
    h.push_str(&row_fn(m.t_knots.len(), has_centred_terms(m)));
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
    let smoothing = section_in_state("smoothing");
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
    /* A step of more than DRIFTLAB_GAP_FACTOR periods is a dropout: T's filter, rates and lag
     * start afresh, and nothing is read from before it; the gyro stayed on, so the self-heating
     * clock runs on. */
    if (st->has_time && time_s - st->last_time_s > DRIFTLAB_GAP_FACTOR * DRIFTLAB_DT_S) {{
        st->smooth_sum = 0.0;
        st->smooth_next = 0;
        st->smooth_filled = 0;
        st->lag_started = 0;
        st->segment_start = i;
    }}
    st->last_time_s = time_s;
    st->has_time = 1;
{lag}
{smoothing}    st->smoothed[(size_t)(i % sr)] = ts;

    /* Backward differences (3x_i - 4x_(i-s) + x_(i-2s)) / (2H) of smoothed T, then of Tdot. */
    tdot = i - st->segment_start < 2 * s ? 0.0
                     : (3.0 * ts - 4.0 * st->smoothed[(size_t)((i - s) % sr)] +
                        st->smoothed[(size_t)((i - 2 * s) % sr)]) /
                           DRIFTLAB_TWO_H_S;
    st->tdot[(size_t)(i % tr)] = tdot;
    tddot = i - st->segment_start < 4 * s ? 0.0
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
        f = f > (double)st->segment_start ? f : (double)st->segment_start;
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

/// The body of `driftlab_delay_at` for `n` delay points (as [`crate::models::regression::Delay::at`]).
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
/// [`crate::models::regression::terms::row`]); `centred` when a `(T-Tref)^k` term is among
/// the terms, its power raised by repeated products as
/// [`crate::models::regression::terms::centred_power`] does.
fn row_fn(knots: usize, centred: bool) -> String {
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
    let centred_case = if centred {
        r#"        case DRIFTLAB_TERM_T_LESS_TREF: /* (T - Tref)^k as repeated products */
            d = temp - DRIFTLAB_T_REF_C;
            v = d;
            for (k = 1; k < (size_t)driftlab_term_powers[term]; k++) {
                v = v * d;
            }
            row[col++] = v;
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
    double v{d_decl};
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
{pwl_case}{centred_case}        default:
            break;
        }}
    }}
}}
"#,
        k_decl = if knots > 0 || centred { ", k" } else { "" },
        d_decl = if centred { ", d" } else { "" },
    ));
    out
}
