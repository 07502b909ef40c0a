//! The terms of a calibration left out for want of points: a K1± or K2± set with no usable
//! point (a dead-band wide enough to switch K2 off, `deadband_tddot 1`) is fitted as zero
//! ([`Approx::zero`](crate::models::approx::Approx::zero)). Such a term adds nothing, and has
//! no range a sample could lie outside of ([`Approx::judged_range`]); where the share of
//! samples outside the calibrated ranges is shown, the terms left out of it are named, so
//! that the figure is read as the ranges of K0 and of the terms fitted.

use super::Calibration;
use crate::models::approx::Approx;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Which of a calibration's rate terms were left out (zero, with no range).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct LeftOut {
    /// K1 of the + set.
    pub k1_plus: bool,
    /// K1 of the − set.
    pub k1_minus: bool,
    /// K2 of the + set.
    pub k2_plus: bool,
    /// K2 of the − set.
    pub k2_minus: bool,
}

impl LeftOut {
    /// Whether no term was left out.
    pub fn is_none(&self) -> bool {
        *self == LeftOut::default()
    }

    /// The names of the terms left out, in the order of the model (`K1+`, `K1−`, `K2+`, `K2−`).
    pub fn names(&self) -> Vec<&'static str> {
        [
            (self.k1_plus, "K1+"),
            (self.k1_minus, "K1−"),
            (self.k2_plus, "K2+"),
            (self.k2_minus, "K2−"),
        ]
        .into_iter()
        .filter_map(|(left, name)| left.then_some(name))
        .collect()
    }
}

/// `K2+ and K2− left out: zero, with no range`: a note for the share of samples outside the
/// calibrated ranges; empty when no term was left out.
impl fmt::Display for LeftOut {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names = self.names();
        let Some((last, first)) = names.split_last() else {
            return Ok(());
        };
        let listed = if first.is_empty() {
            (*last).to_string()
        } else {
            format!("{} and {last}", first.join(", "))
        };
        write!(f, "{listed} left out: zero, with no range")
    }
}

impl Calibration {
    /// The rate terms of this calibration left out for want of points ([`Approx::is_left_out`]).
    pub fn left_out(&self) -> LeftOut {
        let left = Approx::is_left_out;
        LeftOut {
            k1_plus: left(&self.k1_plus),
            k1_minus: left(&self.k1_minus),
            k2_plus: left(&self.k2_plus),
            k2_minus: left(&self.k2_minus),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::LeftOut;

    #[test]
    fn the_note_names_the_terms_left_out() {
        assert_eq!(LeftOut::default().to_string(), "");
        let k2 = LeftOut {
            k2_plus: true,
            k2_minus: true,
            ..LeftOut::default()
        };
        assert_eq!(k2.to_string(), "K2+ and K2− left out: zero, with no range");
        let one = LeftOut {
            k1_minus: true,
            ..LeftOut::default()
        };
        assert_eq!(one.to_string(), "K1− left out: zero, with no range");
    }
}
