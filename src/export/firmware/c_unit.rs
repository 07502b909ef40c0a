//! The calibration of a whole unit (every gyro axis of one IMU) as one C99 header: one state,
//! one push taking the time, the temperature and every axis's rate, writing every axis's
//! corrected rate.
//!
//! The axes share the housing's temperature, so the header smooths and differentiates T once
//! for all of its Vakhrameev axes (their T settings are one, as
//! [`crate::models::UnitCalibration::validate`] checks), exactly as the single-axis header does
//! it for one; each axis then has its own curves, dead-bands, `driftlab_<axis>_predict` and
//! `driftlab_<axis>_is_outside` (the single-axis header's functions under the axis's name). A
//! regression axis keeps its own corrector inside the same state: the single-axis regression
//! header's constants and corrector with every `driftlab_` / `DRIFTLAB_` name put under the
//! axis's (`driftlab_gz_`), so it is the same code, operation for operation.
//!
//! Each axis is therefore corrected bit for bit as driftlab's streaming corrector of that axis
//! corrects it (the tests compile the header and compare every sample of every axis). No
//! malloc: the state is one struct sized at compile time.

use super::c_corrector::regression_corrector;
use super::c_header::{
    ModelNames, beyond_fn, c_string, curve_evaluator, is_outside_fn, model_constants, predict_fn,
    regime_fn, regimes,
};
use super::c_regression::regression_constants;
use super::{ExportError, MAX_RING_SAMPLES, comment_text, number};
use crate::models::fitted::DriftModel;
use crate::models::unit::UnitCalibration;

/// One axis of the header: its model and the names of its C identifiers.
struct Axis<'a> {
    /// The axis's name in the calibration (`gx`).
    name: &'a str,
    /// Its identifiers' part (`gx`): the name as a C identifier.
    ident: String,
    model: &'a DriftModel,
}

/// Identifiers of the header's own that an axis's part must not repeat.
const RESERVED: [&str; 12] = [
    "curve",
    "edge",
    "regime",
    "beyond",
    "state",
    "sample",
    "init",
    "reset",
    "push",
    "temperature",
    "axis",
    "kind",
];

/// The name of an axis as the part of a C identifier: ASCII letters and digits in lower case,
/// anything else `_`; a reserved word or a name already taken gets `_axis<k>` after it.
fn ident(name: &str, k: usize, taken: &[String]) -> String {
    let mut s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || RESERVED.contains(&s.as_str()) || taken.contains(&s) {
        s = format!("{s}_axis{k}");
    }
    s
}

/// The shared temperature history's settings: sampling period, smoothing window and derivative
/// step, in samples.
#[derive(Debug, Clone, Copy, PartialEq)]
struct SharedT {
    dt_s: f64,
    smooth: usize,
    step: usize,
}

/// The header for `unit`.
///
/// # Errors
/// A number a processor cannot use; Vakhrameev axes made at different sampling periods or with
/// different T settings (they cannot share one temperature history); a regression axis that
/// reads a second temperature sensor or extra channels (the unit's push takes one
/// temperature: export that axis alone).
pub fn c_unit_header(unit: &UnitCalibration) -> Result<String, ExportError> {
    unit.validate()?;
    let mut axes: Vec<Axis<'_>> = Vec::with_capacity(unit.axes.len());
    for (k, a) in unit.axes.iter().enumerate() {
        let taken: Vec<String> = axes.iter().map(|x| x.ident.clone()).collect();
        axes.push(Axis {
            name: &a.name,
            ident: ident(&a.name, k, &taken),
            model: &a.model,
        });
    }
    let shared = shared_temperature(&axes)?;
    for a in &axes {
        if let DriftModel::Regression(r) = a.model {
            r.model.validate()?;
            let (temp2, channels) = a.model.inputs();
            if temp2.is_some() || !channels.is_empty() {
                let mut reads: Vec<String> = temp2
                    .iter()
                    .map(|t| format!("the second temperature {t}"))
                    .collect();
                reads.extend(channels.iter().map(|c| format!("the channel {c}")));
                return Err(ExportError::Calibration(format!(
                    "axis {}: its regression model reads {}; the unit's header takes one \
                     temperature for all axes: export that axis alone (--axis {})",
                    a.name,
                    reads.join(", "),
                    a.name
                )));
            }
        }
    }
    let mut h = String::new();
    preamble(&mut h, unit, &axes, shared);
    if shared.is_some() {
        curve_evaluator(&mut h);
        regimes(&mut h);
        regime_fn(&mut h);
        beyond_fn(&mut h);
    }
    for a in &axes {
        model_part(&mut h, a)?;
    }
    corrector(&mut h, &axes, shared)?;
    h.push_str("\n#endif /* DRIFTLAB_CALIBRATION_H */\n");
    Ok(h)
}

/// The one temperature history of the Vakhrameev axes, `None` when there are none.
fn shared_temperature(axes: &[Axis<'_>]) -> Result<Option<SharedT>, ExportError> {
    let mut shared: Option<(SharedT, &str)> = None;
    for a in axes {
        let DriftModel::Vakhrameev(cal) = a.model else {
            continue;
        };
        let dt_s = cal.resolved.dt_s;
        let steps = cal.steps_for(dt_s);
        // As StreamCorrector::new: a window or step of 0 is taken as 1.
        let this = SharedT {
            dt_s,
            smooth: steps.smooth.max(1),
            step: steps.step.max(1),
        };
        if this.smooth > MAX_RING_SAMPLES || this.step > MAX_RING_SAMPLES {
            return Err(ExportError::Calibration(format!(
                "axis {}: a smoothing window of {} samples and a derivative step of {} samples: \
                 more than the {MAX_RING_SAMPLES} samples a ring buffer is sized for",
                a.name, this.smooth, this.step
            )));
        }
        match shared {
            None => shared = Some((this, a.name)),
            Some((first, first_name)) if first != this => {
                return Err(ExportError::Calibration(format!(
                    "axes {first_name} and {}: sampled every {} s and {} s, T smoothed over {} \
                     and {} samples, differentiated over {} and {}: the axes of a unit share one \
                     temperature history, so these must be one",
                    a.name, first.dt_s, this.dt_s, first.smooth, this.smooth, first.step, this.step
                )));
            }
            Some(_) => {}
        }
    }
    Ok(shared.map(|(s, _)| s))
}

/// The comment block naming every axis, the include guard, the includes and the axis indices.
fn preamble(h: &mut String, unit: &UnitCalibration, axes: &[Axis<'_>], shared: Option<SharedT>) {
    let first = axes[0].model;
    let src = first.source();
    let sha = if src.sha256.is_empty() {
        "(not recorded)".to_string()
    } else {
        comment_text(&src.sha256)
    };
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
        list.push_str(&format!(
            " *   [{k}] {name}: {model}{gyro}\n",
            name = comment_text(a.name)
        ));
    }
    let t_doc = match shared {
        Some(_) => concat!(
            " * The Vakhrameev axes share the housing's temperature: T is smoothed and differentiated\n",
            " * once for all of them (a causal moving average, then 3-point backward differences), and\n",
            " * each axis predicts\n",
            " *     Omega_pred = K0(T) + K1(Tdot)*Tdot + K2(Tddot)*Tddot\n",
            " * from its own curves, named by the axis (driftlab_<axis>_k0, ...). A step of more than\n",
            " * DRIFTLAB_GAP_FACTOR periods in time_s is a dropout: the T history restarts from that\n",
            " * sample, as driftlab restarts each segment of a log.\n",
        ),
        None => "",
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
 * Thermal-drift calibration of a unit of {n} gyro axes ({axis_list}), for the unit's processor.
 * Written by driftlab {version} (`driftlab export --format c-header`); do not edit by hand:
 * export again from the calibration file instead.
 *
 * Axes, in the order of the arrays driftlab_push reads and writes:
{list} *
 *   source:    {source} ({samples} samples, {duration} s)
 *   sha256:    {sha}
 *   created:   {created}
 *
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
#ifndef DRIFTLAB_CALIBRATION_H
#define DRIFTLAB_CALIBRATION_H

#include <math.h>   /* isfinite (a macro), and what a regression axis calls */
#include <stddef.h> /* size_t, NULL */

#if defined(__clang__) || !defined(__GNUC__)
#pragma STDC FP_CONTRACT OFF
#endif

#define DRIFTLAB_CREATED {created_c}

/* The axes: how many, their names, and each one's index in the rate arrays. */
#define DRIFTLAB_N_AXES {n}
#define DRIFTLAB_AXIS_NAMES {{ {names} }}
{indices}"#,
        n = unit.axes.len(),
        axis_list = comment_text(&unit.axis_names().join(", ")),
        version = env!("CARGO_PKG_VERSION"),
        source = comment_text(&src.name),
        samples = src.samples,
        duration = src.duration_s,
        created = comment_text(created),
        created_c = c_string(created),
        names = names.join(", "),
    ));
}

/// One axis's model: a Vakhrameev axis's dead-bands, curves, predict and is_outside under its
/// name; a regression axis's constants and corrector under its name.
fn model_part(h: &mut String, a: &Axis<'_>) -> Result<(), ExportError> {
    let lower = format!("driftlab_{}", a.ident);
    let upper = lower.to_ascii_uppercase();
    h.push_str(&format!(
        "\n/* ==== Axis {} ({}) {} */\n",
        comment_text(a.name),
        a.model.tag(),
        "=".repeat(60usize.saturating_sub(a.name.len()))
    ));
    match a.model {
        DriftModel::Vakhrameev(cal) => {
            let names = ModelNames {
                lower,
                upper,
                title: format!("axis {}: ", a.name),
            };
            model_constants(h, cal, &names)?;
            predict_fn(h, &names);
            is_outside_fn(h, &names);
        }
        DriftModel::Regression(r) => {
            let mut part = String::new();
            regression_constants(&mut part, &r.model)?;
            regression_corrector(&mut part, &r.model)?;
            h.push_str(
                &part
                    .replace("driftlab_", &format!("{lower}_"))
                    .replace("DRIFTLAB_", &format!("{upper}_")),
            );
        }
    }
    Ok(())
}

/// The shared temperature history, the unit's state and its push.
fn corrector(
    h: &mut String,
    axes: &[Axis<'_>],
    shared: Option<SharedT>,
) -> Result<(), ExportError> {
    h.push_str(
        "\n/* ---- The unit's streaming corrector --------------------------------------------- */\n",
    );
    if let Some(t) = shared {
        temperature_history(h, t)?;
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
                    "    driftlab_{id}_state {id};            /* axis {}: its own corrector */\n",
                    comment_text(a.name)
                ));
                init.push_str(&format!("    driftlab_{id}_init(&st->{id});\n"));
                body.push_str(&format!(
                    r#"
    /* Axis {name}: its own corrector (it reads no second sensor and no channel). */
    {{
        driftlab_{id}_sample s;
        omega_cor_dph[{k}] =
            driftlab_{id}_push_detail(&st->{id}, time_s, omega_dph[{k}], temp_c, 0.0, NULL, &s);
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

/// The temperature history every Vakhrameev axis reads: the single-axis header's smoothing and
/// differences, as a struct and a push of their own.
fn temperature_history(h: &mut String, t: SharedT) -> Result<(), ExportError> {
    let two_h = 2.0 * t.step as f64 * t.dt_s;
    h.push_str(&format!(
        r#"
#define DRIFTLAB_DT_S {dt}          /* the sampling period it expects, s */
#define DRIFTLAB_GAP_FACTOR {gap}    /* a longer step is a dropout */
#define DRIFTLAB_SMOOTH_SAMPLES {smooth} /* causal moving average of T, samples */
#define DRIFTLAB_STEP_SAMPLES {step}   /* derivative step s, samples (H = s * DRIFTLAB_DT_S) */
#define DRIFTLAB_RING_SAMPLES (2 * DRIFTLAB_STEP_SAMPLES + 1)
#define DRIFTLAB_TWO_H_S {two_h}      /* 2H, s: divisor of the backward differences */
"#,
        dt = number(t.dt_s, "the sampling period")?,
        two_h = number(two_h, "2H")?,
        gap = number(crate::signal::timing::GAP_FACTOR, "the dropout factor")?,
        smooth = t.smooth,
        step = t.step,
    ));
    h.push_str(
        r#"
/* The temperature's history: smoothed once, differentiated once, for every Vakhrameev axis. */
typedef struct {
    double smooth_buf[DRIFTLAB_SMOOTH_SAMPLES]; /* the last raw temperatures, degC */
    double smooth_sum;                          /* their running sum */
    size_t smooth_next;                         /* slot of the next temperature */
    size_t smooth_filled;                       /* temperatures in the window */
    double temp_ring[DRIFTLAB_RING_SAMPLES];    /* smoothed T, degC */
    double tdot_ring[DRIFTLAB_RING_SAMPLES];    /* Tdot, degC/s */
    size_t slot;                                /* ring slot of the next sample */
    size_t history;                             /* samples seen, counted up to 4 * step */
} driftlab_temperature;

/* Starts the temperature's history afresh. */
static inline void driftlab_temperature_init(driftlab_temperature *t)
{
    size_t k;
    for (k = 0; k < DRIFTLAB_SMOOTH_SAMPLES; k++) {
        t->smooth_buf[k] = 0.0;
    }
    for (k = 0; k < DRIFTLAB_RING_SAMPLES; k++) {
        t->temp_ring[k] = 0.0;
        t->tdot_ring[k] = 0.0;
    }
    t->smooth_sum = 0.0;
    t->smooth_next = 0;
    t->smooth_filled = 0;
    t->slot = 0;
    t->history = 0;
}

/* Feeds one temperature (degC); Tdot (degC/s) and Tddot (degC/s^2) go to *tdot_out and
 * *tddot_out (0 while the history is too short). */
static inline void driftlab_temperature_push(driftlab_temperature *t, double temp_c,
                                             double *tdot_out, double *tddot_out)
{
    const size_t s = DRIFTLAB_STEP_SAMPLES, len = DRIFTLAB_RING_SAMPLES;
    const size_t slot = t->slot;
    const size_t back1 = slot >= s ? slot - s : slot + len - s;
    const size_t back2 = slot >= 2 * s ? slot - 2 * s : slot + len - 2 * s;
    double ts, tdot, tddot;

    /* Causal moving average of T over the last DRIFTLAB_SMOOTH_SAMPLES samples. */
    if (t->smooth_filled == DRIFTLAB_SMOOTH_SAMPLES) {
        t->smooth_sum -= t->smooth_buf[t->smooth_next];
    } else {
        t->smooth_filled++;
    }
    t->smooth_sum += temp_c;
    t->smooth_buf[t->smooth_next] = temp_c;
    t->smooth_next = t->smooth_next + 1 == DRIFTLAB_SMOOTH_SAMPLES ? 0 : t->smooth_next + 1;
    ts = t->smooth_sum / (double)t->smooth_filled;

    /* Backward differences (3x_i - 4x_{i-s} + x_{i-2s}) / (2H) of smoothed T, then of Tdot. */
    t->temp_ring[slot] = ts;
    tdot = t->history < 2 * s
               ? 0.0
               : (3.0 * ts - 4.0 * t->temp_ring[back1] + t->temp_ring[back2]) / DRIFTLAB_TWO_H_S;
    t->tdot_ring[slot] = tdot;
    tddot = t->history < 4 * s
                ? 0.0
                : (3.0 * tdot - 4.0 * t->tdot_ring[back1] + t->tdot_ring[back2]) /
                      DRIFTLAB_TWO_H_S;
    if (t->history < 4 * s) {
        t->history++;
    }
    t->slot = slot + 1 == len ? 0 : slot + 1;
    *tdot_out = tdot;
    *tddot_out = tddot;
}
"#,
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_names_become_distinct_c_identifiers() {
        let mut taken = Vec::new();
        for (k, name) in ["gx", "G-Y", "gx", "state", ""].iter().enumerate() {
            let id = ident(name, k, &taken);
            taken.push(id);
        }
        assert_eq!(taken, ["gx", "g_y", "gx_axis2", "state_axis3", "_axis4"]);
    }
}
