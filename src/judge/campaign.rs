//! A campaign's acceptance figures, read from its runs' plateaus as the calibration records
//! them ([`crate::models::campaign::RunRecord`]): the bias **repeatability** at each
//! temperature two or more plateaus share, and the **thermal hysteresis** between the bias
//! reached heating and reached cooling at one temperature.
//!
//! Plateaus share a temperature when they fall in one group: the plateaus sorted by
//! temperature, a group grows while its next plateau is within twice the tolerance of its
//! coldest, so every plateau of a group is within the tolerance of the group's middle.
//! Repeatability is made from the plateaus' mean raw output, turn-on offsets included: it is
//! what the gyro does from one turn-on to the next. Hysteresis is made from the same less each
//! run's turn-on offset when the fit estimated them: a heating run and a cooling run on two
//! days differ by their turn-ons too, which is no hysteresis.

use crate::models::campaign::{Approach, RunRecord};
use serde::Serialize;

/// The bias at one temperature shared by two or more plateaus.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Repeatability {
    /// The plateaus' mean temperature, °C.
    pub temp_c: f64,
    /// The largest less the smallest plateau bias there, °/h.
    pub spread_dph: f64,
    /// The run of each plateau (its name), in the order of `values`.
    pub runs: Vec<String>,
    /// Each plateau's bias, °/h.
    pub values: Vec<f64>,
    /// Each plateau's temperature, °C.
    pub temps_c: Vec<f64>,
}

/// The bias at one temperature reached heating against reached cooling.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Hysteresis {
    /// The plateaus' mean temperature, °C.
    pub temp_c: f64,
    /// Mean bias of the plateaus reached heating, °/h.
    pub heating_dph: f64,
    /// Mean bias of the plateaus reached cooling, °/h.
    pub cooling_dph: f64,
    /// Heating less cooling, °/h.
    pub difference_dph: f64,
    /// Plateaus reached heating.
    pub heating_plateaus: usize,
    /// Plateaus reached cooling.
    pub cooling_plateaus: usize,
    /// Whether the biases are net of the runs' turn-on offsets (estimated by the fit); when
    /// not, a difference between runs' turn-ons is in the figure.
    pub net_of_turn_on_offsets: bool,
}

/// A plateau of a run, as the groups see it.
#[derive(Debug, Clone, Copy)]
struct Point<'a> {
    run: &'a str,
    temp_c: f64,
    bias_dph: f64,
    /// The bias less the run's turn-on offset, when one was estimated.
    net_dph: f64,
    approach: Approach,
}

/// The groups of plateaus that share a temperature, each of two plateaus or more, coldest
/// first.
fn groups(runs: &[RunRecord], tolerance_c: f64) -> Vec<Vec<Point<'_>>> {
    let mut points: Vec<Point> = runs
        .iter()
        .flat_map(|r| {
            r.plateaus.iter().map(|p| Point {
                run: r.name.as_str(),
                temp_c: p.temp_c,
                bias_dph: p.bias_dph,
                net_dph: p.bias_dph - r.turn_on_offset_dph.unwrap_or(0.0),
                approach: p.approach,
            })
        })
        .filter(|p| p.temp_c.is_finite() && p.bias_dph.is_finite())
        .collect();
    points.sort_by(|a, b| a.temp_c.total_cmp(&b.temp_c));
    let mut out: Vec<Vec<Point>> = Vec::new();
    for p in points {
        match out.last_mut() {
            Some(g) if p.temp_c - g[0].temp_c <= 2.0 * tolerance_c => g.push(p),
            _ => out.push(vec![p]),
        }
    }
    out.retain(|g| g.len() >= 2);
    out
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    s / n as f64
}

/// The bias repeatability at each temperature two or more plateaus share (within
/// `tolerance_c`), whether in different runs or repeated within one, coldest first.
pub fn repeatability(runs: &[RunRecord], tolerance_c: f64) -> Vec<Repeatability> {
    groups(runs, tolerance_c)
        .into_iter()
        .map(|g| {
            let values: Vec<f64> = g.iter().map(|p| p.bias_dph).collect();
            let (lo, hi) = values
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            Repeatability {
                temp_c: mean(g.iter().map(|p| p.temp_c)),
                spread_dph: hi - lo,
                runs: g.iter().map(|p| p.run.to_string()).collect(),
                temps_c: g.iter().map(|p| p.temp_c).collect(),
                values,
            }
        })
        .collect()
}

/// The thermal hysteresis at each shared temperature that plateaus reach both heating and
/// cooling (within `tolerance_c`), coldest first, net of the runs' turn-on offsets when they
/// were estimated. A plateau the run started at was reached from neither side and is left
/// out.
pub fn hysteresis(runs: &[RunRecord], tolerance_c: f64) -> Vec<Hysteresis> {
    let net = runs.iter().any(|r| r.turn_on_offset_dph.is_some());
    groups(runs, tolerance_c)
        .into_iter()
        .filter_map(|g| {
            let side = |a: Approach| g.iter().filter(move |p| p.approach == a);
            let (heating, cooling) = (side(Approach::Heating), side(Approach::Cooling));
            let (nh, nc) = (heating.clone().count(), cooling.clone().count());
            if nh == 0 || nc == 0 {
                return None;
            }
            let h = mean(heating.map(|p| p.net_dph));
            let c = mean(cooling.map(|p| p.net_dph));
            let both = g
                .iter()
                .filter(|p| p.approach != Approach::Start)
                .map(|p| p.temp_c);
            Some(Hysteresis {
                temp_c: mean(both),
                heating_dph: h,
                cooling_dph: c,
                difference_dph: h - c,
                heating_plateaus: nh,
                cooling_plateaus: nc,
                net_of_turn_on_offsets: net,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::campaign::RunPlateau;

    fn run(name: &str, plateaus: &[(f64, f64, Approach)]) -> RunRecord {
        RunRecord {
            name: name.into(),
            sha256: String::new(),
            samples: 10,
            start_s: 0.0,
            duration_s: 10.0,
            plateaus: plateaus
                .iter()
                .map(|&(temp_c, bias_dph, approach)| RunPlateau {
                    start_s: 0.0,
                    end_s: 1.0,
                    temp_c,
                    bias_dph,
                    approach,
                })
                .collect(),
            turn_on_offset_dph: None,
        }
    }

    #[test]
    fn spread_is_largest_less_smallest_of_a_shared_temperature() {
        use Approach::*;
        let runs = [
            run("a", &[(20.0, 1.0, Start), (60.0, 2.0, Heating)]),
            run(
                "b",
                &[
                    (20.4, 1.25, Start),
                    (-50.0, 3.0, Cooling),
                    (19.7, 0.9, Heating),
                ],
            ),
        ];
        let r = repeatability(&runs, 1.0);
        assert_eq!(r.len(), 1, "{r:?}");
        assert_eq!(r[0].values, vec![0.9, 1.0, 1.25]);
        assert_eq!(r[0].runs, vec!["b", "a", "b"]);
        assert!((r[0].spread_dph - 0.35).abs() < 1e-12);
        // Within ±0.3 °C the group of 19.7 °C reaches 20.3 °C: 20.4 °C stands alone.
        let tight = repeatability(&runs, 0.3);
        assert_eq!(tight.len(), 1);
        assert_eq!(tight[0].values, vec![0.9, 1.0]);
    }

    #[test]
    fn hysteresis_needs_both_approaches_and_leaves_the_start_out() {
        use Approach::*;
        let runs = [
            run(
                "a",
                &[
                    (20.0, 1.0, Start),
                    (60.0, 2.0, Heating),
                    (20.0, 1.3, Cooling),
                ],
            ),
            run("b", &[(60.2, 2.2, Cooling), (20.1, 1.1, Heating)]),
        ];
        let h = hysteresis(&runs, 1.0);
        assert_eq!(h.len(), 2, "{h:?}");
        assert!((h[0].heating_dph - 1.1).abs() < 1e-12);
        assert!((h[0].cooling_dph - 1.3).abs() < 1e-12);
        assert!((h[0].difference_dph + 0.2).abs() < 1e-12);
        assert_eq!((h[0].heating_plateaus, h[0].cooling_plateaus), (1, 1));
        assert!((h[1].difference_dph + 0.2).abs() < 1e-12);
        // Only heating at a temperature: no hysteresis there.
        let one_side = [run("a", &[(20.0, 1.0, Heating), (20.3, 1.1, Heating)])];
        assert!(hysteresis(&one_side, 1.0).is_empty());
    }
}
