//! The fibre-optic gyro (or a unit of several, with accelerometers) through the chamber
//! program, one sample at a time (physics in the module doc of [`crate::sim`]).

use rand_chacha::ChaCha8Rng;

use super::axes::{AccelParams, AxisParams};
use super::noise::{self, GyroNoise, NoiseParts, Sensor};
use super::profile::{GyroParams, Profile};
use super::run::{AccelSample, AxisSample, Sample};
use super::thermal::{self, Coil, Program};
use super::{ASYMMETRY_SCALE_C, Steps};

/// The thermal state of the unit: the housing and the winding it drives.
#[derive(Debug, Clone)]
struct State {
    housing: f64,
    coil: Coil,
}

impl State {
    /// Advances from `ta` to `tb` (`h` = tb − ta, passed so that the profile's own steps stay
    /// the bits they have always been) with the air following the program.
    fn advance(&mut self, program: &Program, p: &GyroParams, ta: f64, tb: f64, h: f64) {
        let next = thermal::lag_step(
            self.housing,
            program.air_c(ta),
            program.air_c(tb),
            h,
            p.housing_tau_s,
        );
        self.coil.step(self.housing, next, h);
        self.housing = next;
    }

    /// Makes this state a copy of `other` without allocating.
    fn copy_from(&mut self, other: &State) {
        self.housing = other.housing;
        self.coil.copy_from(&other.coil);
    }

    /// Makes this state the straight line from `a` (at `f` = 0) to `b` (at `f` = 1).
    fn interpolate(&mut self, a: &State, b: &State, f: f64) {
        self.housing = a.housing + (b.housing - a.housing) * f;
        self.coil.interpolate(&a.coil, &b.coil, f);
    }
}

/// The random parts of one axis: its noise, and the stream that splits its white noise over
/// faster samples.
struct AxisNoise {
    noise: GyroNoise,
    split: ChaCha8Rng,
    /// This profile sample's noise.
    parts: NoiseParts,
    /// White noise of the faster samples of this profile sample.
    fine_white: Vec<f64>,
}

/// The random parts of one accelerometer.
struct AccelNoise {
    rng: ChaCha8Rng,
    split: ChaCha8Rng,
    /// Standard deviation of the white noise of one profile sample, g.
    sigma: f64,
    white: f64,
    fine_white: Vec<f64>,
}

/// Runs `profile` (checked, not a laser gyro), logging `fine` samples per profile sample
/// (1: the profile's own rate), and hands every sample to `sink` in time order.
pub(crate) fn run<E>(
    profile: &Profile,
    fine: usize,
    seed: u64,
    progress: &dyn Fn(f64),
    sink: &mut dyn FnMut(&Sample) -> Result<(), E>,
) -> Result<(), E> {
    let p = &profile.gyro;
    let axes = profile.unit_axes();
    let accels = &profile.accelerometers;
    let steps = Steps::of(profile, fine);
    let (dt, n, subs) = (steps.dt, steps.n, steps.subs);
    let (h, h_fine) = (steps.h, steps.h_fine);
    let (sqrt_fine, report_every) = (steps.sqrt_fine, steps.report_every);

    let program = Program::new(profile);
    let mut state = State {
        housing: profile.start_c,
        coil: Coil::new(p, profile.start_c),
    };
    // The state at the previous profile instant, and the one between it and the current.
    let mut prev = state.clone();
    let mut between = state.clone();
    let mut sensor = Sensor::new(p, seed);
    let mut fine_sensor = Sensor::on_stream(p, seed, noise::FINE_SENSOR_STREAM);
    let mut axis_noise: Vec<AxisNoise> = axes
        .iter()
        .enumerate()
        .map(|(k, a)| AxisNoise {
            noise: GyroNoise::for_axis(a, dt, seed, k),
            split: noise::rng(seed, noise::bridge_stream(k)),
            parts: NoiseParts {
                white: 0.0,
                gm: 0.0,
                rrw: 0.0,
            },
            fine_white: vec![0.0; fine],
        })
        .collect();
    let mut accel_noise: Vec<AccelNoise> = accels
        .iter()
        .enumerate()
        .map(|(k, a)| AccelNoise {
            rng: noise::rng(seed, noise::accel_stream(k)),
            split: noise::rng(seed, noise::accel_bridge_stream(k)),
            sigma: a.noise_g_per_sqrt_hz * (0.5 / dt).sqrt(),
            white: 0.0,
            fine_white: vec![0.0; fine],
        })
        .collect();
    let mut sample = Sample {
        axes: vec![AxisSample::default(); axes.len()],
        accel: vec![AccelSample::default(); accels.len()],
        ..Sample::default()
    };

    progress(0.0);
    for i in 0..n {
        let t = i as f64 * dt;
        if i > 0 {
            let t_prev = (i - 1) as f64 * dt;
            if fine > 1 {
                prev.copy_from(&state);
            }
            for k in 0..subs {
                let ta = t_prev + k as f64 * h;
                let tb = t_prev + (k + 1) as f64 * h;
                state.advance(&program, p, ta, tb, h);
            }
            // The faster samples between the previous instant and this one, in the state
            // interpolated between the two and with the previous sample's noise split.
            for j in 1..fine {
                let f = j as f64 / fine as f64;
                between.interpolate(&prev, &state, f);
                let tj = t_prev + j as f64 * h_fine;
                let temp = fine_sensor.read(between.housing);
                observe(
                    &mut sample,
                    tj,
                    &program,
                    p,
                    &axes,
                    accels,
                    &mut between,
                    temp,
                );
                for (s, a) in sample.axes.iter_mut().zip(&axis_noise) {
                    s.set_noise(a.parts.with_white(a.fine_white[j]));
                }
                for ((s, a), n) in sample.accel.iter_mut().zip(accels).zip(&accel_noise) {
                    s.set_noise(n.fine_white[j], a);
                }
                sink(&sample)?;
            }
        }
        for a in &mut axis_noise {
            a.parts = a.noise.next_parts();
        }
        for a in &mut accel_noise {
            a.white = a.sigma * noise::normal(&mut a.rng);
        }
        let temp_c = sensor.read(state.housing);
        observe(
            &mut sample,
            t,
            &program,
            p,
            &axes,
            accels,
            &mut state,
            temp_c,
        );
        if fine == 1 {
            for (s, a) in sample.axes.iter_mut().zip(&axis_noise) {
                s.set_noise(a.parts.total());
            }
            for ((s, a), n) in sample.accel.iter_mut().zip(accels).zip(&accel_noise) {
                s.set_noise(n.white, a);
            }
        } else {
            for a in &mut axis_noise {
                let sigma = a.noise.white_sigma() * sqrt_fine;
                noise::split_white(a.parts.white, sigma, &mut a.split, &mut a.fine_white);
            }
            for a in &mut accel_noise {
                let sigma = a.sigma * sqrt_fine;
                noise::split_white(a.white, sigma, &mut a.split, &mut a.fine_white);
            }
            for (s, a) in sample.axes.iter_mut().zip(&axis_noise) {
                s.set_noise(a.parts.with_white(a.fine_white[0]));
            }
            for ((s, a), n) in sample.accel.iter_mut().zip(accels).zip(&accel_noise) {
                s.set_noise(n.fine_white[0], a);
            }
        }
        sink(&sample)?;
        if i % report_every == 0 && i > 0 {
            progress(i as f64 / n as f64);
        }
    }
    progress(1.0);
    Ok(())
}

/// Fills `sample` with everything at time `t` in thermal state `st` but the noise: the
/// temperatures, the shared thermal field, every axis's drift and every accelerometer's
/// noise-free reading.
#[allow(clippy::too_many_arguments)]
fn observe(
    sample: &mut Sample,
    t: f64,
    program: &Program,
    p: &GyroParams,
    axes: &[AxisParams],
    accels: &[AccelParams],
    st: &mut State,
    temp_c: f64,
) {
    let gradient = st.coil.gradient_c();
    let rate_gradient = st.coil.rate_gradient_c_per_s(st.housing);
    let mean = st.coil.mean_c();
    // The stress follows the heat flux through the winding (conductivity × gradient): on a
    // steady ramp the flux is set by the heat the coil must take up, Ṫ times its capacity,
    // whatever the temperature; the gradient itself grows as the diffusivity falls.
    let flux_factor = p.diffusivity_m2_per_s(mean) / p.coil_diffusivity_20c_m2_per_s;
    for (s, a) in sample.axes.iter_mut().zip(axes) {
        let shupe = a.shupe_dph_per_c_per_s * rate_gradient;
        let stress = a.stress_dph_per_c * gradient * flux_factor;
        let asymmetry = 1.0 + a.heating_asymmetry * (gradient / ASYMMETRY_SCALE_C).tanh();
        s.static_dph = a.static_bias_dph(mean);
        s.thermal = s.static_dph + (shupe + stress) * asymmetry;
        s.shupe_dph = shupe * asymmetry;
        s.stress_dph = stress * asymmetry;
    }
    for (s, a) in sample.accel.iter_mut().zip(accels) {
        s.true_g = a.true_g(st.housing);
    }
    sample.time_s = (t * 1e9).round() / 1e9;
    sample.chamber_c = program.air_c(t);
    sample.temp_c = temp_c;
    sample.housing_c = st.housing;
    sample.coil_mean_c = mean;
    sample.coil_inner_c = st.coil.layers_c()[0];
    sample.coil_gradient_c = gradient;
    sample.coil_rate_gradient_c_per_s = rate_gradient;
}
