//! The C runtime every generated header shares: the curve evaluator, the Vakhrameev regimes and
//! the temperature's history (causal moving average, backward differences), kept as one static
//! C source, `runtime.c`, beside the Rust that writes the tables.
//!
//! Why one C file and not strings in each writer: the code a processor runs is the same for one
//! axis and for every axis of a unit, and a port of driftlab's arithmetic is checked once (the
//! tests compile every header and compare it with driftlab sample for sample). The file is cut
//! into sections by `/*@ begin NAME */` and `/*@ end NAME */` lines; a header takes the sections
//! it needs, without the markers.

use super::{ExportError, MAX_RING_SAMPLES, number};
use crate::models::vakhrameev::Calibration;

/// The runtime's C source.
const RUNTIME_C: &str = include_str!("runtime.c");

/// A section of the runtime, without its markers or those of the sections inside it.
///
/// A missing section is a mistake in this crate's source, caught by the tests of this module.
pub(super) fn section(name: &str) -> String {
    let begin = format!("/*@ begin {name} */");
    let end = format!("/*@ end {name} */");
    let mut out = String::new();
    let mut inside = false;
    for line in RUNTIME_C.lines() {
        if line == begin {
            inside = true;
        } else if line == end {
            break;
        } else if inside && !line.starts_with("/*@ ") {
            out.push_str(line);
            out.push('\n');
        }
    }
    debug_assert!(inside, "runtime.c has no section {name}");
    out
}

/// A section written for a state named `st` instead of the history `t`: every `t->` that
/// begins a name becomes `st->`.
pub(super) fn section_in_state(name: &str) -> String {
    let text = section(name);
    let mut out = String::with_capacity(text.len() + 64);
    let mut prev: Option<char> = None;
    let mut rest = text.as_str();
    while let Some(c) = rest.chars().next() {
        let begins_name = !prev.is_some_and(|p| p.is_ascii_alphanumeric() || p == '_');
        if begins_name && rest.starts_with("t->") {
            out.push_str("st->");
            rest = &rest[3..];
            prev = Some('>');
        } else {
            out.push(c);
            rest = &rest[c.len_utf8()..];
            prev = Some(c);
        }
    }
    out
}

/// The settings of the temperature's history a header keeps: sampling period, smoothing window
/// and derivative step, in samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct TemperatureHistory {
    pub dt_s: f64,
    pub smooth: usize,
    pub step: usize,
}

impl TemperatureHistory {
    /// The history a Vakhrameev calibration's corrector keeps, sampled at its log's step; `axis`
    /// names it in the error (empty for a single axis).
    ///
    /// # Errors
    /// [`ExportError::RingTooLong`] when a window or step needs a larger ring than
    /// [`MAX_RING_SAMPLES`].
    pub fn of(cal: &Calibration, axis: &str) -> Result<TemperatureHistory, ExportError> {
        let dt_s = cal.resolved.dt_s;
        let steps = cal.steps_for(dt_s);
        // As StreamCorrector::new: a window or step of 0 is taken as 1.
        let t = TemperatureHistory {
            dt_s,
            smooth: steps.smooth.max(1),
            step: steps.step.max(1),
        };
        if t.smooth > MAX_RING_SAMPLES || t.step > MAX_RING_SAMPLES {
            return Err(ExportError::RingTooLong {
                axis: axis.to_string(),
                smooth: t.smooth,
                step: t.step,
                delay: None,
            });
        }
        Ok(t)
    }

    /// The history's constants; `gap_doc` says what DRIFTLAB_GAP_FACTOR does in this header.
    pub fn constants(&self, h: &mut String, gap_doc: &str) -> Result<(), ExportError> {
        let two_h = 2.0 * self.step as f64 * self.dt_s;
        h.push_str(&format!(
            r#"
#define DRIFTLAB_DT_S {dt}          /* the sampling period it expects, s */
#define DRIFTLAB_GAP_FACTOR {gap}    /* {gap_doc} */
#define DRIFTLAB_SMOOTH_SAMPLES {smooth} /* causal moving average of T, samples */
#define DRIFTLAB_STEP_SAMPLES {step}   /* derivative step s, samples (H = s * DRIFTLAB_DT_S) */
#define DRIFTLAB_RING_SAMPLES (2 * DRIFTLAB_STEP_SAMPLES + 1)
#define DRIFTLAB_TWO_H_S {two_h}      /* 2H, s: divisor of the backward differences */
"#,
            dt = number(self.dt_s, "the sampling period")?,
            two_h = number(two_h, "2H")?,
            gap = number(crate::signal::timing::GAP_FACTOR, "the dropout factor")?,
            smooth = self.smooth,
            step = self.step,
        ));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_section_is_there_and_markers_are_not_copied() {
        for name in [
            "curves",
            "regimes",
            "regime_fn",
            "beyond_fn",
            "temperature",
            "temperature_fields",
            "temperature_init",
            "temperature_rings",
            "temperature_push",
            "smoothing",
        ] {
            let s = section(name);
            assert!(!s.trim().is_empty(), "{name}");
            assert!(!s.contains("/*@"), "{name}");
        }
        assert!(section("temperature").contains(&section("temperature_push")));
        assert!(section("temperature_push").contains(&section("smoothing")));
    }

    #[test]
    fn the_history_moves_into_a_state_by_its_pointer_alone() {
        let s = section_in_state("temperature_push");
        assert!(s.contains("st->smooth_sum += temp_c;"));
        assert!(!s.contains(" t->") && !s.contains("(t->") && !s.contains("sst->"));
        assert_eq!(s.replace("st->", "t->"), section("temperature_push"));
    }
}
