//! Random parts of the output: gyro noise and temperature-sensor noise, from one seed.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use super::profile::GyroParams;

/// Gyro rate noise: white (angle random walk) + first-order Gauss-Markov (bias instability)
/// + rate random walk, one value per sample.
pub(crate) struct GyroNoise {
    rng: ChaCha8Rng,
    white_sigma: f64,
    gm_phi: f64,
    gm_drive: f64,
    gm: f64,
    rrw_step: f64,
    rrw: f64,
}

/// ChaCha stream of the gyro noise and of the temperature-sensor noise: separate streams of
/// one seed, so changing one noise never reshuffles the other.
const GYRO_STREAM: u64 = 0;
const SENSOR_STREAM: u64 = 1;

fn normal(rng: &mut ChaCha8Rng) -> f64 {
    StandardNormal.sample(rng)
}

impl GyroNoise {
    pub(crate) fn new(p: &GyroParams, dt_s: f64, seed: u64) -> GyroNoise {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(GYRO_STREAM);
        // ARW N in °/√h is 60·N in °/h·√s; a sample averaging over dt has σ = 60·N/√dt.
        let white_sigma = 60.0 * p.arw_deg_per_sqrt_h / dt_s.sqrt();
        let gm_phi = (-dt_s / p.bias_correlation_s).exp();
        let gm_drive = p.bias_instability_dph * (1.0 - gm_phi * gm_phi).sqrt();
        // Start the Gauss-Markov bias in its stationary distribution: no settling transient.
        let gm = p.bias_instability_dph * normal(&mut rng);
        let rrw_step = p.rrw_dph_per_sqrt_h * (dt_s / 3600.0).sqrt();
        GyroNoise {
            rng,
            white_sigma,
            gm_phi,
            gm_drive,
            gm,
            rrw_step,
            rrw: 0.0,
        }
    }

    /// The next sample's noise, °/h.
    pub(crate) fn next(&mut self) -> f64 {
        let white = self.white_sigma * normal(&mut self.rng);
        let out = white + self.gm + self.rrw;
        self.gm = self.gm_phi * self.gm + self.gm_drive * normal(&mut self.rng);
        self.rrw += self.rrw_step * normal(&mut self.rng);
        out
    }
}

/// The calibration temperature sensor: true temperature + white noise, quantised.
pub(crate) struct Sensor {
    rng: ChaCha8Rng,
    sigma: f64,
    resolution: f64,
}

impl Sensor {
    pub(crate) fn new(p: &GyroParams, seed: u64) -> Sensor {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(SENSOR_STREAM);
        Sensor {
            rng,
            sigma: p.sensor_noise_c,
            resolution: p.sensor_resolution_c,
        }
    }

    /// One reading of a true temperature `temp_c`, °C.
    pub(crate) fn read(&mut self, temp_c: f64) -> f64 {
        let noisy = temp_c + self.sigma * normal(&mut self.rng);
        quantise(noisy, self.resolution)
    }
}

/// Rounds `x` to a multiple of `step`, returning the nearest f64 to that multiple so that
/// printing with the step's decimals gives the same number back.
pub(crate) fn quantise(x: f64, step: f64) -> f64 {
    let n = (x / step).round();
    // For decimal steps (0.001) dividing by 1/step is exact where multiplying is not.
    let inv = (1.0 / step).round();
    if inv >= 1.0 && ((1.0 / inv) - step).abs() <= 1e-15 * step {
        n / inv
    } else {
        n * step
    }
}
