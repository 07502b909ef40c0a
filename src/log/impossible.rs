//! Single readings no sensor gives: the garbage of a float register (1e38, near the largest
//! float32), an exponent bit flipped in a transfer. One such sample among hours of readings
//! sinks a calibration: an accelerometer's mean vector becomes 10³³ m/s² long (and is refused
//! as a unit mistake), a gyro's rate terms are fitted through 10³⁴ °/h (and the file is refused
//! after the fit). So a reading beyond what any sensor on a stand reads is a glitch, dropped as
//! a blank cell is and told, with its line or sample; but only while such readings are a few:
//! a column most of whose readings are beyond is not glitching but read in the wrong unit, or
//! is another column, and the plausibility checks say that instead of emptying it.

use crate::log::STANDARD_GRAVITY_M_S2;
use crate::log::mapping_check::MAX_PLAUSIBLE_RATE_DPH;

/// The most an accelerometer on a stand reads, m/s²: 1000 g, beyond the ±400 g of the widest
/// MEMS ranges, and 10⁴ times the gravity an IMU at rest reads.
pub const MAX_PLAUSIBLE_ACCEL_M_S2: f64 = 1000.0 * STANDARD_GRAVITY_M_S2;

/// The largest share of a column's finite readings read as glitches: past it the readings
/// beyond are the column's own (a unit or a column mistaken), not glitches.
pub const MOST_GLITCH_SHARE: f64 = 0.01;

/// The readings of a column beyond its bound, read as glitches.
#[derive(Debug, Clone, PartialEq)]
pub struct Glitches {
    /// Their places in the column, increasing.
    pub samples: Vec<usize>,
    /// The reading farthest from zero among them, for the message.
    pub worst: f64,
}

/// The readings of `values` whose magnitude is beyond `bound` (infinities included: no reading
/// is infinite), when they are at most [`MOST_GLITCH_SHARE`] of the readings that are not NaN;
/// `None` when there are none, or more.
pub fn glitches(values: impl IntoIterator<Item = f64>, bound: f64) -> Option<Glitches> {
    let mut samples = Vec::new();
    let mut worst = 0.0f64;
    let mut readings = 0usize;
    for (i, v) in values.into_iter().enumerate() {
        if v.is_nan() {
            continue;
        }
        readings += 1;
        if v.abs() > bound {
            samples.push(i);
            if v.abs() > worst.abs() {
                worst = v;
            }
        }
    }
    let few = samples.len() as f64 <= MOST_GLITCH_SHARE * readings as f64;
    (!samples.is_empty() && few).then_some(Glitches { samples, worst })
}

impl Glitches {
    /// What was done, for a problem: `N readings of "COLUMN" beyond BOUND (WORST at WHERE, the
    /// first), which no QUANTITY gives: read as glitches, their rows dropped` (or `kept as NaN`
    /// when `dropped` is false).
    pub fn message(
        &self,
        column: &str,
        limit: &str,
        first_at: &str,
        quantity: &str,
        dropped: bool,
    ) -> String {
        let n = self.samples.len();
        format!(
            "{n} reading{} of \"{}\" beyond {limit} ({} at {first_at}{}), which no {quantity} \
             gives: read as {}, {}",
            if n == 1 { "" } else { "s" },
            crate::text::escaped(column, false),
            crate::number::readable(self.worst),
            if n == 1 { "" } else { ", the first" },
            if n == 1 { "a glitch" } else { "glitches" },
            if dropped {
                if n == 1 {
                    "its row dropped"
                } else {
                    "their rows dropped"
                }
            } else {
                "kept as NaN"
            }
        )
    }
}

/// [`glitches`] of a gyro's rate, °/h, beyond [`MAX_PLAUSIBLE_RATE_DPH`].
pub fn rate_glitches(rate_dph: impl IntoIterator<Item = f64>) -> Option<Glitches> {
    glitches(rate_dph, MAX_PLAUSIBLE_RATE_DPH)
}

/// The words of the rate's bound, for [`Glitches::message`].
pub const RATE_LIMIT_WORDS: &str = "the 10⁴ °/s of any gyro";

/// The words of the acceleration's bound, for [`Glitches::message`].
pub const ACCEL_LIMIT_WORDS: &str = "the 1000 g of any accelerometer";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_few_readings_beyond_are_glitches_and_a_column_of_them_is_not() {
        // 1000 readings and a NaN, which is none.
        let mut x = vec![0.5; 1001];
        x[10] = 1e38;
        x[20] = f64::NEG_INFINITY;
        x[30] = f64::NAN;
        let g = glitches(x.iter().copied(), 100.0).unwrap();
        assert_eq!(g.samples, [10, 20]);
        assert_eq!(g.worst, f64::NEG_INFINITY);
        // Ten in 1000 is the most; eleven is the column's own.
        for k in 0..8 {
            x[100 + k] = 1e3;
        }
        assert_eq!(
            glitches(x.iter().copied(), 100.0).unwrap().samples.len(),
            10
        );
        x[200] = 1e3;
        assert_eq!(glitches(x.iter().copied(), 100.0), None);
        assert_eq!(glitches([0.5, -0.5], 100.0), None);
    }
}
