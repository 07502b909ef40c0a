//! The units that do not look like their lot: a figure or coefficient more than a few robust
//! standard deviations from the lot's median, whether the unit passes or not. A unit within
//! every limit can still be the one whose K0 slope is twice its neighbours', which is worth a
//! look before it ships.
//!
//! The spread is robust: 1.4826 times the median absolute deviation from the median (MAD), the
//! standard deviation of a normal lot that a few wild units cannot inflate. When more than
//! half the lot shares the median exactly (a count such as the plateaus, a share of zero), the
//! MAD is 0 and would make any other value infinitely far: the spread is then √(π/2) times the
//! mean absolute deviation from the median, the standard deviation of a normal lot by that
//! measure. When that is 0 too (to the rounding of the values), every unit holds the same value
//! and none is an outlier.

use super::figures::AxisFigures;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// MAD × this is the standard deviation of a normal distribution.
const MAD_TO_SD: f64 = 1.4826;

/// The mean absolute deviation × this is the standard deviation of a normal distribution
/// (√(π/2)).
const MEAN_AD_TO_SD: f64 = 1.253_314_137_315_500_3;

/// How the spread of a figure over the lot was measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Spread {
    /// 1.4826 × the median absolute deviation.
    Mad,
    /// √(π/2) × the mean absolute deviation from the median, where the MAD is 0.
    MeanAbsoluteDeviation,
}

/// One figure of one unit's axis far from the lot's median.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Outlier {
    /// The unit.
    pub unit: String,
    /// Its axis (empty for a single-axis unit).
    pub axis: String,
    /// The figure.
    pub figure: String,
    /// The unit's value.
    pub value: f64,
    /// The lot's median of it.
    pub median: f64,
    /// The lot's robust standard deviation of it.
    pub robust_sd: f64,
    /// (value − median) ÷ robust_sd.
    pub sigmas: f64,
    /// How the spread was measured.
    pub spread: Spread,
    /// How many units had the figure.
    pub units: usize,
}

/// A figure of an axis: (axis, figure).
type Column<'a> = (&'a str, &'a str);

/// Every figure of every unit's axis more than `sigmas` robust standard deviations from the
/// median of the units that have it (an axis compared with the same axis of the others: gx
/// with gx), in the order of `units` and then of the figures.
pub fn outliers(units: &[(&str, &[AxisFigures])], sigmas: f64) -> Vec<Outlier> {
    // (axis, figure) → every unit's value (its index in `units`), in the order first met.
    let mut groups: Vec<(Column<'_>, Vec<(usize, f64)>)> = Vec::new();
    // Each group's place in `groups`, so that gathering is linear in the figures.
    let mut index: HashMap<Column<'_>, usize> = HashMap::new();
    for (k, (_, axes)) in units.iter().enumerate() {
        for axis in axes.iter() {
            for f in &axis.figures {
                let Some(v) = f.value.filter(|_| super::figures::compared(&f.name)) else {
                    continue;
                };
                let key = (axis.axis.as_str(), f.name.as_str());
                match index.get(&key) {
                    Some(&at) => groups[at].1.push((k, v)),
                    None => {
                        index.insert(key, groups.len());
                        groups.push((key, vec![(k, v)]));
                    }
                }
            }
        }
    }
    let mut out = Vec::new();
    for ((axis, figure), values) in &groups {
        let xs: Vec<f64> = values.iter().map(|(_, v)| *v).collect();
        let Some((median, sd, spread)) = robust_spread(&xs) else {
            continue;
        };
        for (k, v) in values {
            let z = (v - median) / sd;
            if z.is_finite() && z.abs() > sigmas {
                out.push(Outlier {
                    unit: units[*k].0.to_string(),
                    axis: axis.to_string(),
                    figure: figure.to_string(),
                    value: *v,
                    median,
                    robust_sd: sd,
                    sigmas: z,
                    spread,
                    units: xs.len(),
                });
            }
        }
    }
    out.sort_by_key(|o| units.iter().position(|(name, _)| *name == o.unit));
    out
}

/// The median of `xs`, its robust standard deviation and how it was measured; `None` when
/// there is no spread to measure (no value, or every value the same to the rounding of the
/// values themselves: a spread of a few ulps is no spread, and would put a unit 10³⁰⁰
/// deviations away).
pub fn robust_spread(xs: &[f64]) -> Option<(f64, f64, Spread)> {
    let m = median(xs)?;
    let deviations: Vec<f64> = xs.iter().map(|x| (x - m).abs()).collect();
    let rounding = (m.abs() * 8.0 * f64::EPSILON).max(f64::MIN_POSITIVE);
    let mad = median(&deviations)?;
    if mad > rounding {
        return Some((m, MAD_TO_SD * mad, Spread::Mad));
    }
    let mean_ad = deviations.iter().sum::<f64>() / deviations.len() as f64;
    (mean_ad > rounding).then_some((m, MEAN_AD_TO_SD * mean_ad, Spread::MeanAbsoluteDeviation))
}

/// The median (the mean of the two middle values of an even count); `None` for no value.
fn median(xs: &[f64]) -> Option<f64> {
    let mut v: Vec<f64> = xs.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lot::figures::Figure;

    fn unit(v: f64) -> Vec<AxisFigures> {
        vec![AxisFigures {
            axis: String::new(),
            figures: vec![Figure {
                name: "x".into(),
                value: Some(v),
                unavailable: None,
            }],
            worse_than_raw: Vec::new(),
        }]
    }

    #[test]
    fn a_value_far_from_a_normal_lot_is_found_and_its_neighbours_are_not() {
        // Median 10, deviations 0, 1, 1, 2, 2, 30, 0: MAD 1, robust sd 1.4826.
        let values = [10.0, 9.0, 11.0, 8.0, 12.0, 40.0, 10.0];
        let axes: Vec<Vec<AxisFigures>> = values.iter().map(|v| unit(*v)).collect();
        let names: Vec<String> = (0..values.len()).map(|k| format!("u{k}")).collect();
        let units: Vec<(&str, &[AxisFigures])> = names
            .iter()
            .zip(&axes)
            .map(|(n, a)| (n.as_str(), a.as_slice()))
            .collect();
        let found = outliers(&units, 5.0);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].unit, "u5");
        assert_eq!(found[0].spread, Spread::Mad);
        assert!(
            (found[0].robust_sd - 1.4826 * 1.0).abs() < 1e-12,
            "{found:?}"
        );
        assert!((found[0].sigmas - 30.0 / 1.4826).abs() < 1e-9);
    }

    #[test]
    fn a_mad_of_zero_falls_back_to_the_mean_deviation_and_equal_values_have_no_outlier() {
        // Seven of eight share the median: MAD 0; mean deviation 1/8.
        let xs = [5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 4.0];
        let (m, sd, spread) = robust_spread(&xs).unwrap();
        assert_eq!(m, 5.0);
        assert_eq!(spread, Spread::MeanAbsoluteDeviation);
        assert!((sd - MEAN_AD_TO_SD / 8.0).abs() < 1e-15);
        assert!(robust_spread(&[3.0; 6]).is_none());
        // A spread at the values' rounding is none.
        assert!(robust_spread(&[1.0, 1.0 + f64::EPSILON, 1.0, 1.0 - f64::EPSILON]).is_none());
        assert!(robust_spread(&[]).is_none());
    }
}
