//! The sets' samples against their definition, over a log long enough to be cut into many
//! spans: each set's indices, and the count and range of their finite rates, equal what one
//! plain walk over the log gives.

use super::*;

/// A log's rates of every kind: both signs, inside and outside the dead-bands, NaN, infinite,
/// and a stretch without rate history.
fn rates(n: usize) -> Derivatives {
    let tdot: Vec<f64> = (0..n)
        .map(|i| match i % 97 {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => 1e-9,
            _ => ((i as f64) * 0.0137).sin() * (1.0 + (i % 13) as f64),
        })
        .collect();
    let tddot: Vec<f64> = (0..n)
        .map(|i| match i % 89 {
            0 => f64::NEG_INFINITY,
            1 => f64::NAN,
            2 => -1e-9,
            _ => ((i as f64) * 0.0071).cos() * (0.5 + (i % 7) as f64),
        })
        .collect();
    Derivatives {
        tdot,
        tddot,
        ready_from: 40,
        ready: vec![40..n / 2, n / 2 + 100..n],
    }
}

#[test]
fn the_sets_samples_and_ranges_are_their_definition() {
    let n = 300_000;
    let d = rates(n);
    let mask: Vec<bool> = (0..n).map(|i| (i / 1000) % 5 == 0).collect();
    let db = (0.05, 0.02);
    let sets = set_samples(&d, &mask, db);
    for (s, regime) in [(0, Regime::Plus), (1, Regime::Minus)] {
        let members = |col: &[f64], band: f64| -> Vec<u32> {
            d.ready
                .iter()
                .flat_map(|r| r.clone())
                .filter(|&i| !mask[i] && Regime::of(d.tdot[i], d.tddot[i]) == regime)
                .filter(|&i| col[i].abs() > band || col[i].is_nan())
                .map(|i| i as u32)
                .collect()
        };
        let range = |idx: &[u32], col: &[f64]| {
            let finite: Vec<f64> = idx
                .iter()
                .map(|&i| col[i as usize])
                .filter(|x| x.is_finite())
                .collect();
            let lo = finite.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (finite.len(), lo.to_bits(), hi.to_bits())
        };
        let got = &sets[s];
        let (k1, k2) = (members(&d.tdot, db.0), members(&d.tddot, db.1));
        assert!(
            k1.len() > 10_000 && k2.len() > 10_000,
            "set {s} too small to test"
        );
        assert_eq!(got.k1, k1, "set {s}: K1's samples");
        assert_eq!(got.k2, k2, "set {s}: K2's samples");
        let bits = |r: &XRange| (r.n, r.lo.to_bits(), r.hi.to_bits());
        assert_eq!(bits(&got.k1_range.unwrap()), range(&k1, &d.tdot), "set {s}");
        assert_eq!(
            bits(&got.k2_range.unwrap()),
            range(&k2, &d.tddot),
            "set {s}"
        );
    }
    // Infinite rates were members, and no part of any range: the case was met (a NaN rate
    // makes its sample static, a member of neither set).
    let mut members = sets.iter().flat_map(|s| &s.k1);
    assert!(members.any(|&i| d.tdot[i as usize].is_infinite()));
}
