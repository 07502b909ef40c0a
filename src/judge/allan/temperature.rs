//! Whether the temperature of the samples an Allan deviation is read from held still.
//!
//! A gyro's bias follows its temperature, and a temperature that moves over hours draws its
//! drift on the long-τ end of the curve: a ramp or a slow swing rises as τ^(+½) to τ^(+1), the
//! slope of a rate random walk, and lifts the floor the bias instability is read at. On a
//! chamber run (−50 … 60 °C at 1 °C/min) the +½ line the rate random walk is read from is
//! the program's drift: the same noise with the drift left out shows no +½ region at all. The
//! deviation cannot tell the two apart; the temperature column can, so `allan` looks at it.

use serde::Serialize;

/// The most a log's temperature may span and still be read as steady, °C.
///
/// A laboratory's air conditioning holds a room within about ±1 °C, and a gyro's noise is
/// recorded at a temperature held at least that well: a span of 2 °C is what a stable lab
/// allows, and more is a temperature that moves (a chamber's program, the warm-up of
/// an IMU after power-on, a room with its heating off at night). It is also the span below
/// which driftlab refuses to calibrate against temperature (`models::MIN_TEMP_SPAN_C`): a log
/// that holds enough temperature to calibrate on holds too much to read noise from. The span
/// is taken between the 0.5th and 99.5th percentiles of the readings, so a bad read or a
/// sensor's last-digit flicker does not count.
pub const STEADY_SPAN_C: f64 = 2.0;

/// What the temperature of the analysed samples did.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TemperatureMotion {
    /// The lowest reading, °C (0.5th percentile).
    pub min_c: f64,
    /// The highest reading, °C (99.5th percentile).
    pub max_c: f64,
    /// `max_c − min_c`, °C.
    pub span_c: f64,
    /// The span beyond which the temperature moves, °C ([`STEADY_SPAN_C`]).
    pub steady_span_c: f64,
    /// Whether the span is more than [`STEADY_SPAN_C`]: the long-τ slopes then hold the
    /// thermal drift.
    pub moves: bool,
}

impl TemperatureMotion {
    /// The temperature of `temp_c` (NaN readings left out), `None` when it holds fewer than
    /// two readings.
    pub fn of(temp_c: &[f64]) -> Option<TemperatureMotion> {
        let mut t: Vec<f64> = temp_c.iter().copied().filter(|v| v.is_finite()).collect();
        if t.len() < 2 {
            return None;
        }
        t.sort_unstable_by(f64::total_cmp);
        let at = |q: f64| t[((t.len() - 1) as f64 * q).round() as usize];
        let (min_c, max_c) = (at(0.005), at(0.995));
        let span_c = max_c - min_c;
        Some(TemperatureMotion {
            min_c,
            max_c,
            span_c,
            steady_span_c: STEADY_SPAN_C,
            moves: span_c > STEADY_SPAN_C,
        })
    }

    /// What the motion does to the read-outs, for a warning: `the temperature moves by 110 °C
    /// (−50 … 60 °C), more than the 2 °C a stable lab holds: ...`.
    pub fn describe(&self) -> String {
        let r = crate::number::readable;
        format!(
            "the temperature moves by {} °C ({} … {} °C), more than the {} °C a stable lab \
             holds: the long-τ end of the curve holds the thermal drift, so the rate random walk \
             (+½ line) and the bias instability (the minimum) read off it are the drift's as \
             much as the gyro's noise; read them from a log at a steady temperature",
            r(self.span_c),
            r(self.min_c),
            r(self.max_c),
            r(self.steady_span_c)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_span_past_what_a_lab_holds_moves_and_a_bad_read_does_not() {
        // A room within ±0.9 °C, with one bad read of 85 °C: steady.
        let mut t: Vec<f64> = (0..10_000)
            .map(|i| 20.0 + 0.9 * (i as f64 / 500.0).sin())
            .collect();
        t[4000] = 85.0;
        t[10] = f64::NAN;
        let m = TemperatureMotion::of(&t).unwrap();
        assert!(!m.moves && m.span_c < 1.81, "{m:?}");
        // A warm-up of 3 °C: moves.
        let w: Vec<f64> = (0..10_000)
            .map(|i| 25.0 + 3.0 * (1.0 - (-(i as f64) / 900.0).exp()))
            .collect();
        assert!(TemperatureMotion::of(&w).unwrap().moves);
        assert_eq!(TemperatureMotion::of(&[f64::NAN, 20.0]), None);
    }
}
