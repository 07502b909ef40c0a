//! A pwl or spline K0 has its knots at the plateaus' temperatures, never more than they hold
//! (the knot count is a maximum), picked evenly by index when fewer are asked for; knots placed
//! by hand stay where they are; and the kind of K0 the plateaus support (what the workbench
//! opens a log with). The truth is the plateaus the tests make: their temperatures and their
//! mean drifts, from a K0 written here.

use driftlab::models::approx::{ApproxKind, ApproxSpec, Curve};
use driftlab::models::recipe::Recipe;
use driftlab::models::vakhrameev::{self, fit_k0, k0_supported};
use driftlab::signal::plateau::{PlateauRange, PlateauStats};

/// The K0 the plateaus are made from: curved, so that a knot anywhere but at a plateau
/// would show.
fn k0_truth(t: f64) -> f64 {
    0.05 + 0.004 * t + 0.0002 * t * t
}

/// A plateau held at `temp_c`, reading `omega_dph`.
fn plateau(k: usize, temp_c: f64, omega_dph: f64) -> PlateauStats {
    let start_s = 10_000.0 * k as f64;
    PlateauStats {
        range: PlateauRange {
            start_s,
            end_s: start_s + 1_800.0,
        },
        temp_c,
        omega_dph,
        omega_std_dph: Some(0.2),
        omega_sem_dph: Some(0.2 / 1800f64.sqrt()),
        temp_spread_c: 0.02,
        samples: 1_800,
    }
}

/// Plateaus at these temperatures, each reading the true K0 there.
fn plateaus_at(temps: &[f64]) -> Vec<PlateauStats> {
    temps
        .iter()
        .enumerate()
        .map(|(k, &t)| plateau(k, t, k0_truth(t)))
        .collect()
}

fn spec(kind: ApproxKind, knots: usize) -> ApproxSpec {
    ApproxSpec {
        kind,
        knots,
        ..ApproxSpec::default()
    }
}

fn knots_of(a: &driftlab::models::approx::Approx) -> (Vec<f64>, Vec<f64>) {
    let (x, y) = a.knots();
    (x.to_vec(), y.to_vec())
}

#[test]
fn pwl_and_spline_knots_land_on_the_plateau_temperatures_and_pass_through_their_means() {
    let temps = [-40.0, -10.0, 20.0, 60.0];
    let plateaus = plateaus_at(&temps);
    for kind in [ApproxKind::Pwl, ApproxKind::Spline] {
        // As many knots as temperatures, and more: one knot per temperature either way.
        for asked in [4, 5, 10] {
            let mut warnings = Vec::new();
            let k0 = fit_k0(&plateaus, &spec(kind, asked), &mut warnings).unwrap();
            let (x, y) = knots_of(&k0);
            assert_eq!(x, temps, "{kind} {asked}");
            for (t, v) in temps.iter().zip(&y) {
                assert!((v - k0_truth(*t)).abs() < 1e-9, "{kind} {asked}: {t} {v}");
                assert!(
                    (k0.eval(*t) - k0_truth(*t)).abs() < 1e-9,
                    "{kind} {asked}: {t}"
                );
            }
            // The knot count is a maximum: nothing to warn of, and a curve through every
            // plateau mean is what K0 is.
            assert!(warnings.is_empty(), "{kind} {asked}: {warnings:?}");
        }
    }
}

#[test]
fn a_pwl_k0_stays_between_the_plateaus_where_none_was_held() {
    // Four plateaus at three temperatures (two at one set point): five knots spread evenly
    // put one at 5 °C and one at 32.5 °C, where nothing was measured; at the plateaus'
    // temperatures the line between two set points stays between what they read.
    let plateaus = vec![
        plateau(0, -50.0, k0_truth(-50.0)),
        plateau(1, 20.0, k0_truth(20.0) + 0.004),
        plateau(2, 60.0, k0_truth(60.0)),
        plateau(3, 20.03, k0_truth(20.0) - 0.002),
    ];
    let mut warnings = Vec::new();
    let k0 = fit_k0(&plateaus, &spec(ApproxKind::Pwl, 5), &mut warnings).unwrap();
    let (x, y) = knots_of(&k0);
    // The set point held twice is one knot, at the mean of its two plateaus' temperatures.
    assert_eq!(x.len(), 3);
    assert_eq!(x[0], -50.0);
    assert!((x[1] - 20.015).abs() < 1e-12, "{x:?}");
    assert_eq!(x[2], 60.0);
    // The set points held once read their plateau's drift, but for the share of the
    // compromise at 20 °C their segments take (a millionth of a degree per hour).
    assert!((y[0] - k0_truth(-50.0)).abs() < 1e-5, "{y:?}");
    assert!((y[2] - k0_truth(60.0)).abs() < 1e-5, "{y:?}");
    // Its value is the two plateaus' mean drift (each reads 0.003 °/h off it), to what the
    // slopes either side make of the hundredths of a degree between them (0.02 °/h/°C).
    assert!((y[1] - (k0_truth(20.0) + 0.001)).abs() < 5e-4, "{y:?}");
    for k in 0..=110 {
        let t = -50.0 + k as f64;
        let v = k0.eval(t);
        let (lo, hi) = if t < 20.0 { (y[1], y[0]) } else { (y[1], y[2]) };
        let (lo, hi) = (lo.min(hi), lo.max(hi));
        assert!(
            v >= lo - 1e-12 && v <= hi + 1e-12,
            "K0({t}) = {v}, not in {lo} … {hi}"
        );
    }
    assert!(warnings.is_empty(), "{warnings:?}");
}

#[test]
fn fewer_knots_than_temperatures_are_picked_evenly_by_index_with_both_ends() {
    let temps = [-45.0, -30.0, -15.0, 0.0, 15.0, 35.0, 65.0];
    let plateaus = plateaus_at(&temps);
    // Written out by hand: index i of k knots over 7 temperatures is i·6/(k−1) rounded, a
    // half up (five knots: 0, 1.5, 3, 4.5, 6 -> 0, 2, 3, 5, 6).
    for (asked, want) in [
        (2, vec![-45.0, 65.0]),
        (3, vec![-45.0, 0.0, 65.0]),
        (4, vec![-45.0, -15.0, 15.0, 65.0]),
        (5, vec![-45.0, -15.0, 0.0, 35.0, 65.0]),
        (7, temps.to_vec()),
    ] {
        for kind in [ApproxKind::Pwl, ApproxKind::Spline] {
            let mut warnings = Vec::new();
            let k0 = fit_k0(&plateaus, &spec(kind, asked), &mut warnings).unwrap();
            let (x, _) = knots_of(&k0);
            assert_eq!(x, want, "{kind} {asked}");
            assert!(warnings.is_empty(), "{kind} {asked}: {warnings:?}");
        }
    }
}

#[test]
fn knots_placed_by_hand_stay_where_they_were_placed() {
    let plateaus = plateaus_at(&[-40.0, -10.0, 20.0, 60.0]);
    let at = vec![-45.0, 0.0, 30.0, 65.0];
    let placed = ApproxSpec {
        at: Some(at.clone()),
        ..spec(ApproxKind::Pwl, 4)
    };
    let mut warnings = Vec::new();
    let k0 = fit_k0(&plateaus, &placed, &mut warnings).unwrap();
    assert_eq!(knots_of(&k0).0, at);
}

#[test]
fn the_calibration_records_the_knots_at_the_plateaus_temperatures() {
    // The sample log: four plateaus at three set points (-50, 20 twice, 60 °C).
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    let log = driftlab::log::ingest::read_path(&path, &Default::default()).unwrap();
    let recipe = Recipe {
        k0: spec(ApproxKind::Pwl, 5),
        ..Recipe::default()
    };
    let fit = vakhrameev::fit(&log, &recipe.checked().unwrap()).unwrap();
    let plateaus = &fit.calibration.plateaus;
    // The set points, found here apart from the engine: sorted, a gap of more than 1 °C
    // between two.
    let mut t: Vec<(f64, f64)> = plateaus.iter().map(|p| (p.temp_c, p.omega_dph)).collect();
    t.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut sets: Vec<Vec<(f64, f64)>> = Vec::new();
    for p in t {
        match sets.last_mut() {
            Some(s) if p.0 - s.last().unwrap().0 <= 1.0 => s.push(p),
            _ => sets.push(vec![p]),
        }
    }
    assert_eq!(sets.len(), 3, "{plateaus:?}");
    assert_eq!(plateaus.len(), 4);
    let mean =
        |s: &[(f64, f64)], f: fn(&(f64, f64)) -> f64| s.iter().map(f).sum::<f64>() / s.len() as f64;
    let Curve::Pwl { knots_x, knots_y } = fit.calibration.k0.curve() else {
        panic!("{:?}", fit.calibration.k0);
    };
    assert_eq!(knots_x.len(), 3);
    for (j, s) in sets.iter().enumerate() {
        assert!((knots_x[j] - mean(s, |p| p.0)).abs() < 1e-9, "{knots_x:?}");
        // The drift at a set point held once is its plateau's; at one held twice, theirs
        // within the hundredths of a degree between them.
        assert!(
            (knots_y[j] - mean(s, |p| p.1)).abs() < 1e-4,
            "{knots_y:?} / {sets:?}"
        );
    }
    // No K0 of +12 °/h between them: the curve stays within what the plateaus read.
    let (lo, hi) = knots_y
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| {
            (a.min(y), b.max(y))
        });
    for k in 0..=110 {
        let v = fit.calibration.k0.eval(-50.0 + k as f64);
        assert!(v >= lo - 1e-12 && v <= hi + 1e-12, "{v}");
    }
    assert!(
        !fit.warnings.iter().any(|w| w.starts_with("K0")),
        "{:?}",
        fit.warnings
    );
    // The file holds the knots where they are: written and read back, the same positions.
    let json = serde_json::to_value(&fit.calibration.k0).unwrap();
    let written: Vec<f64> = json["curve"]["knots_x"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(&written, knots_x);
}

#[test]
fn the_kind_the_plateaus_support_follows_their_temperatures() {
    let parabola = Recipe::default().k0;
    assert_eq!(parabola.kind, ApproxKind::Parabolic);
    // Three plateaus at two set points (the papers' square waves): a line.
    let two = vec![
        plateau(0, -25.0, 0.03),
        plateau(1, -45.0, 0.15),
        plateau(2, -25.02, 0.031),
    ];
    let s = k0_supported(&two, &parabola);
    assert_eq!(s.spec.kind, ApproxKind::Linear);
    // The set point held twice at the mean of its two plateaus' temperatures.
    assert_eq!(s.temperatures.len(), 2);
    assert_eq!(s.temperatures[0], -45.0);
    assert!(
        (s.temperatures[1] - -25.01).abs() < 1e-12,
        "{:?}",
        s.temperatures
    );
    assert_eq!(
        s.describe(),
        "K0 linear: the plateaus hold 2 temperatures (-45, -25 °C)"
    );
    // Fitted, the line warns of nothing; the parabola asked for does.
    let mut warnings = Vec::new();
    fit_k0(&two, &s.spec, &mut warnings).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    fit_k0(&two, &parabola, &mut warnings).unwrap();
    assert!(
        warnings[0].contains("at only 2 temperatures"),
        "{warnings:?}"
    );
    // Three set points: the parabola, through every plateau mean without a warning.
    let three = plateaus_at(&[-4.0, 26.0, 56.0]);
    let s = k0_supported(&three, &parabola);
    assert_eq!(s.spec, parabola);
    let mut warnings = Vec::new();
    let k0 = fit_k0(&three, &s.spec, &mut warnings).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    for t in [-4.0, 26.0, 56.0] {
        assert!((k0.eval(t) - k0_truth(t)).abs() < 1e-9);
    }
    // A line and a knot curve stand from two set points (the knots go to them).
    for kind in [ApproxKind::Linear, ApproxKind::Pwl, ApproxKind::Spline] {
        assert_eq!(k0_supported(&two, &spec(kind, 5)).spec, spec(kind, 5));
    }
    // Knots placed by hand for more set points than there are: as many as they hold.
    let placed = ApproxSpec {
        at: Some(vec![-50.0, -40.0, -30.0, -20.0]),
        ..spec(ApproxKind::Spline, 4)
    };
    assert_eq!(
        k0_supported(&two, &placed).spec,
        spec(ApproxKind::Spline, 2)
    );
    // One set point determines no curve: the spec stays, and the fit holds K0 constant.
    let one = vec![plateau(0, 25.0, 0.1), plateau(1, 25.01, 0.2)];
    let s = k0_supported(&one, &parabola);
    assert_eq!(s.spec, parabola);
    assert_eq!(
        s.describe(),
        "K0 constant: the plateaus hold 1 temperature (25 °C)"
    );
}
