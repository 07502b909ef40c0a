//! The chamber simulator against truths computed here, independently of its code: the
//! program's own arithmetic, the analytic quasi-steady ramp of a cylindrical shell, the K0
//! parabola from the gyro's constants, and the paper's magnitudes.

use driftlab::ingest::{self, ReadOptions};
use driftlab::sim::{
    Coil, GyroParams, LaserParams, Profile, Segment, SimRun, profile, profile_names, simulate,
    simulate_noise_only, simulate_with_progress,
};

/// Centred moving average over `w` samples, full windows only.
fn centred_ma(x: &[f64], w: usize) -> Vec<f64> {
    let lo = w / 2;
    (lo..x.len() + lo - w + 1)
        .map(|i| x[i - lo..i - lo + w].iter().sum::<f64>() / w as f64)
        .collect()
}

fn p2p(x: &[f64]) -> f64 {
    let max = x.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let min = x.iter().cloned().fold(f64::INFINITY, f64::min);
    max - min
}

/// K0 from the constants, written out here rather than taken from the crate.
fn k0(g: &GyroParams, t: f64) -> f64 {
    g.bias_20c_dph
        + g.bias_slope_dph_per_c * (t - 20.0)
        + g.bias_curvature_dph_per_c2 * (t - 20.0) * (t - 20.0)
}

/// (start time, end time, start temperature, end temperature, segment) of every segment.
fn segments(p: &Profile) -> Vec<(f64, f64, f64, f64, Segment)> {
    let (mut t, mut temp) = (0.0, p.start_c);
    let mut out = Vec::new();
    for seg in &p.program {
        let (dur, to) = match *seg {
            Segment::Hold { duration_s } => (duration_s, temp),
            Segment::Ramp {
                to_c,
                rate_c_per_min,
            } => ((to_c - temp).abs() / (rate_c_per_min / 60.0), to_c),
        };
        out.push((t, t + dur, temp, to, *seg));
        t += dur;
        temp = to;
    }
    out
}

/// Index of the last sample at or before `t`.
fn index_at(run: &SimRun, t: f64) -> usize {
    run.time_s.partition_point(|&x| x <= t + 1e-9) - 1
}

fn step_profile(from_c: f64, to_c: f64) -> Profile {
    Profile {
        name: "step".into(),
        description: "a near-step for lag measurements".into(),
        sample_rate_hz: 1.0,
        start_c: from_c,
        program: vec![
            Segment::Hold { duration_s: 600.0 },
            Segment::Ramp {
                to_c,
                rate_c_per_min: 600.0,
            },
            Segment::Hold {
                duration_s: 6.0 * 3600.0,
            },
        ],
        gyro: GyroParams::default(),
        laser: None,
    }
}

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
        assert_eq!(
            p.gyro, gyro,
            "{name}: every profile runs the same gyro noise"
        );
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
fn same_seed_same_run_other_seed_other_noise_same_drift() {
    let p = profile("fast-ramps").unwrap();
    let a = simulate(&p, 7);
    let b = simulate(&p, 7);
    let c = simulate(&p, 8);
    assert_eq!(a.time_s, b.time_s);
    assert_eq!(a.omega_dph, b.omega_dph);
    assert_eq!(a.temp_c, b.temp_c);
    assert_eq!(a.noise_dph, b.noise_dph);
    assert_eq!(
        a.thermal_dph, c.thermal_dph,
        "the drift does not depend on the seed"
    );
    assert_eq!(a.chamber_c, c.chamber_c);
    assert_eq!(a.housing_c, c.housing_c);
    let differ = a
        .noise_dph
        .iter()
        .zip(&c.noise_dph)
        .filter(|(x, y)| x != y)
        .count();
    assert!(
        differ > a.len() * 99 / 100,
        "only {differ} noise samples differ"
    );
    // A fixed sample of the seed-7 noise: the same on every machine (ChaCha8 + StandardNormal).
    assert!(a.noise_dph.iter().all(|x| x.is_finite()));
}

#[test]
fn output_is_drift_plus_noise_and_temperature_is_quantised() {
    let p = profile("calibration").unwrap();
    let r = simulate(&p, 3);
    let n = p.sample_count();
    for col in [
        &r.time_s,
        &r.chamber_c,
        &r.temp_c,
        &r.omega_dph,
        &r.thermal_dph,
        &r.noise_dph,
    ] {
        assert_eq!(col.len(), n);
    }
    for i in 0..n {
        assert_eq!(r.omega_dph[i], r.thermal_dph[i] + r.noise_dph[i]);
        let t = r.temp_c[i];
        assert!(((t * 1000.0).round() - t * 1000.0).abs() < 1e-6, "{t}");
        assert_eq!(format!("{t:.3}").parse::<f64>().unwrap(), t);
        assert!((t - r.housing_c[i]).abs() < 0.003, "sensor noise is tiny");
        assert_eq!(r.time_s[i], i as f64);
    }
}

#[test]
fn chamber_follows_the_program() {
    for name in profile_names() {
        let p = profile(name).unwrap();
        let r = simulate(&p, 1);
        let segs = segments(&p);
        assert!((r.time_s.last().unwrap() - segs.last().unwrap().1).abs() <= 1.0);
        for (t0, t1, from, to, seg) in segs {
            match seg {
                Segment::Hold { .. } => {
                    let i = index_at(&r, t1);
                    assert!(
                        (r.chamber_c[i] - to).abs() < 1e-9,
                        "{name}: hold end at {t1}"
                    );
                    let j = index_at(&r, t0).max(1);
                    assert!(r.chamber_c[j..=i].iter().all(|&c| (c - to).abs() < 1e-9));
                }
                Segment::Ramp { rate_c_per_min, .. } => {
                    // Least-squares slope of the samples strictly inside the ramp.
                    let (i0, i1) = (index_at(&r, t0) + 2, index_at(&r, t1) - 1);
                    let xs = &r.time_s[i0..=i1];
                    let ys = &r.chamber_c[i0..=i1];
                    let m = xs.len() as f64;
                    let (mx, my) = (xs.iter().sum::<f64>() / m, ys.iter().sum::<f64>() / m);
                    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
                    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
                    let slope_c_per_min = sxy / sxx * 60.0;
                    let want = rate_c_per_min * (to - from).signum();
                    assert!(
                        (slope_c_per_min - want).abs() < 1e-6,
                        "{name}: ramp {from}->{to} at {slope_c_per_min} °C/min, not {want}"
                    );
                }
            }
        }
    }
}

#[test]
fn coil_matches_the_quasi_steady_ramp_of_a_cylindrical_shell() {
    // Constant diffusivity, outer surface ramped at β: once the start-up transient has died,
    // every layer heats at β and T(r) − T(r_i) = β/(2K)·((r² − r_i²)/2 − r_i²·ln(r/r_i)).
    let g = GyroParams {
        coil_diffusivity_coeff_per_c: 0.0,
        ..GyroParams::default()
    };
    let k = g.coil_diffusivity_20c_m2_per_s;
    let (ri, ro) = (g.coil_inner_radius_m, g.coil_outer_radius_m);
    let beta = 1.0 / 60.0;
    let f = |r: f64| beta / (2.0 * k) * ((r * r - ri * ri) / 2.0 - ri * ri * (r / ri).ln());
    let mut coil = Coil::new(&g, 0.0);
    let dt = 1.0;
    let steps = 4 * 3600;
    for i in 0..steps {
        coil.step(beta * i as f64, beta * (i + 1) as f64, dt);
    }
    let outer = beta * steps as f64;
    let n = g.coil_layers;
    let dr = (ro - ri) / n as f64;
    for (i, &t) in coil.layers_c().iter().enumerate() {
        let r = ri + (i as f64 + 0.5) * dr;
        let want = f(ro) - f(r);
        let got = outer - t;
        assert!(
            (got - want).abs() < 0.005 * f(ro),
            "layer {i}: lag {got} °C, analytic {want} °C"
        );
    }
    // The steady lag of the innermost layer, in seconds, is the coil's delay: hundreds of s.
    let delay_s = (f(ro) - f(ri + 0.5 * dr)) / beta;
    assert!((300.0..1500.0).contains(&delay_s), "{delay_s}");
}

#[test]
fn coil_settles_everywhere_and_is_stable_for_any_step() {
    let g = GyroParams::default();
    let mut coil = Coil::new(&g, 20.0);
    coil.step(20.0, 30.0, 60.0);
    for _ in 0..(8 * 60) {
        coil.step(30.0, 30.0, 60.0);
    }
    for &t in coil.layers_c() {
        assert!((t - 30.0).abs() < 1e-6, "layer at {t} after 8 h");
    }
    // One huge step is sub-divided, never oscillates, never overshoots.
    let mut coil = Coil::new(&g, -50.0);
    coil.step(-50.0, 60.0, 3.0 * 3600.0);
    let mut prev = f64::NEG_INFINITY;
    for &t in coil.layers_c() {
        assert!(t.is_finite() && (-50.0..=60.0 + 1e-9).contains(&t), "{t}");
        assert!(t >= prev, "heated from outside: warmer towards the outside");
        prev = t;
    }
}

#[test]
fn after_a_long_hold_everything_is_at_the_hold_temperature() {
    let g = GyroParams::default();
    for (from, to) in [(20.0, -45.0), (-10.0, 55.0)] {
        let mut p = step_profile(from, to);
        p.program[1] = Segment::Ramp {
            to_c: to,
            rate_c_per_min: 1.0,
        };
        let r = simulate(&p, 5);
        let i = r.len() - 1;
        assert!((r.housing_c[i] - to).abs() < 1e-4);
        assert!(
            (r.coil_inner_c[i] - to).abs() < 1e-4,
            "{}",
            r.coil_inner_c[i]
        );
        assert!((r.coil_mean_c[i] - to).abs() < 1e-4);
        assert!((r.temp_c[i] - to).abs() <= 0.0025);
        assert!(
            (r.thermal_dph[i] - k0(&g, to)).abs() < 1e-3,
            "drift {} on the plateau, K0 {}",
            r.thermal_dph[i],
            k0(&g, to)
        );
    }
    // The calibration plateaus (2 h) settle closely enough for K0 to be read off them.
    let p = profile("calibration").unwrap();
    let r = simulate(&p, 5);
    for (_, t1, _, to, seg) in segments(&p) {
        if matches!(seg, Segment::Hold { .. }) {
            let i = index_at(&r, t1);
            let e = r.thermal_dph[i] - k0(&g, to);
            assert!(e.abs() < 0.01, "plateau {to}: drift − K0 = {e}");
        }
    }
}

/// Time for the innermost coil layer to make half of a small near-step, minus the time the
/// housing takes, s.
fn coil_half_lag_s(from: f64, to: f64) -> f64 {
    let r = simulate(&step_profile(from, to), 1);
    let half = 0.5 * (from + to);
    let s = (to - from).signum();
    let crossing = |v: &[f64]| r.time_s[v.iter().position(|&x| (x - half) * s >= 0.0).unwrap()];
    crossing(&r.coil_inner_c) - crossing(&r.housing_c)
}

#[test]
fn coil_lags_less_when_warm() {
    let cold = coil_half_lag_s(-40.0, -35.0);
    let warm = coil_half_lag_s(50.0, 55.0);
    assert!(
        (600.0..1500.0).contains(&cold),
        "lag at -40 °C: {cold} s (Yan: ~860 s low band)"
    );
    assert!(
        (200.0..600.0).contains(&warm),
        "lag at +50 °C: {warm} s (Yan: ~310 s high band)"
    );
    assert!(warm < 0.6 * cold, "warm {warm} s vs cold {cold} s");
    // Cooling steps lag too, and also less when warm.
    assert!(coil_half_lag_s(55.0, 50.0) < 0.6 * coil_half_lag_s(-35.0, -40.0));
}

#[test]
fn drift_differs_between_thermal_acceleration_and_deceleration() {
    // On the 20 → 60 °C ramp of the calibration run, pick the frame rate 0.5 °C/min once while
    // it speeds up (Ṫ·T̈ > 0) and once while it slows down after the ramp (Ṫ·T̈ < 0).
    let p = profile("calibration").unwrap();
    let g = &p.gyro;
    let r = simulate(&p, 1);
    let segs = segments(&p);
    let (t_start, t_end) = (segs[1].0, segs[1].1);
    let rate = |i: usize| (r.housing_c[i + 1] - r.housing_c[i - 1]) / 2.0 * 60.0;
    let excess = |i: usize| r.thermal_dph[i] - k0(g, r.housing_c[i]);
    let i_acc = (index_at(&r, t_start) + 1..)
        .find(|&i| rate(i) >= 0.5)
        .unwrap();
    let i_dec = (index_at(&r, t_end) + 1..)
        .find(|&i| rate(i) <= 0.5)
        .unwrap();
    let (acc, dec) = (excess(i_acc), excess(i_dec));
    assert!(acc > 0.05 && dec > 0.05, "heating drift {acc}, {dec}");
    assert!(
        (acc - dec).abs() > 0.1,
        "same Ṫ, opposite T̈: {acc} vs {dec} °/h"
    );
}

#[test]
fn magnitudes_match_the_paper() {
    let p = profile("calibration").unwrap();
    for seed in [1, 2] {
        let r = simulate(&p, seed);
        let drift = p2p(&centred_ma(&r.thermal_dph, 100));
        let noise = p2p(&centred_ma(&r.noise_dph, 100));
        assert!((1.2..=2.5).contains(&drift), "filtered drift p2p {drift}");
        assert!((0.05..=0.25).contains(&noise), "filtered noise p2p {noise}");
        // Raw output strongly noisy: per-sample white σ of a few tenths of °/h.
        let diffs: Vec<f64> = r.noise_dph.windows(2).map(|w| w[1] - w[0]).collect();
        let sigma = (diffs.iter().map(|d| d * d).sum::<f64>() / diffs.len() as f64 / 2.0).sqrt();
        assert!((0.1..=0.5).contains(&sigma), "white σ {sigma}");
    }
}

#[test]
fn noise_has_the_statistics_of_its_constants() {
    let mut p = step_profile(20.0, 20.0);
    p.program = vec![Segment::Hold {
        duration_s: 40.0 * 3600.0,
    }];
    // White part: first differences of white noise have variance 2σ², σ = 60·ARW·√fs.
    let r = simulate(&p, 21);
    let want = 60.0 * p.gyro.arw_deg_per_sqrt_h * p.sample_rate_hz.sqrt();
    let diffs: Vec<f64> = r.noise_dph.windows(2).map(|w| w[1] - w[0]).collect();
    let sigma = (diffs.iter().map(|d| d * d).sum::<f64>() / diffs.len() as f64 / 2.0).sqrt();
    assert!(
        (sigma / want - 1.0).abs() < 0.02,
        "white σ {sigma}, want {want}"
    );

    // Gauss-Markov part alone: standard deviation and correlation e⁻¹ at one correlation time.
    p.gyro.arw_deg_per_sqrt_h = 0.0;
    p.gyro.rrw_dph_per_sqrt_h = 0.0;
    let x = simulate(&p, 22).noise_dph;
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / n;
    let sd = var.sqrt();
    let want = p.gyro.bias_instability_dph;
    assert!(
        (sd / want - 1.0).abs() < 0.25,
        "Gauss-Markov σ {sd}, want {want}"
    );
    let lag = p.gyro.bias_correlation_s as usize;
    let cov = x
        .iter()
        .zip(&x[lag..])
        .map(|(a, b)| (a - m) * (b - m))
        .sum::<f64>()
        / (n - lag as f64);
    let rho = cov / var;
    assert!(
        (0.2..0.55).contains(&rho),
        "correlation at τ: {rho}, want ≈ 0.37"
    );
}

#[test]
fn progress_is_reported_up_to_one() {
    let p = profile("fast-ramps").unwrap();
    let seen = std::cell::RefCell::new(Vec::new());
    let r = simulate_with_progress(&p, 1, &|f| seen.borrow_mut().push(f));
    let seen = seen.into_inner();
    assert!(seen.len() > 10);
    assert!(seen.windows(2).all(|w| w[0] <= w[1]));
    assert_eq!(*seen.last().unwrap(), 1.0);
    assert_eq!(r.len(), p.sample_count());
}

#[test]
fn to_log_carries_the_chamber_as_a_channel() {
    let p = profile("fast-ramps").unwrap();
    let r = simulate(&p, 1);
    let log = r.to_log("sim:fast-ramps");
    assert_eq!(log.source, "sim:fast-ramps");
    assert_eq!(log.time_s, r.time_s);
    assert_eq!(log.omega_dph, r.omega_dph);
    assert_eq!(log.temp_c, r.temp_c);
    assert_eq!(log.channel("temp_chamber_c").unwrap().values, r.chamber_c);
    assert_eq!(log.nominal_dt_s(), 1.0);
}

fn read_back(path: &std::path::Path) -> (Vec<String>, Vec<[f64; 4]>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head = vec![
        lines.next().unwrap().to_string(),
        lines.next().unwrap().to_string(),
    ];
    let rows = lines
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [f[0], f[1], f[2], f[3]]
        })
        .collect();
    (head, rows)
}

#[test]
fn csv_reads_back_at_the_written_precision() {
    let dir = tempfile::tempdir().unwrap();
    let p = profile("fast-ramps").unwrap();
    let r = simulate(&p, 11);
    let path = dir.path().join("fast.csv");
    r.write_csv(&path).unwrap();
    let (head, rows) = read_back(&path);
    assert_eq!(
        head[0],
        "# driftlab simulate --profile fast-ramps --seed 11"
    );
    assert_eq!(head[1], "time_s,omega_dph,temp_c,temp_chamber_c");
    assert_eq!(rows.len(), r.len());
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row[0], r.time_s[i]);
        assert!((row[1] - r.omega_dph[i]).abs() <= 0.5e-4 + 1e-12);
        assert_eq!(row[2], r.temp_c[i]);
        assert!((row[3] - r.chamber_c[i]).abs() <= 0.5e-3 + 1e-12);
    }

    // A faster sampling: times such as 0.1 s come back exactly too.
    let mut p = step_profile(20.0, 21.0);
    p.name = "ten-hz".into();
    p.sample_rate_hz = 10.0;
    p.program.truncate(2);
    let r = simulate(&p, 12);
    let path = dir.path().join("ten.csv");
    r.write_csv(&path).unwrap();
    let (_, rows) = read_back(&path);
    assert_eq!(rows.len(), r.len());
    assert_eq!(rows[3][0], 0.3);
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row[0], r.time_s[i]);
        assert!((row[0] - i as f64 / 10.0).abs() < 1e-9);
    }
}

/// Solves the least-squares problem `X·b ≈ y` for the columns `cols` (each standardised, so
/// that the normal equations stay well conditioned), returning b and the residual sum of
/// squares.
fn least_squares(cols: &[Vec<f64>], y: &[f64]) -> (Vec<f64>, f64) {
    let k = cols.len();
    let n = y.len() as f64;
    // Scale of each column: its root mean square (a constant column keeps scale 1).
    let scale: Vec<f64> = cols
        .iter()
        .map(|c| {
            (c.iter().map(|v| v * v).sum::<f64>() / n)
                .sqrt()
                .max(1e-300)
        })
        .collect();
    let mut a = vec![vec![0.0; k + 1]; k];
    for i in 0..k {
        for j in 0..k {
            a[i][j] = cols[i]
                .iter()
                .zip(&cols[j])
                .map(|(x, z)| x * z)
                .sum::<f64>()
                / (scale[i] * scale[j]);
        }
        a[i][k] = cols[i].iter().zip(y).map(|(x, v)| x * v).sum::<f64>() / scale[i];
    }
    // Gauss-Jordan with partial pivoting.
    for c in 0..k {
        let piv = (c..k)
            .max_by(|&p, &q| a[p][c].abs().total_cmp(&a[q][c].abs()))
            .unwrap();
        a.swap(c, piv);
        let pivot = a[c].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != c {
                let f = row[c] / pivot[c];
                for (x, p) in row[c..].iter_mut().zip(&pivot[c..]) {
                    *x -= f * p;
                }
            }
        }
    }
    let b: Vec<f64> = (0..k).map(|i| a[i][k] / a[i][i] / scale[i]).collect();
    let sse = y
        .iter()
        .enumerate()
        .map(|(s, v)| {
            let pred: f64 = (0..k).map(|i| b[i] * cols[i][s]).sum();
            (v - pred) * (v - pred)
        })
        .sum();
    (b, sse)
}

/// The laser-gyro run written as CSV and read back by the engine's reader.
fn laser_log(seed: u64) -> (SimRun, driftlab::Log) {
    let dir = tempfile::tempdir().unwrap();
    let run = simulate(&profile("laser-gyro").unwrap(), seed);
    let path = dir.path().join("laser.csv");
    run.write_csv(&path).unwrap();
    let log = ingest::read_path(&path, &ReadOptions::default()).unwrap();
    (run, log)
}

#[test]
fn laser_channels_are_logged_and_read_back_by_name() {
    let (run, log) = laser_log(1);
    assert_eq!(log.len(), run.len());
    assert!(log.time_s == run.time_s);
    // The resonator-base sensor is the first temperature column: the calibration temperature.
    assert!(log.temp_c == run.temp_c);
    assert_eq!(
        log.extra
            .iter()
            .map(|c| c.name.as_str())
            .collect::<Vec<_>>(),
        [
            "temp_chamber_c",
            "temp_housing_c",
            "laser_power_mw",
            "piezo_v",
            "dither_amp_arcsec"
        ]
    );
    for c in &run.channels {
        // The channels are quantised to the decimals written: they read back exactly.
        assert!(
            log.channel(&c.name).unwrap().values == c.values,
            "{}",
            c.name
        );
    }
    assert_eq!(log.channel("temp_housing_c").unwrap().unit, "°C");
    let from_run = run.to_log("sim:laser-gyro");
    let names = |l: &driftlab::Log| l.extra.iter().map(|c| c.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&from_run), names(&log));
    assert!(from_run.temp_c == log.temp_c);
    assert_eq!(from_run.channel("laser_power_mw").unwrap().unit, "mW");

    // Realistic, slowly varying channels within their ranges.
    let l = LaserParams::default();
    let range = |name: &str| {
        let v = &log.channel(name).unwrap().values;
        (
            v.iter().cloned().fold(f64::INFINITY, f64::min),
            v.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
        )
    };
    let (pmin, pmax) = range("laser_power_mw");
    assert!(
        pmin > 0.6 && pmax < 0.95 && pmax - pmin > 0.1,
        "{pmin}..{pmax}"
    );
    let (umin, umax) = range("piezo_v");
    assert!(
        umin > 40.0 && umax < 170.0 && umax - umin > 60.0,
        "{umin}..{umax}"
    );
    let (amin, amax) = range("dither_amp_arcsec");
    let band = l.dither_band_arcsec + l.dither_drive_step_arcsec;
    assert!(
        amin > l.dither_setpoint_arcsec - band - 0.5
            && amax < l.dither_setpoint_arcsec + band + 0.5,
        "stabilised: {amin}..{amax}"
    );
    assert!(amax - amin > 2.0, "but moving: {amin}..{amax}");

    // Self-heating: powered on in a constant chamber, the base warms by both self-heating
    // rises, the housing by its own, within the first two hours.
    let i = index_at(&run, 7000.0);
    let rise_base = log.temp_c[i] - log.temp_c[0];
    let rise_housing = log.channel("temp_housing_c").unwrap().values[i] - 20.0;
    let want_base = l.housing_self_heating_c + l.base_self_heating_c;
    assert!(
        (rise_base - want_base).abs() < 0.1,
        "base rose {rise_base} °C"
    );
    assert!((rise_housing - l.housing_self_heating_c).abs() < 0.05);
}

#[test]
fn laser_drift_is_sukhanovs_model_with_its_self_heating_term() {
    // Fit Ω = k0 + k1·T + k2·T² + B1·(1 − e^(−t/λ)) + B2·ΔT + B3·ΔT² + B4·A + B5·P + B6·U on the
    // noise-free drift, with the channels as the reader gets them from the CSV, λ by a search:
    // the profile's constants come back.
    let (run, log) = laser_log(2);
    let l = LaserParams::default();
    let t = &log.time_s;
    let tr: Vec<f64> = log.temp_c.iter().map(|v| v - 20.0).collect();
    let th = &log.channel("temp_housing_c").unwrap().values;
    let dt: Vec<f64> = th.iter().zip(&log.temp_c).map(|(h, r)| h - r).collect();
    let ch = |name: &str, offset: f64| -> Vec<f64> {
        log.channel(name)
            .unwrap()
            .values
            .iter()
            .map(|v| v - offset)
            .collect()
    };
    let fixed = vec![
        vec![1.0; t.len()],
        tr.clone(),
        tr.iter().map(|v| v * v).collect(),
        dt.clone(),
        dt.iter().map(|v| v * v).collect(),
        ch("dither_amp_arcsec", 400.0),
        ch("laser_power_mw", 0.8),
        ch("piezo_v", 100.0),
    ];
    let fit = |lambda: f64| {
        let mut cols = fixed.clone();
        cols.push(t.iter().map(|s| 1.0 - (-s / lambda).exp()).collect());
        least_squares(&cols, &run.thermal_dph)
    };
    let mut best = (f64::INFINITY, 0.0);
    for lambda in (6..=144).map(|k| k as f64 * 50.0) {
        best = best.min_by_key_sse(lambda, fit(lambda).1);
    }
    let coarse = best.1;
    for lambda in (-50..=50).map(|k| coarse + k as f64) {
        best = best.min_by_key_sse(lambda, fit(lambda).1);
    }
    let lambda = best.1;
    let (b, _) = fit(lambda);
    let rel = |got: f64, want: f64| (got / want - 1.0).abs();
    assert!(
        rel(lambda, l.self_heating_tau_s) < 0.03,
        "λ {lambda} s, want {}",
        l.self_heating_tau_s
    );
    assert!(
        rel(b[8], l.b1_self_heating_dph) < 0.03,
        "B1 {}, want {}",
        b[8],
        l.b1_self_heating_dph
    );
    for (i, want, what) in [
        (1, l.bias_slope_dph_per_c, "k1"),
        (3, l.b2_dph_per_c, "B2"),
        (4, l.b3_dph_per_c2, "B3"),
        (5, l.b4_dph_per_arcsec, "B4"),
        (6, l.b5_dph_per_mw, "B5"),
        (7, l.b6_dph_per_v, "B6"),
    ] {
        assert!(rel(b[i], want) < 0.05, "{what} {} want {want}", b[i]);
    }

    // The self-heating term itself is in the truth, with its shape.
    let truth = run.laser.as_ref().unwrap();
    for &s in &[0.0, 1800.0, 7200.0] {
        let i = index_at(&run, s);
        let want = l.b1_self_heating_dph * (1.0 - (-s / l.self_heating_tau_s).exp());
        assert!((truth.self_heating_dph[i] - want).abs() < 1e-12);
    }
    // The drift spans a few tenths of °/h filtered, several times the filtered noise.
    let drift = p2p(&centred_ma(&run.thermal_dph, 100));
    let noise = p2p(&centred_ma(&run.noise_dph, 100));
    assert!((0.25..=1.0).contains(&drift), "filtered drift p2p {drift}");
    assert!(drift > 2.0 * noise, "{drift} vs noise {noise}");
}

/// Keeps the (SSE, λ) pair of the smaller SSE.
trait MinSse {
    fn min_by_key_sse(self, lambda: f64, sse: f64) -> Self;
}

impl MinSse for (f64, f64) {
    fn min_by_key_sse(self, lambda: f64, sse: f64) -> Self {
        if sse < self.0 { (sse, lambda) } else { self }
    }
}

#[test]
fn noise_only_run_is_the_noise_of_the_full_run() {
    for name in ["fast-ramps", "laser-gyro"] {
        let p = profile(name).unwrap();
        let full = simulate(&p, 9);
        let quiet = simulate_noise_only(&p, 9);
        assert!(quiet.noise_only && !full.noise_only);
        assert!(quiet.time_s == full.time_s, "{name}: same time grid");
        assert!(
            quiet.omega_dph == full.noise_dph,
            "{name}: same noise samples"
        );
        assert!(quiet.noise_dph == full.noise_dph);
        assert!(quiet.thermal_dph.iter().all(|&x| x == 0.0));
        assert!(quiet.temp_c == full.temp_c);
        assert!(quiet.chamber_c == full.chamber_c);
        assert!(quiet.channels == full.channels);
        for i in 0..full.len() {
            // Full output minus the noise floor is the deterministic drift (to the rounding of
            // the one addition that made the output).
            let d = full.omega_dph[i] - quiet.omega_dph[i];
            assert!(
                (d - full.thermal_dph[i]).abs() <= 1e-12,
                "{name} sample {i}"
            );
        }
        if let Some(l) = &quiet.laser {
            assert!(l.self_heating_dph.iter().all(|&x| x == 0.0));
        }
        // Its CSV says what it is and differs from the full one by the drift alone.
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("full.csv"), dir.path().join("noise.csv"));
        full.write_csv(&a).unwrap();
        quiet.write_csv(&b).unwrap();
        let text = std::fs::read_to_string(&b).unwrap();
        assert_eq!(
            text.lines().next().unwrap(),
            format!("# driftlab simulate --profile {name} --seed 9 --noise-only")
        );
        let la = ingest::read_path(&a, &ReadOptions::default()).unwrap();
        let lb = ingest::read_path(&b, &ReadOptions::default()).unwrap();
        assert!(la.time_s == lb.time_s);
        assert!(la.temp_c == lb.temp_c);
        assert!(la.extra == lb.extra);
        for i in 0..la.len() {
            let d = la.omega_dph[i] - lb.omega_dph[i];
            assert!(
                (d - full.thermal_dph[i]).abs() <= 1e-4 + 1e-9,
                "{name} row {i}"
            );
        }
    }
}

fn driftlab_cli(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .output()
        .expect("driftlab runs")
}

#[test]
fn cli_lists_the_profiles_and_writes_noise_only() {
    let help = driftlab_cli(&["simulate", "--help"]);
    let help = String::from_utf8(help.stdout).unwrap();
    for name in profile_names() {
        assert!(help.contains(name), "--help lists {name}");
    }
    assert!(help.contains("--noise-only"));

    let dir = tempfile::tempdir().unwrap();
    let full = dir.path().join("full.csv");
    let quiet = dir.path().join("quiet.csv");
    for (path, extra) in [(&full, None), (&quiet, Some("--noise-only"))] {
        let mut args = vec![
            "simulate",
            "--profile",
            "yan-steps-high",
            "--seed",
            "4",
            "--out",
            path.to_str().unwrap(),
        ];
        args.extend(extra);
        let out = driftlab_cli(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let run = simulate(&profile("yan-steps-high").unwrap(), 4);
    let a = ingest::read_path(&full, &ReadOptions::default()).unwrap();
    let b = ingest::read_path(&quiet, &ReadOptions::default()).unwrap();
    assert!(a.time_s == run.time_s);
    assert!(b.time_s == run.time_s);
    for i in 0..run.len() {
        assert!((b.omega_dph[i] - run.noise_dph[i]).abs() <= 0.5e-4 + 1e-12);
        let d = a.omega_dph[i] - b.omega_dph[i];
        assert!((d - run.thermal_dph[i]).abs() <= 1e-4 + 1e-9);
    }
    let bad = driftlab_cli(&["simulate", "--profile", "moon", "--out", "x.csv"]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("laser-gyro"));
}

#[test]
fn sample_logs_are_what_their_first_line_says() {
    // Every bundled log is remade, byte for byte, by the command on its first line.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs");
    let mut seen = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("csv") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let first = text.lines().next().unwrap();
        let words: Vec<&str> = first.split_whitespace().collect();
        assert_eq!(
            &words[..4],
            ["#", "driftlab", "simulate", "--profile"],
            "{first}"
        );
        let name = words[4];
        assert_eq!(words[5], "--seed");
        let seed: u64 = words[6].parse().unwrap();
        let mut run = simulate(&profile(name).unwrap(), seed);
        if words.get(7) == Some(&"--noise-only") {
            run = run.noise_only();
        }
        let out = tempfile::tempdir().unwrap();
        let remade = out.path().join("x.csv");
        run.write_csv(&remade).unwrap();
        assert!(
            std::fs::read_to_string(&remade).unwrap() == text,
            "{} differs from `{first}`",
            path.display()
        );
        seen.push(path.file_stem().unwrap().to_string_lossy().to_string());
    }
    for name in [
        "calibration",
        "validation",
        "yan-steps-low",
        "yan-steps-mid",
        "yan-steps-high",
        "yan-full-range",
        "laser-gyro",
    ] {
        assert!(
            seen.iter().any(|s| s == name),
            "sample_logs/{name}.csv missing"
        );
    }
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
    assert!(bad.check().unwrap_err().contains("base_tau_s"));
}
