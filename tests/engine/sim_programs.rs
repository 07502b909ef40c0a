//! The chamber simulator's programs against the papers: the profiles asked for, Yan's square
//! waves and full-range program, and profiles written as JSON (old files still load).

use driftlab::sim::{GyroParams, Profile, Segment, profile, profile_names, simulate};

use crate::common;
use common::sim::*;

#[test]
fn profiles_are_the_ones_asked_for() {
    let names = profile_names();
    for n in [
        "calibration",
        "validation",
        "no-plateaus",
        "fast-ramps",
        "square-steps",
        "yan-steps-low",
        "yan-steps-mid",
        "yan-steps-high",
        "yan-full-range",
        "laser-gyro",
        "mems-imu",
    ] {
        assert!(names.contains(&n), "{n} missing");
    }
    assert!(profile("no-such-profile").is_none());
    let gyro = GyroParams::default();
    for name in names {
        let p = profile(name).unwrap();
        assert_eq!(&p.name, name);
        assert!(!p.description.is_empty());
        assert_eq!(p.sample_rate_hz, 1.0);
        // The fibre-optic profiles run one gyro; the MEMS IMU is a board of its own.
        if *name == "mems-imu" {
            assert_eq!(p.axes.len(), 3);
            assert_eq!(p.accelerometers.len(), 3);
        } else {
            assert_eq!(
                p.gyro, gyro,
                "{name}: every profile runs the same gyro noise"
            );
        }
        assert_eq!(p.laser.is_some(), *name == "laser-gyro", "{name}");
        p.check().unwrap();
        // The calibration run spans -50..60 °C; only Yan's tests go to his 65 °C.
        let top = if name.starts_with("yan-") { 65.0 } else { 60.0 };
        for (_, _, a, b, _) in segments(&p) {
            assert!(
                (-50.0..=top).contains(&a) && (-50.0..=top).contains(&b),
                "{name}"
            );
        }
    }

    let cal = profile("calibration").unwrap();
    let dur_h = segments(&cal).last().unwrap().1 / 3600.0;
    assert!(
        (10.5..=12.5).contains(&dur_h),
        "calibration lasts {dur_h} h"
    );
    let plateaus: Vec<f64> = segments(&cal)
        .iter()
        .filter(|s| matches!(s.4, Segment::Hold { duration_s } if duration_s >= 5400.0))
        .map(|s| s.2)
        .collect();
    for t in [60.0, 20.0, -50.0] {
        assert!(plateaus.contains(&t), "no plateau at {t}: {plateaus:?}");
    }
    let rates = |p: &Profile| -> Vec<f64> {
        p.program
            .iter()
            .filter_map(|s| match *s {
                Segment::Ramp { rate_c_per_min, .. } => Some(rate_c_per_min),
                _ => None,
            })
            .collect()
    };
    assert!(rates(&cal).iter().all(|&r| r == 1.0));
    let val = rates(&profile("validation").unwrap());
    assert!(val.contains(&0.5) && val.contains(&1.5));
    let np = profile("no-plateaus").unwrap();
    assert!(np.program.iter().all(|s| matches!(s, Segment::Ramp { .. })));
    assert!(rates(&np).iter().all(|r| (0.7..=1.2).contains(r)));
    assert!(
        rates(&profile("fast-ramps").unwrap())
            .iter()
            .all(|&r| r == 2.0)
    );
    // "Ramps twice as fast as any in the calibration".
    let fastest = |p: &Profile| rates(p).into_iter().fold(0.0, f64::max);
    assert_eq!(
        fastest(&profile("fast-ramps").unwrap()),
        2.0 * fastest(&cal)
    );
}

/// The square-wave program of Yan (2019) §3, written out from the paper: (from, 180 min) →
/// (from → to, 20 min) → (to, 180 min) → (to → from, 20 min) → (from, 180 min).
#[test]
fn yan_steps_are_the_papers_square_waves() {
    for (name, from, to) in [
        ("yan-steps-low", -25.0, -45.0),
        ("yan-steps-mid", 10.0, -10.0),
        ("yan-steps-high", 45.0, 65.0),
    ] {
        let p = profile(name).unwrap();
        assert_eq!(p.start_c, from, "{name}");
        let segs = segments(&p);
        let want = [
            (10800.0, from, from),
            (1200.0, from, to),
            (10800.0, to, to),
            (1200.0, to, from),
            (10800.0, from, from),
        ];
        assert_eq!(segs.len(), want.len(), "{name}");
        for (s, (dur, a, b)) in segs.iter().zip(want) {
            assert!((s.1 - s.0 - dur).abs() < 1e-9, "{name}: {s:?}");
            assert_eq!((s.2, s.3), (a, b), "{name}");
            if let Segment::Ramp { rate_c_per_min, .. } = s.4 {
                assert_eq!(rate_c_per_min, 1.0, "{name}: about 1 °C/min");
            }
        }
        assert_eq!(p.sample_count(), 580 * 60 + 1);
    }
}

#[test]
fn yan_full_range_is_the_papers_program() {
    // (-25, 60 min) → (→ -45, 40 min) → (-45, 120) → (→ 65, 220) → (65, 120) → (→ 25, 80)
    // → (25, 30), at about 0.5 °C/min.
    let p = profile("yan-full-range").unwrap();
    assert_eq!(p.start_c, -25.0);
    let want = [
        (60.0, -25.0),
        (40.0, -45.0),
        (120.0, -45.0),
        (220.0, 65.0),
        (120.0, 65.0),
        (80.0, 25.0),
        (30.0, 25.0),
    ];
    let segs = segments(&p);
    assert_eq!(segs.len(), want.len());
    for (s, (min, to)) in segs.iter().zip(want) {
        assert!((s.1 - s.0 - min * 60.0).abs() < 1e-9, "{s:?}");
        assert_eq!(s.3, to);
        if let Segment::Ramp { rate_c_per_min, .. } = s.4 {
            assert_eq!(rate_c_per_min, 0.5);
        }
    }
}

#[test]
fn yan_bands_settle_sooner_when_warm() {
    // On the first ramp of each square wave, the innermost layer of the winding crosses the
    // middle of the step later than the housing, and the more so the colder the band: Yan's
    // delays shrink with temperature (863, 547, 309 s).
    let settle = |name: &str| {
        let p = profile(name).unwrap();
        let r = simulate(&p, 1);
        let (_, _, from, to, _) = segments(&p)[1];
        let (half, s) = (0.5 * (from + to), (to - from).signum());
        let crossing = |v: &[f64]| r.time_s[v.iter().position(|&x| (x - half) * s >= 0.0).unwrap()];
        crossing(&r.coil_inner_c) - crossing(&r.housing_c)
    };
    let (low, mid, high) = (
        settle("yan-steps-low"),
        settle("yan-steps-mid"),
        settle("yan-steps-high"),
    );
    assert!(low > 1.2 * mid && mid > 1.2 * high, "{low} {mid} {high} s");
}

#[test]
fn profiles_round_trip_through_json_and_old_files_still_load() {
    for name in ["laser-gyro", "yan-steps-mid"] {
        let p = profile(name).unwrap();
        let text = serde_json::to_string(&p).unwrap();
        assert_eq!(text.contains("\"laser\""), name == "laser-gyro");
        let back: Profile = serde_json::from_str(&text).unwrap();
        assert_eq!(back, p);
    }
    // A profile file written before the laser gyro existed has no `laser` field: a FOG.
    let mut v = serde_json::to_value(profile("calibration").unwrap()).unwrap();
    v.as_object_mut().unwrap().remove("laser");
    let old: Profile = serde_json::from_value(v).unwrap();
    assert!(old.laser.is_none());
    // A hand-made laser profile with an unusable constant is refused with its name.
    let mut bad = profile("laser-gyro").unwrap();
    bad.laser.as_mut().unwrap().base_tau_s = f64::NAN;
    assert_eq!(bad.check().unwrap_err().field, "laser.base_tau_s");
}
