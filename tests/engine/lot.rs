//! A lot judged against its simulator's truth: the units built ordinary pass, the one built
//! with ten times the noise fails on the noise limit, the one built with three times the K0
//! slope passes and is the lot's outlier, the corrupt file is an error and the others go on;
//! the figures the lot reads agree with the constants the units were simulated with.

use crate::common::lot::{
    CAMPAIGN, CORRUPT, NOISY, ORDINARY, SLOPED, arws, slopes, spec_json, write_lot,
};
use driftlab::lot::{Lot, LotOutcome, Spec, Status, UnitOutcome, figures};

fn unit<'a>(lot: &'a LotOutcome, name: &str) -> &'a UnitOutcome {
    lot.units
        .iter()
        .find(|u| u.unit == name)
        .unwrap_or_else(|| panic!("no unit {name} in {:?}", lot.units))
}

fn value(u: &UnitOutcome, figure: &str) -> f64 {
    u.axes[0]
        .get(figure)
        .and_then(|f| f.value)
        .unwrap_or_else(|| panic!("{}: no {figure}: {:?}", u.unit, u.axes[0].get(figure)))
}

#[test]
fn a_simulated_lot_is_judged_as_its_truth_says() {
    let dir = tempfile::tempdir().unwrap();
    let units = dir.path().join("units");
    std::fs::create_dir(&units).unwrap();
    write_lot(&units);
    let lot = Lot {
        inputs: vec![units.clone()],
        spec: Spec::from_json(&spec_json()).unwrap(),
        out: dir.path().join("out"),
        recipe: None,
        jobs: 2,
        shard: None,
    };
    let mut told = 0;
    let outcome = driftlab::lot::run(&lot, &mut |p| {
        told += 1;
        assert_eq!(p.done, told);
        assert_eq!(p.total, 9);
    })
    .unwrap();
    assert_eq!(told, 9);
    assert_eq!(outcome.units.len(), 9);

    // The ordinary units and the campaign pass; so does the sloped one, within every limit.
    for name in ORDINARY.iter().chain(&[SLOPED, CAMPAIGN]) {
        let u = unit(&outcome, name);
        assert_eq!(u.status, Status::Pass, "{name}: {:?}", u.reasons);
        assert!(
            dir.path()
                .join("out")
                .join(u.calibration.as_ref().unwrap())
                .is_file()
        );
    }
    // Each ordinary unit's noise floor is the simulated gyro's, read off the corrected rate.
    let (arw, noisy_arw) = arws();
    for name in ORDINARY {
        let read = value(unit(&outcome, name), figures::ARW);
        assert!(
            (read / arw - 1.0).abs() < 0.1,
            "{name}: ARW {read} against {arw}"
        );
    }
    // The noisy unit fails on its noise floor, and on nothing else.
    let noisy = unit(&outcome, NOISY);
    assert_eq!(noisy.status, Status::Fail);
    assert_eq!(noisy.reasons.len(), 1, "{:?}", noisy.reasons);
    assert!(
        noisy.reasons[0].starts_with("max_arw_deg_rt_h: "),
        "{:?}",
        noisy.reasons
    );
    let read = value(noisy, figures::ARW);
    assert!(
        (read / noisy_arw - 1.0).abs() < 0.1,
        "ARW {read} against {noisy_arw}"
    );

    // The corrupt file is an error that names it, and the lot went on.
    let corrupt = unit(&outcome, CORRUPT);
    assert_eq!(corrupt.status, Status::Error);
    assert!(
        corrupt.reasons[0].contains(CORRUPT),
        "{:?}",
        corrupt.reasons
    );
    assert!(corrupt.axes.is_empty() && corrupt.calibration.is_none());
    assert_eq!(outcome.status(), Status::Error);
    assert_eq!(outcome.counts(), [7, 1, 1]);

    // K0's slope between 0 and 40 °C is the simulated one (K0 = b1·(T − 20) + b2·(T − 20)²,
    // whose curvature cancels between 0 and 40 °C), for the ordinary units and the sloped one.
    let (slope, steep) = slopes();
    let k0_slope =
        |u: &UnitOutcome| (value(u, &figures::k0_at(40.0)) - value(u, &figures::k0_at(0.0))) / 40.0;
    for name in ORDINARY {
        let s = k0_slope(unit(&outcome, name));
        assert!(
            (s / slope - 1.0).abs() < 0.15,
            "{name}: slope {s} against {slope}"
        );
    }
    let s = k0_slope(unit(&outcome, SLOPED));
    assert!((s / steep - 1.0).abs() < 0.15, "slope {s} against {steep}");

    // The sloped unit is the lot's outlier on K0, far beyond the five robust deviations; no
    // ordinary unit is one on K0.
    let on_k0 = |name: &str| -> Vec<&driftlab::lot::Outlier> {
        outcome
            .outliers
            .iter()
            .filter(|o| o.unit == name && o.figure.starts_with("k0_"))
            .collect()
    };
    let sloped = on_k0(SLOPED);
    assert!(
        sloped.iter().any(|o| o.figure == figures::k0_at(0.0)),
        "{:?}",
        outcome.outliers
    );
    assert!(sloped.iter().all(|o| o.sigmas.abs() > 5.0));
    for name in ORDINARY {
        assert!(on_k0(name).is_empty(), "{name}: {:?}", on_k0(name));
    }
}
