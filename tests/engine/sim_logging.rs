//! How the chamber simulator's logger records a run, against truths computed here: a faster
//! log is the same history (exact at the profile's instants, the housing's lag solved in
//! closed form between them, the noise averaging back to the 1 Hz noise), a gap removes
//! exactly the samples in it, bursts hold exactly ON·rate samples, and host stamps have the
//! statistics the model states while the data stay those of the regular run.

use driftlab::sim::{
    Bursts, Gap, HostJitter, Logging, Profile, Segment, SimRun, profile, simulate, simulate_logged,
};

use crate::common;
use common::sim::*;

fn logged(p: &Profile, seed: u64, logging: Logging) -> SimRun {
    simulate_logged(p, seed, &logging, &|_| {}).unwrap()
}

fn at_rate(rate_hz: f64) -> Logging {
    Logging {
        rate_hz: Some(rate_hz),
        ..Logging::default()
    }
}

/// The housing temperature at time `t`, solved in closed form: on each segment of the
/// program the air is linear, u = u0 + s·(t − t0), and y' = (u − y)/τ has the solution
/// y = u − s·τ + (y0 − u0 + s·τ)·e^(−(t − t0)/τ).
fn housing_exact(p: &Profile, t: f64) -> f64 {
    let tau = p.gyro.housing_tau_s;
    let mut y = p.start_c;
    for (t0, t1, from, to, _) in segments(p) {
        let s = if t1 > t0 {
            (to - from) / (t1 - t0)
        } else {
            0.0
        };
        let end = t.min(t1);
        let u_end = from + s * (end - t0);
        y = u_end - s * tau + (y - from + s * tau) * (-(end - t0) / tau).exp();
        if t <= t1 {
            return y;
        }
    }
    y
}

#[test]
fn a_faster_log_is_the_same_history() {
    let p = profile("fast-ramps").unwrap();
    let slow = simulate(&p, 3);
    let fast = logged(&p, 3, at_rate(10.0));
    let n = slow.len();
    assert_eq!(fast.len(), (n - 1) * 10 + 1);
    assert_eq!(fast.sample_rate_hz, 10.0);
    let mut worst_housing: f64 = 0.0;
    let mut worst_drift: f64 = 0.0;
    for (k, &t) in fast.time_s.iter().enumerate() {
        assert!((t - k as f64 / 10.0).abs() < 1e-9, "sample {k} at {t} s");
        let (i, j) = (k / 10, k % 10);
        if j == 0 {
            // The profile's instants: the 1 Hz run's state and readings, bit for bit.
            assert_eq!(fast.thermal_dph[k], slow.thermal_dph[i], "drift at {t} s");
            assert_eq!(fast.housing_c[k], slow.housing_c[i]);
            assert_eq!(fast.coil_mean_c[k], slow.coil_mean_c[i]);
            assert_eq!(fast.coil_inner_c[k], slow.coil_inner_c[i]);
            assert_eq!(fast.temp_c[k], slow.temp_c[i]);
            assert_eq!(fast.chamber_c[k], slow.chamber_c[i]);
        } else {
            // Between them the state lies on the line between the 1 Hz states: the housing
            // within the curvature of the lag's exact solution, the drift close to the line
            // between the 1 Hz drifts (no sawtooth).
            worst_housing = worst_housing.max((fast.housing_c[k] - housing_exact(&p, t)).abs());
            let f = j as f64 / 10.0;
            let line = slow.thermal_dph[i] * (1.0 - f) + slow.thermal_dph[i + 1] * f;
            worst_drift = worst_drift.max((fast.thermal_dph[k] - line).abs());
        }
        assert_eq!(fast.omega_dph[k], fast.thermal_dph[k] + fast.noise_dph[k]);
    }
    assert!(
        worst_housing < 2e-5,
        "housing off the exact lag by {worst_housing} °C"
    );
    assert!(
        worst_drift < 1e-5,
        "drift off the 1 Hz line by {worst_drift} °/h"
    );
    // The angle does not depend on the logging rate: each second's ten noise samples average
    // to the 1 Hz run's noise of that second.
    for i in 0..n - 1 {
        let mean = fast.noise_dph[i * 10..i * 10 + 10].iter().sum::<f64>() / 10.0;
        assert!((mean - slow.noise_dph[i]).abs() < 1e-12, "second {i}");
    }
    // And the faster white noise has the σ of its rate: 60·ARW·√fs.
    let want = 60.0 * p.gyro.arw_deg_per_sqrt_h * 10f64.sqrt();
    let diffs: Vec<f64> = fast.noise_dph.windows(2).map(|w| w[1] - w[0]).collect();
    let sigma = (diffs.iter().map(|d| d * d).sum::<f64>() / diffs.len() as f64 / 2.0).sqrt();
    assert!(
        (sigma / want - 1.0).abs() < 0.02,
        "white σ {sigma}, want {want}"
    );
}

#[test]
fn fifty_hertz_on_a_ramp_and_a_laser_gyro() {
    let p = ramp_profile(0.25, 20.0, 30.0);
    let slow = simulate(&p, 5);
    let fast = logged(&p, 5, at_rate(50.0));
    assert_eq!(fast.len(), (slow.len() - 1) * 50 + 1);
    for i in 0..slow.len() {
        assert_eq!(fast.thermal_dph[i * 50], slow.thermal_dph[i]);
        assert_eq!(fast.temp_c[i * 50], slow.temp_c[i]);
    }
    for i in 0..slow.len() - 1 {
        let mean = fast.noise_dph[i * 50..i * 50 + 50].iter().sum::<f64>() / 50.0;
        assert!((mean - slow.noise_dph[i]).abs() < 1e-12);
    }
    // The laser gyro too: its state at the profile's instants and its channels there.
    let mut lp = profile("laser-gyro").unwrap();
    lp.program.truncate(2);
    let slow = simulate(&lp, 2);
    let fast = logged(&lp, 2, at_rate(4.0));
    let (ls, lf) = (slow.laser.as_ref().unwrap(), fast.laser.as_ref().unwrap());
    for i in 0..slow.len() {
        assert_eq!(fast.thermal_dph[i * 4], slow.thermal_dph[i]);
        assert_eq!(lf.base_c[i * 4], ls.base_c[i]);
        assert_eq!(lf.dither_amp_arcsec[i * 4], ls.dither_amp_arcsec[i]);
        for (a, b) in fast.channels.iter().zip(&slow.channels) {
            assert_eq!(a.values[i * 4], b.values[i], "{}", a.name);
        }
    }
    for i in 0..slow.len() - 1 {
        let mean = fast.noise_dph[i * 4..i * 4 + 4].iter().sum::<f64>() / 4.0;
        assert!((mean - slow.noise_dph[i]).abs() < 1e-12);
    }
}

#[test]
fn a_slower_log_keeps_the_thermal_state_at_the_common_instants() {
    let p = profile("fast-ramps").unwrap();
    let slow = simulate(&p, 3);
    let half = logged(&p, 3, at_rate(0.5));
    assert_eq!(half.len(), (slow.len() - 1) / 2 + 1);
    for (k, &t) in half.time_s.iter().enumerate() {
        assert_eq!(t, (2 * k) as f64);
        assert_eq!(half.thermal_dph[k], slow.thermal_dph[2 * k]);
        assert_eq!(half.housing_c[k], slow.housing_c[2 * k]);
    }
    // The noise is drawn for the 2-s interval: σ = 60·ARW/√2.
    let want = 60.0 * p.gyro.arw_deg_per_sqrt_h * 0.5f64.sqrt();
    let diffs: Vec<f64> = half.noise_dph.windows(2).map(|w| w[1] - w[0]).collect();
    let sigma = (diffs.iter().map(|d| d * d).sum::<f64>() / diffs.len() as f64 / 2.0).sqrt();
    assert!(
        (sigma / want - 1.0).abs() < 0.05,
        "white σ {sigma}, want {want}"
    );
    // A rate that is no multiple runs at that rate.
    let odd = logged(&p, 3, at_rate(3.7));
    // Samples k/3.7 s up to 15600 s: k = 0..=57720.
    assert_eq!(odd.len(), 57721);
    assert!((odd.time_s[37] - 10.0).abs() < 1e-9);
}

#[test]
fn a_gap_removes_exactly_the_samples_in_it() {
    let p = profile("fast-ramps").unwrap();
    let full = logged(&p, 4, at_rate(10.0));
    let gaps = vec![
        Gap {
            start_s: 3600.0,
            duration_s: 1800.0,
        },
        "9000:0.55".parse::<Gap>().unwrap(),
    ];
    let cut = logged(
        &p,
        4,
        Logging {
            gaps: gaps.clone(),
            ..at_rate(10.0)
        },
    );
    // Samples k/10 s with 36000 ≤ k < 54000, and 90000 ≤ k < 90005.5: 18000 + 6.
    assert_eq!(cut.len(), full.len() - 18006);
    for &t in &cut.time_s {
        assert!(
            !(3600.0..5400.0).contains(&t) && !(9000.0..9000.55).contains(&t),
            "{t}"
        );
    }
    // Around the gap: the last sample before it and the first after it.
    let before = cut.time_s.iter().rposition(|&t| t < 3600.0).unwrap();
    assert!((cut.time_s[before] - 3599.9).abs() < 1e-9);
    assert_eq!(cut.time_s[before + 1], 5400.0);
    // What is left is the continuous log's samples, untouched.
    let pairs = matching_samples(&cut.time_s, &full.time_s);
    assert_eq!(pairs.len(), cut.len());
    for (i, j) in pairs {
        assert_eq!(cut.omega_dph[i], full.omega_dph[j]);
        assert_eq!(cut.temp_c[i], full.temp_c[j]);
        assert_eq!(cut.thermal_dph[i], full.thermal_dph[j]);
    }
    assert_eq!(cut.logging.gaps, gaps);
    assert!(
        cut.command()
            .contains("--rate-hz 10 --gap 3600:1800 --gap 9000:0.55")
    );
}

/// The runs of consecutive samples of `time_s` (a step above 1.5 `dt` starts a new one), as
/// (first index, length).
fn bursts_of(time_s: &[f64], dt: f64) -> Vec<(usize, usize)> {
    let mut out = vec![(0, 1)];
    for i in 1..time_s.len() {
        if time_s[i] - time_s[i - 1] > 1.5 * dt {
            out.push((i, 1));
        } else {
            out.last_mut().unwrap().1 += 1;
        }
    }
    out
}

#[test]
fn bursts_hold_exactly_on_times_rate_samples() {
    let p = profile("fast-ramps").unwrap();
    let every = Bursts {
        on_s: 10.0,
        every_s: 120.0,
    };
    let full = logged(&p, 6, at_rate(50.0));
    let burst = logged(
        &p,
        6,
        Logging {
            bursts: Some(every),
            ..at_rate(50.0)
        },
    );
    let runs = bursts_of(&burst.time_s, 0.02);
    // The program lasts 15600 s: bursts start at 0, 120, ..., 15600 (131), the last one cut
    // to the final sample.
    assert_eq!(runs.len(), 131);
    for (k, &(first, len)) in runs.iter().enumerate() {
        assert_eq!(burst.time_s[first], 120.0 * k as f64, "burst {k}");
        let want = if k == 130 { 1 } else { 500 };
        assert_eq!(len, want, "burst {k} at {} s", burst.time_s[first]);
    }
    let pairs = matching_samples(&burst.time_s, &full.time_s);
    assert_eq!(pairs.len(), burst.len());
    for (i, j) in pairs {
        assert_eq!(burst.omega_dph[i], full.omega_dph[j]);
        assert_eq!(burst.temp_c[i], full.temp_c[j]);
    }
    // A gap inside a burst log takes out whole and partial bursts.
    let both = logged(
        &p,
        6,
        Logging {
            bursts: Some(every),
            gaps: vec!["245:590".parse().unwrap()],
            ..at_rate(50.0)
        },
    );
    // The gap [245, 835): the burst at 240 keeps 240..245 (250 samples), those at 360..720
    // go, the one at 840 is whole.
    let runs = bursts_of(&both.time_s, 0.02);
    assert_eq!(runs[2], (1000, 250));
    assert_eq!(both.time_s[runs[3].0], 840.0);
    assert_eq!(runs.len(), 131 - 4);
}

#[test]
fn host_stamps_bunch_but_the_data_are_the_regular_run() {
    let mut p = step_profile(20.0, 20.0);
    p.program = vec![Segment::Hold {
        duration_s: 1.5 * 3600.0,
    }];
    let regular = logged(&p, 8, at_rate(100.0));
    let model = HostJitter::default();
    let jittered = logged(
        &p,
        8,
        Logging {
            jitter: Some(model.clone()),
            ..at_rate(100.0)
        },
    );
    assert_eq!(jittered.time_s, regular.time_s);
    assert_eq!(jittered.omega_dph, regular.omega_dph);
    assert_eq!(jittered.temp_c, regular.temp_c);
    let stamps = jittered.stamp_s.as_ref().unwrap();
    assert_eq!(stamps.len(), regular.len());
    assert_eq!(jittered.logged_time_s(), &stamps[..]);

    let steps: Vec<f64> = stamps.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(steps.iter().all(|&s| s > 0.0), "stamps keep the order");
    let mut lag_max: f64 = 0.0;
    for (s, t) in stamps.iter().zip(&jittered.time_s) {
        assert!(s >= t, "a stamp is never before its sample");
        lag_max = lag_max.max(s - t);
    }
    assert!(lag_max < 1.0, "stamps lag the samples by up to {lag_max} s");
    // Over the log, the mean step is the true one.
    let mean = (stamps.last().unwrap() - stamps[0]) / steps.len() as f64;
    assert!((mean / 0.01 - 1.0).abs() < 0.002, "mean step {mean} s");
    // About half the steps are the host's 2 ms, the rest spread up to half a second.
    let per_sample = steps
        .iter()
        .filter(|&&s| (s - model.per_sample_s).abs() < 1.5e-6)
        .count() as f64
        / steps.len() as f64;
    assert!(
        (0.4..0.6).contains(&per_sample),
        "{per_sample} of the steps are 2 ms"
    );
    let longest = steps.iter().cloned().fold(0.0, f64::max);
    assert!(longest > 0.2, "longest step {longest} s");
    assert!(
        longest <= model.stall_max_s + 0.01 + 1e-6,
        "longest step {longest} s: more than a stall and a sampling step"
    );
    let mut sorted = steps.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    assert!(
        median < 0.005,
        "median step {median} s: the trap of a median sampling step"
    );
    // Stamps on the host's 1 µs clock.
    for &s in stamps.iter().take(1000) {
        assert!(((s * 1e6).round() - s * 1e6).abs() < 1e-3, "{s}");
    }
    // Deterministic per seed, other seeds other stamps.
    let again = logged(&p, 8, jittered.logging.clone());
    assert_eq!(again.stamp_s, jittered.stamp_s);
    let other = logged(&p, 9, jittered.logging.clone());
    assert_ne!(other.stamp_s, jittered.stamp_s);
    // A host that cannot keep up is refused with the option named.
    let too_fast = simulate_logged(
        &p,
        8,
        &Logging {
            jitter: Some(model),
            ..at_rate(600.0)
        },
        &|_| {},
    );
    assert!(too_fast.unwrap_err().to_string().contains("--jitter"));
}

#[test]
fn logging_options_are_checked_with_their_names() {
    let p = profile("calibration").unwrap();
    let bad = |l: Logging| simulate_logged(&p, 1, &l, &|_| {}).unwrap_err().to_string();
    assert!(bad(at_rate(0.0)).contains("--rate-hz"));
    assert!(bad(at_rate(1e6)).contains("10⁹"));
    let gap = Gap {
        start_s: 10.0,
        duration_s: f64::NAN,
    };
    assert!(
        bad(Logging {
            gaps: vec![gap],
            ..Logging::default()
        })
        .contains("--gap")
    );
    let bursts = Bursts {
        on_s: 20.0,
        every_s: 10.0,
    };
    assert!(
        bad(Logging {
            bursts: Some(bursts),
            ..Logging::default()
        })
        .contains("--bursts")
    );
}
