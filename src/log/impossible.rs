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

/// The share of a column's finite readings beyond its bound past which they are the column's
/// own (read in the wrong unit, or another quantity altogether): the plausibility checks doubt
/// its unit. Between [`MOST_GLITCH_SHARE`] and this share they are too many to be glitches
/// and too few to be the column: a stretch of garbage the engineer must cut out.
pub const MOST_OF_A_COLUMN: f64 = 0.5;

/// The readings of a column beyond its bound.
#[derive(Debug, Clone, PartialEq)]
pub struct Beyond {
    /// Their places in the column, increasing.
    pub samples: Vec<usize>,
    /// The reading farthest from zero among them, for the message.
    pub worst: f64,
    /// How many readings the column has that are not NaN.
    pub readings: usize,
}

/// What the readings beyond a column's bound are, by their share of its readings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// At most [`MOST_GLITCH_SHARE`]: glitches, dropped (or kept as NaN) and told.
    Glitches,
    /// More, but at most [`MOST_OF_A_COLUMN`]: too many to drop without a word, too few to be
    /// a unit: kept and told, and no fit or judgement takes the axis.
    TooMany,
    /// Most of the column: its unit (or the column chosen) is in doubt.
    Column,
}

/// The readings of `values` whose magnitude is beyond `bound` (infinities included: no reading
/// is infinite); `None` when there are none.
pub fn beyond(values: impl IntoIterator<Item = f64>, bound: f64) -> Option<Beyond> {
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
    (!samples.is_empty()).then_some(Beyond {
        samples,
        worst,
        readings,
    })
}

/// The readings of `values` beyond `bound` when they are glitches ([`Verdict::Glitches`]: at
/// most [`MOST_GLITCH_SHARE`] of the readings that are not NaN); `None` when there are none,
/// or more.
pub fn glitches(values: impl IntoIterator<Item = f64>, bound: f64) -> Option<Beyond> {
    beyond(values, bound).filter(|b| b.verdict() == Verdict::Glitches)
}

impl Beyond {
    /// Their share of the column's readings.
    pub fn share(&self) -> f64 {
        self.samples.len() as f64 / self.readings.max(1) as f64
    }

    /// What they are, by [`Beyond::share`].
    pub fn verdict(&self) -> Verdict {
        let n = self.samples.len() as f64;
        let readings = self.readings as f64;
        if n <= MOST_GLITCH_SHARE * readings {
            Verdict::Glitches
        } else if n <= MOST_OF_A_COLUMN * readings {
            Verdict::TooMany
        } else {
            Verdict::Column
        }
    }

    /// Their share in words, `1.01 % of its N readings`.
    fn share_words(&self) -> String {
        format!(
            "{} % of its {} readings",
            share_percent(self.samples.len(), self.readings),
            self.readings
        )
    }

    /// Why a column most of whose readings are beyond is doubted ([`Verdict::Column`]): `WHAT
    /// read as UNIT reaches W °/s, beyond the 10⁴ °/s of any gyro on a stand, in N of its M
    /// readings (S %, the first at FIRST, the last at LAST): check its unit …`. The count and
    /// where they lie are kept, as the stretch's message has them, so that the edge between the
    /// two (half the column) reads as one.
    pub fn column_message(
        &self,
        what: &str,
        unit: &str,
        (first_at, last_at): (&str, &str),
    ) -> String {
        format!(
            "{what} read as {unit} reaches {:.3e} °/s, beyond the 10⁴ °/s of any gyro on a \
             stand, in {} of its {} readings ({} %, the first at {first_at}, the last at \
             {last_at}): more than half of the column, so it is no stretch of glitches: check \
             its unit (rate_unit) or choose another column (rate_col)",
            self.worst.abs() / 3600.0,
            self.samples.len(),
            self.readings,
            share_percent(self.samples.len(), self.readings),
        )
    }

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

    /// Why they are kept, for [`Verdict::TooMany`]: `N readings of "COLUMN" beyond BOUND
    /// (WORST at WHERE, the first; the last at LAST), S % of its N readings, which no QUANTITY
    /// gives: more than the 1 % taken for glitches, so they are kept as read, and the axis is
    /// neither fitted nor judged: cut that stretch out …`.
    pub fn too_many_message(
        &self,
        column: &str,
        limit: &str,
        (first_at, last_at): (&str, &str),
        quantity: &str,
    ) -> String {
        format!(
            "{} readings of \"{}\" beyond {limit} ({} at {first_at}, the first; the last at \
             {last_at}), {}, which no {quantity} gives: more than the {} % taken for \
             glitches, so they are kept as read, and the axis is neither fitted nor judged: \
             cut that stretch out of the log, or check the logger",
            self.samples.len(),
            crate::text::escaped(column, false),
            crate::number::readable(self.worst),
            self.share_words(),
            100.0 * MOST_GLITCH_SHARE
        )
    }
}

/// `count` of `of` in percent, for a message, with as many significant digits (three at the
/// least) as keep it on its side of the bounds of the rules it is judged by
/// ([`MOST_GLITCH_SHARE`], [`MOST_OF_A_COLUMN`]): 9150 of 18301 is `49.997`, 9151 `50.003`,
/// 183 of 18301 `0.9999`, never a rounded `50` or `1` on the wrong side of the rule that
/// changed what the message says. Exactly at a bound it reads the bound.
pub fn share_percent(count: usize, of: usize) -> String {
    let exact = 100.0 * count as f64 / of.max(1) as f64;
    let bounds = [100.0 * MOST_GLITCH_SHARE, 100.0 * MOST_OF_A_COLUMN];
    let on_its_side = |shown: f64| {
        bounds
            .iter()
            .all(|&b| (shown > b) == (exact > b) && (shown < b) == (exact < b))
    };
    (3..=17)
        .map(|digits| crate::number::significant(exact, digits))
        .find(|text| text.parse::<f64>().is_ok_and(on_its_side))
        .unwrap_or_else(|| exact.to_string())
}

/// [`glitches`] of a gyro's rate, °/h, beyond [`MAX_PLAUSIBLE_RATE_DPH`].
pub fn rate_glitches(rate_dph: impl IntoIterator<Item = f64>) -> Option<Beyond> {
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

    #[test]
    fn past_a_few_readings_are_a_stretch_and_past_half_the_column() {
        // 1000 readings: 11 beyond are too many for glitches; 500 are still a stretch; 501 are
        // most of the column.
        let with = |n: usize| {
            let mut x = vec![0.5; 1000];
            x[..n].fill(1e3);
            beyond(x, 100.0).unwrap()
        };
        assert_eq!(with(10).verdict(), Verdict::Glitches);
        assert_eq!(with(11).verdict(), Verdict::TooMany);
        assert_eq!(with(11).share(), 0.011);
        assert_eq!(with(500).verdict(), Verdict::TooMany);
        assert_eq!(with(501).verdict(), Verdict::Column);
        assert_eq!(beyond([0.5, f64::NAN], 100.0), None);
        let m = with(11).too_many_message("w", "the bound", ("line 2", "line 12"), "gyro");
        assert!(
            m.starts_with("11 readings of \"w\" beyond the bound (1000 at line 2, the first; the last at line 12), 1.1 % of its 1000 readings"),
            "{m}"
        );
    }

    #[test]
    fn a_share_is_never_printed_on_the_other_side_of_a_bound() {
        // 9150 and 9151 of 18301 are 49.99727 % and 50.00273 %: three digits read 50 for both.
        assert_eq!(share_percent(9150, 18301), "49.997");
        assert_eq!(share_percent(9151, 18301), "50.003");
        // 183 and 184 of 18301: 0.999945 % and 1.0054 %.
        assert_eq!(share_percent(183, 18301), "0.9999");
        assert_eq!(share_percent(184, 18301), "1.01");
        // Exactly at a bound, the bound; away from the bounds, three digits.
        assert_eq!(share_percent(5, 10), "50");
        assert_eq!(share_percent(1, 100), "1");
        assert_eq!(share_percent(600, 40201), "1.49");
        assert_eq!(share_percent(10, 10), "100");
    }
}
