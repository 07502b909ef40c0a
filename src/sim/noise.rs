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

/// ChaCha streams of one seed, one for each random part, so that changing one noise never
/// reshuffles another: the gyro noise, the calibration temperature sensor, and (laser gyro
/// only) the housing sensor, the wander of the laser's channels and their measurement noise.
const GYRO_STREAM: u64 = 0;
const SENSOR_STREAM: u64 = 1;
pub(crate) const HOUSING_SENSOR_STREAM: u64 = 2;
pub(crate) const WANDER_STREAM: u64 = 3;
pub(crate) const CHANNEL_NOISE_STREAM: u64 = 4;

/// The generator of stream `stream` of `seed`.
pub(crate) fn rng(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    rng
}

pub(crate) fn normal(rng: &mut ChaCha8Rng) -> f64 {
    StandardNormal.sample(rng)
}

/// A first-order Gauss-Markov process sampled every `dt_s`, started in its stationary
/// distribution: standard deviation `sigma`, correlation time `corr_s`.
pub(crate) struct GaussMarkov {
    phi: f64,
    drive: f64,
    x: f64,
}

impl GaussMarkov {
    pub(crate) fn new(sigma: f64, corr_s: f64, dt_s: f64, rng: &mut ChaCha8Rng) -> GaussMarkov {
        let phi = (-dt_s / corr_s).exp();
        GaussMarkov {
            phi,
            drive: sigma * (1.0 - phi * phi).sqrt(),
            x: sigma * normal(rng),
        }
    }

    /// The current value.
    pub(crate) fn value(&self) -> f64 {
        self.x
    }

    /// Moves on by one sample.
    pub(crate) fn advance(&mut self, rng: &mut ChaCha8Rng) {
        self.x = self.phi * self.x + self.drive * normal(rng);
    }
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
        Sensor::on_stream(p, seed, SENSOR_STREAM)
    }

    /// A sensor with the constants of `p` drawing its noise from stream `stream` of `seed`.
    pub(crate) fn on_stream(p: &GyroParams, seed: u64, stream: u64) -> Sensor {
        Sensor {
            rng: rng(seed, stream),
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
