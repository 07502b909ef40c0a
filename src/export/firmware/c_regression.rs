//! A regression model's part of a header: the single-axis header's preamble, and its terms as
//! codes with its constants; its streaming corrector is [`super::c_corrector`] (see the module
//! doc of [`super::c_header`] for what bit-for-bit agreement rests on).

use super::c_curves::array;
use super::c_header::{BIT_FOR_BIT_DOC, c_string, guard, source_doc};
use super::{AxisOfUnit, ExportError, comment_text, number};
use crate::models::regression::{RegressionCalibration, RegressionModel, Term};

/// C code of a term: its `DRIFTLAB_TERM_*` macro (a `(T-Tref)^k` term's power is in
/// `driftlab_term_powers`).
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
        Term::Tc { .. } => "DRIFTLAB_TERM_T_LESS_TREF",
    }
}

/// The comment block of a single-axis regression header (what the model is, how to call it,
/// what bit-for-bit agreement rests on; the only libm function it calls is `exp`, for a
/// `selfheat` term, so agreement there also needs the C library's `exp` to give what Rust's
/// `f64::exp` gives), the include guard and the includes.
pub(super) fn regression_preamble(
    h: &mut String,
    cal: &RegressionCalibration,
    of: Option<&AxisOfUnit<'_>>,
) -> Result<(), ExportError> {
    let m = &cal.model;
    let (axis_doc, axis_define) = super::c_header::axis_lines(of);
    let gyro = if cal.gyro_id.is_empty() {
        "(no gyro id)".to_string()
    } else {
        comment_text(&cal.gyro_id)
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
    let kind = of.map_or(crate::log::AxisKind::Gyro, |o| o.kind);
    let (what, unit) = match kind {
        crate::log::AxisKind::Gyro => ("rate", "deg/h"),
        crate::log::AxisKind::Accel => ("reading", "m/s^2"),
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
{axis_doc}{source_doc} *
 * Units: time s, {what} {unit}, temperatures degC, Tdot degC/s, Tddot degC/s^2; each
 * coefficient in {unit} per unit of its term.
 *
 * Correction, sample by sample, using only past samples:
 *     Omega_cor = Omega_raw - Omega_pred,   Omega_pred = sum_k coeff[k] * term_k
 * T is read through a first-order lag when DRIFTLAB_HAS_LAG, Tdot and Tddot are 3-point
 * backward differences of that T after a causal moving average, and T, Tdot, Tddot and the
 * second sensor are read tau_d(T) seconds back (linear interpolation between samples). T, dT
 * and the channels are clamped to the ranges of the fit; Tdot and Tddot are only flagged.
 *
 * Use: call driftlab_init once, then driftlab_push for every sample, at the sampling period
 * DRIFTLAB_DT_S. A step in time_s of more than DRIFTLAB_GAP_FACTOR periods is a dropout: the
 * filters, rates and lag start afresh by themselves, as driftlab restarts each segment of a
 * log, and the self-heating clock runs on. Call driftlab_reset after a power cycle (the
 * self-heating clock restarts at the first sample after it).
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
{bit_for_bit}{exp_doc} */
{guard}
#define DRIFTLAB_GYRO_ID {gyro_c}
#define DRIFTLAB_CREATED {created_c}
#define DRIFTLAB_MODEL {name_c}
{axis_define}"#,
        gyro = gyro,
        version = env!("CARGO_PKG_VERSION"),
        name = comment_text(&m.spec.name),
        terms = comment_text(&terms.join(" + ")),
        source_doc = source_doc(&cal.source, &cal.created),
        gyro_c = c_string(&cal.gyro_id),
        created_c = c_string(&cal.created),
        name_c = c_string(&m.spec.name),
        bit_for_bit = BIT_FOR_BIT_DOC,
        guard = guard("isfinite, fabs, NAN, exp"),
    ));
    Ok(())
}

/// Terms, coefficients, ranges, knots, delay points and lag of the model.
pub(super) fn regression_constants(
    h: &mut String,
    m: &RegressionModel,
    unit: &str,
) -> Result<(), ExportError> {
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
#define DRIFTLAB_TERM_T_LESS_TREF 16     /* (T - DRIFTLAB_T_REF_C)^k, k its driftlab_term_powers */

#define DRIFTLAB_N_TERMS {n_terms}
#define DRIFTLAB_N_COEFFS {n_coeffs}
#define DRIFTLAB_N_CHANNELS {n_ch}
"#,
        n_terms = terms.len(),
        n_coeffs = m.coefficients.len(),
    ));
    let codes: Vec<&str> = terms.iter().map(term_macro).collect();
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
    centred_constants(h, m)?;
    h.push_str(&format!(
        "\n/* Coefficients, {unit} per unit of their term (one a line: name, standard error). */\n\
         static const double driftlab_coeffs[DRIFTLAB_N_COEFFS] = {{\n",
    ));
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
            crate::models::regression::LAG_REF_C,
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

/// Tref and each term's power, for a model of `(T-Tref)^k` terms (nothing otherwise): the
/// corrector's row raises `T - DRIFTLAB_T_REF_C` to the power by repeated products, as
/// [`crate::models::regression::terms::centred_power`] does.
fn centred_constants(h: &mut String, m: &RegressionModel) -> Result<(), ExportError> {
    if !has_centred_terms(m) {
        return Ok(());
    }
    // A validated model of such terms has its Tref (`check_t_ref`); none reads as NaN, which
    // `number` refuses by name.
    let t_ref = m.t_ref_c.unwrap_or(f64::NAN);
    let powers: Vec<String> = m
        .spec
        .terms
        .iter()
        .map(|t| match t {
            Term::Tc { power } => power.to_string(),
            _ => "0".to_string(),
        })
        .collect();
    h.push_str(&format!(
        "\n/* Tref, degC: the (T-Tref)^k terms are powers of T less it. */\n\
         #define DRIFTLAB_T_REF_C {}\n\
         /* The power k of each (T-Tref)^k term, in the order of the terms (0: another term). */\n\
         static const int driftlab_term_powers[DRIFTLAB_N_TERMS] = {{ {} }};\n",
        number(t_ref, "Tref (model.t_ref_c)")?,
        powers.join(", ")
    ));
    Ok(())
}

/// Whether the model has a `(T-Tref)^k` term, and so a Tref and the powers in its header.
pub(super) fn has_centred_terms(m: &RegressionModel) -> bool {
    m.spec.terms.iter().any(|t| matches!(t, Term::Tc { .. }))
}
