//! The chamber simulator's multi-axis unit against truths computed here: each axis is the
//! single-axis drift formula with its own constants (checked against single-axis runs and
//! against the formula written out on the exposed thermal field), the axes' noises are
//! independent with their own constants, and the accelerometers read what their constants say.

use driftlab::sim::{
    AxisParams, GyroParams, Logging, Profile, default_axes, profile, simulate, simulate_logged,
};

use crate::common;
use common::sim::*;

fn unit(name: &str) -> Profile {
    profile(name)
        .unwrap()
        .with_axes(3)
        .unwrap()
        .with_accelerometers()
        .unwrap()
}

/// The single gyro with axis `a`'s constants and the thermal constants of `g`, written out
/// field by field.
fn single_gyro(a: &AxisParams, g: &GyroParams) -> GyroParams {
    GyroParams {
        bias_20c_dph: a.bias_20c_dph,
        bias_slope_dph_per_c: a.bias_slope_dph_per_c,
        bias_curvature_dph_per_c2: a.bias_curvature_dph_per_c2,
        shupe_dph_per_c_per_s: a.shupe_dph_per_c_per_s,
        stress_dph_per_c: a.stress_dph_per_c,
        heating_asymmetry: a.heating_asymmetry,
        arw_deg_per_sqrt_h: a.arw_deg_per_sqrt_h,
        bias_instability_dph: a.bias_instability_dph,
        bias_correlation_s: a.bias_correlation_s,
        rrw_dph_per_sqrt_h: a.rrw_dph_per_sqrt_h,
        ..g.clone()
    }
}

fn white_sigma(x: &[f64]) -> f64 {
    let d: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    (d.iter().map(|v| v * v).sum::<f64>() / d.len() as f64 / 2.0).sqrt()
}

fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma) * (x - ma)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb) * (y - mb)).sum();
    cov / (va * vb).sqrt()
}

#[test]
fn each_axis_is_the_single_axis_run_of_its_constants() {
    let p = unit("fast-ramps");
    assert_eq!(p.axes.len(), 3);
    let run = simulate(&p, 2);
    let names: Vec<&str> = run.axes.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["x", "y", "z"]);
    for (k, a) in p.axes.iter().enumerate() {
        let single = Profile {
            gyro: single_gyro(a, &p.gyro),
            axes: Vec::new(),
            accelerometers: Vec::new(),
            ..p.clone()
        };
        let s = simulate(&single, 2);
        assert_eq!(run.axes[k].thermal_dph, s.thermal_dph, "axis {}", a.name);
        // One thermal field: the same temperatures for every axis.
        assert_eq!(run.temp_c, s.temp_c);
        assert_eq!(run.coil_mean_c, s.coil_mean_c);
        assert_eq!(run.coil_inner_c, s.coil_inner_c);
    }
    // The first axis is the single gyro, noise and all: the calibration profile's own run.
    let reference = simulate(&profile("fast-ramps").unwrap(), 2);
    assert_eq!(run.axes[0].omega_dph, reference.omega_dph);
    assert_eq!(run.omega_dph, reference.omega_dph);
    assert_eq!(run.noise_dph, run.axes[0].noise_dph);
    assert!(run.axes.iter().all(|a| a.omega_dph.len() == run.len()));
}

#[test]
fn each_axis_drift_is_the_formula_on_the_shared_field() {
    let p = unit("calibration");
    let g = &p.gyro;
    let run = simulate(&p, 1);
    assert_eq!(run.coil_gradient_c.len(), run.len());
    // K(T)/K20 and the drift of METHOD's FOG, written out here.
    let flux = |t: f64| (1.0 + g.coil_diffusivity_coeff_per_c * (t - 20.0)).max(0.05);
    for (k, a) in p.axes.iter().enumerate() {
        let axis = &run.axes[k];
        for i in (0..run.len()).step_by(7) {
            let (grad, rate) = (run.coil_gradient_c[i], run.coil_rate_gradient_c_per_s[i]);
            let t = run.coil_mean_c[i];
            let d = t - 20.0;
            let k0 =
                a.bias_20c_dph + a.bias_slope_dph_per_c * d + a.bias_curvature_dph_per_c2 * d * d;
            let asym = 1.0 + a.heating_asymmetry * (grad / 0.5).tanh();
            let shupe = a.shupe_dph_per_c_per_s * rate * asym;
            let stress = a.stress_dph_per_c * grad * flux(t) * asym;
            let want = k0 + shupe + stress;
            assert!(
                (axis.thermal_dph[i] - want).abs() < 1e-12,
                "axis {} at {i}",
                a.name
            );
            assert!((axis.static_dph[i] - k0).abs() < 1e-15);
            assert!((axis.shupe_dph[i] - shupe).abs() < 1e-12);
            assert!((axis.stress_dph[i] - stress).abs() < 1e-12);
            let parts = axis.static_dph[i] + axis.shupe_dph[i] + axis.stress_dph[i];
            assert!((axis.thermal_dph[i] - parts).abs() < 1e-12);
            assert_eq!(axis.omega_dph[i], axis.thermal_dph[i] + axis.noise_dph[i]);
        }
    }
}

#[test]
fn axes_answer_the_field_with_other_signs_and_sizes() {
    let p = unit("calibration");
    let run = simulate(&p, 1);
    let segs = segments(&p);
    // Mid-way through the 20 → 60 °C ramp the winding is warmer outside: the stress term of
    // x and z is positive, y's negative, and their sizes differ.
    let mid = index_at(&run, 0.5 * (segs[1].0 + segs[1].1));
    let stress: Vec<f64> = run.axes.iter().map(|a| a.stress_dph[mid]).collect();
    assert!(
        stress[0] > 0.05 && stress[1] < -0.05 && stress[2] > 0.05,
        "{stress:?}"
    );
    assert!((stress[2] / stress[0] - 1.0).abs() > 0.1, "{stress:?}");
    // K0 from 20 to 60 °C and to −50 °C: x's parabola opens upwards (it rises both ways),
    // z's downwards (it falls both ways), y's slope is the other way round from x's.
    let end_hold = |s: usize| index_at(&run, segs[s].1);
    let (at20, at60, at_m50) = (end_hold(0), end_hold(2), end_hold(4));
    let change = |a: usize, at: usize| run.axes[a].static_dph[at] - run.axes[a].static_dph[at20];
    assert!(change(0, at60) > 0.1 && change(0, at_m50) > 0.1);
    assert!(change(1, at60) < -0.05);
    assert!(change(2, at60) < 0.0 && change(2, at_m50) < -0.3);
    // Every axis drifts visibly above its noise (filtered as the paper filters).
    for a in &run.axes {
        let drift = p2p(&centred_ma(&a.thermal_dph, 100));
        let noise = p2p(&centred_ma(&a.noise_dph, 100));
        assert!(
            drift > 4.0 * noise,
            "axis {}: drift {drift}, noise {noise}",
            a.name
        );
    }
}

#[test]
fn axes_have_their_own_independent_noise() {
    let p = unit("fast-ramps");
    let run = simulate(&p, 3);
    for (a, axis) in p.axes.iter().zip(&run.axes) {
        let want = 60.0 * a.arw_deg_per_sqrt_h;
        let got = white_sigma(&axis.noise_dph);
        assert!(
            (got / want - 1.0).abs() < 0.03,
            "axis {}: σ {got}, want {want}",
            a.name
        );
    }
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let rho = correlation(&run.axes[i].noise_dph, &run.axes[j].noise_dph);
        assert!(rho.abs() < 0.03, "axes {i} and {j}: correlation {rho}");
    }
    let again = simulate(&p, 3);
    assert_eq!(again.axes, run.axes);
    let other = simulate(&p, 4);
    assert_ne!(other.axes[2].noise_dph, run.axes[2].noise_dph);
    assert_eq!(other.axes[2].thermal_dph, run.axes[2].thermal_dph);

    // The noise floor of every axis.
    let quiet = run.noise_only();
    for (q, a) in quiet.axes.iter().zip(&run.axes) {
        assert_eq!(q.omega_dph, a.noise_dph);
        assert!(q.thermal_dph.iter().all(|&x| x == 0.0));
    }
}

#[test]
fn accelerometers_read_gravity_with_a_small_thermal_sensitivity() {
    let p = unit("calibration");
    let run = simulate(&p, 5);
    assert_eq!(run.accelerometers.len(), 3);
    for (a, acc) in p.accelerometers.iter().zip(&run.accelerometers) {
        let d = |i: usize| run.housing_c[i] - 20.0;
        let truth = |i: usize| {
            a.gravity_g * (1.0 + a.scale_tempco_per_c * d(i))
                + a.bias_20c_g
                + a.bias_slope_g_per_c * d(i)
        };
        let mut resid = Vec::with_capacity(run.len());
        for i in 0..run.len() {
            assert!((acc.true_g[i] - truth(i)).abs() < 1e-15);
            let v = acc.values_g[i];
            assert!(
                ((v * 1e6).round() - v * 1e6).abs() < 1e-6,
                "quantised to 1 µg: {v}"
            );
            resid.push(v - truth(i));
        }
        let n = resid.len() as f64;
        let mean = resid.iter().sum::<f64>() / n;
        let sd = (resid.iter().map(|r| (r - mean) * (r - mean)).sum::<f64>() / n).sqrt();
        let want = a.noise_g_per_sqrt_hz * (0.5f64).sqrt();
        assert!(mean.abs() < 2e-7, "{}: mean residual {mean}", a.name);
        assert!(
            (sd / want - 1.0).abs() < 0.03,
            "{}: σ {sd}, want {want}",
            a.name
        );
        let span = p2p(&acc.true_g);
        assert!(
            span > 1e-4 && span < 0.015,
            "{}: thermal span {span} g",
            a.name
        );
    }
    let z = &run.accelerometers[2];
    assert!((z.values_g.iter().sum::<f64>() / run.len() as f64 - 1.0).abs() < 0.01);
}

#[test]
fn a_faster_multi_axis_log_is_the_same_history_on_every_axis() {
    let mut p = unit("fast-ramps");
    p.program.truncate(3);
    let slow = simulate(&p, 6);
    let fast = simulate_logged(
        &p,
        6,
        &Logging {
            rate_hz: Some(5.0),
            ..Logging::default()
        },
        &|_| {},
    )
    .unwrap();
    for (s, f) in slow.axes.iter().zip(&fast.axes) {
        for i in 0..slow.len() {
            assert_eq!(f.thermal_dph[i * 5], s.thermal_dph[i]);
        }
        for i in 0..slow.len() - 1 {
            let mean = f.noise_dph[i * 5..i * 5 + 5].iter().sum::<f64>() / 5.0;
            assert!((mean - s.noise_dph[i]).abs() < 1e-12, "axis {}", s.name);
        }
    }
    for (s, f) in slow.accelerometers.iter().zip(&fast.accelerometers) {
        for i in 0..slow.len() {
            assert_eq!(f.true_g[i * 5], s.true_g[i]);
        }
    }
}

#[test]
fn the_unit_is_a_fibre_optic_one_and_its_axes_are_checked() {
    let laser = profile("laser-gyro").unwrap();
    assert_eq!(laser.clone().with_axes(3).unwrap_err().field, "--axes");
    assert_eq!(
        laser.clone().with_accelerometers().unwrap_err().field,
        "--accel"
    );
    let forced = Profile {
        axes: default_axes(2).unwrap(),
        ..laser
    };
    let e = forced.check().unwrap_err();
    assert_eq!(e.field, "axes");
    assert!(e.reason.contains("laser"));
    // One axis is the single gyro again; more than three need a profile file.
    assert!(
        profile("calibration")
            .unwrap()
            .with_axes(1)
            .unwrap()
            .axes
            .is_empty()
    );
    assert_eq!(
        profile("calibration")
            .unwrap()
            .with_axes(4)
            .unwrap_err()
            .field,
        "--axes"
    );
    let mut twice = unit("calibration");
    twice.axes[1].name = "x".into();
    let e = twice.check().unwrap_err();
    assert_eq!(e.field, "axes");
    assert!(e.reason.contains("two gyro axes"));
    // A unit written as JSON reads back; a file without axes is a single gyro.
    let p = unit("validation");
    let back: Profile = serde_json::from_str(&serde_json::to_string(&p).unwrap()).unwrap();
    assert_eq!(back, p);
}

#[test]
fn the_unit_as_a_log_carries_every_axis_by_name() {
    let mut p = unit("fast-ramps");
    p.program.truncate(2);
    let run = simulate(&p, 1);
    let log = run.to_log("sim:unit");
    assert_eq!(log.omega_dph, run.axes[0].omega_dph);
    assert_eq!(
        log.channel("omega_y_dph").unwrap().values,
        run.axes[1].omega_dph
    );
    assert_eq!(
        log.channel("omega_z_dph").unwrap().values,
        run.axes[2].omega_dph
    );
    assert_eq!(
        log.channel("acc_z_g").unwrap().values,
        run.accelerometers[2].values_g
    );
    assert_eq!(log.channel("temp_chamber_c").unwrap().values, run.chamber_c);
    let names: Vec<&str> = log.info.columns.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "time_s",
            "omega_x_dph",
            "omega_y_dph",
            "omega_z_dph",
            "acc_x_g",
            "acc_y_g",
            "acc_z_g",
            "temp_c",
            "temp_chamber_c"
        ]
    );
    assert!(run.command().ends_with("--axes 3 --accel"));
}
