//! The chamber simulator against truths computed here, independently of its code: seeds and
//! noise, the chamber following the program, the analytic quasi-steady ramp of a cylindrical
//! shell, the K0 parabola from the gyro's constants, and the paper's magnitudes.

use driftlab::sim::{Coil, GyroParams, Segment, profile, profile_names, simulate};

use crate::common;
use common::sim::*;

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
