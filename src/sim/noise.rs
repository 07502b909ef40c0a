//! Random parts of the output: gyro noise and temperature-sensor noise, from one seed.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use super::axes::AxisParams;
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
/// reshuffles another: the gyro noise (of the first axis), the calibration temperature sensor,
/// and (laser gyro only) the housing sensor, the wander of the laser's channels and their
/// measurement noise.
const GYRO_STREAM: u64 = 0;
const SENSOR_STREAM: u64 = 1;
pub(crate) const HOUSING_SENSOR_STREAM: u64 = 2;
pub(crate) const WANDER_STREAM: u64 = 3;
pub(crate) const CHANNEL_NOISE_STREAM: u64 = 4;
/// Streams of the samples a faster logger records between the profile's own samples
/// (`--rate-hz`): the calibration sensor, the laser gyro's housing sensor and channel noise.
pub(crate) const FINE_SENSOR_STREAM: u64 = 5;
pub(crate) const FINE_HOUSING_SENSOR_STREAM: u64 = 6;
pub(crate) const FINE_CHANNEL_NOISE_STREAM: u64 = 7;
/// The host's reading times (`--jitter`).
pub(crate) const JITTER_STREAM: u64 = 8;
/// First stream of each family that has one stream per axis: gyro noise of axes after the
/// first, the split of each axis's white noise into faster samples, accelerometer noise and
/// its split. 64 axes a family at most, far more than a unit has.
const AXIS_GYRO_STREAMS: u64 = 64;
const AXIS_BRIDGE_STREAMS: u64 = 128;
const ACCEL_STREAMS: u64 = 192;
const ACCEL_BRIDGE_STREAMS: u64 = 256;
/// Axes a unit may have, so that the families of streams above never overlap.
pub(crate) const MAX_AXES: usize = 64;

/// The gyro-noise stream of axis `k`: the first axis draws from the stream of a single-axis
/// gyro, so that it is, sample for sample, the single-axis run of its constants.
pub(crate) fn gyro_stream(k: usize) -> u64 {
    if k == 0 {
        GYRO_STREAM
    } else {
        AXIS_GYRO_STREAMS + k as u64
    }
}

/// The stream that splits axis `k`'s white noise over faster samples.
pub(crate) fn bridge_stream(k: usize) -> u64 {
    AXIS_BRIDGE_STREAMS + k as u64
}

/// The noise stream of accelerometer `k`.
pub(crate) fn accel_stream(k: usize) -> u64 {
    ACCEL_STREAMS + k as u64
}

/// The stream that splits accelerometer `k`'s white noise over faster samples.
pub(crate) fn accel_bridge_stream(k: usize) -> u64 {
    ACCEL_BRIDGE_STREAMS + k as u64
}

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

/// One sample of gyro noise in its three parts, °/h: white (over the sample's interval), the
/// Gauss-Markov bias and the rate random walk at its start.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NoiseParts {
    pub(crate) white: f64,
    pub(crate) gm: f64,
    pub(crate) rrw: f64,
}

impl NoiseParts {
    /// The sample's noise, °/h.
    pub(crate) fn total(self) -> f64 {
        self.white + self.gm + self.rrw
    }

    /// The noise with another white part: a faster sample inside this one's interval, where
    /// the slow parts have not moved.
    pub(crate) fn with_white(self, white: f64) -> f64 {
        white + self.gm + self.rrw
    }
}

impl GyroNoise {
    /// The noise of a single-axis gyro `p` sampled every `dt_s`.
    pub(crate) fn new(p: &GyroParams, dt_s: f64, seed: u64) -> GyroNoise {
        GyroNoise::for_axis(&AxisParams::of_gyro("x", p), dt_s, seed, 0)
    }

    /// The noise of axis number `k` (0 first) with the constants of `a`, sampled every `dt_s`.
    pub(crate) fn for_axis(a: &AxisParams, dt_s: f64, seed: u64, k: usize) -> GyroNoise {
        let mut rng = rng(seed, gyro_stream(k));
        // ARW N in °/√h is 60·N in °/h·√s; a sample averaging over dt has σ = 60·N/√dt.
        let white_sigma = 60.0 * a.arw_deg_per_sqrt_h / dt_s.sqrt();
        let gm_phi = (-dt_s / a.bias_correlation_s).exp();
        let gm_drive = a.bias_instability_dph * (1.0 - gm_phi * gm_phi).sqrt();
        // Start the Gauss-Markov bias in its stationary distribution: no settling transient.
        let gm = a.bias_instability_dph * normal(&mut rng);
        let rrw_step = a.rrw_dph_per_sqrt_h * (dt_s / 3600.0).sqrt();
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

    /// The next sample's noise in its parts.
    pub(crate) fn next_parts(&mut self) -> NoiseParts {
        let white = self.white_sigma * normal(&mut self.rng);
        let out = NoiseParts {
            white,
            gm: self.gm,
            rrw: self.rrw,
        };
        self.gm = self.gm_phi * self.gm + self.gm_drive * normal(&mut self.rng);
        self.rrw += self.rrw_step * normal(&mut self.rng);
        out
    }

    /// Standard deviation of the white part of one sample, °/h.
    pub(crate) fn white_sigma(&self) -> f64 {
        self.white_sigma
    }
}

/// Splits the white noise `mean` of one sample into `out.len()` samples of a logger `m` times
/// faster, each of standard deviation `sigma_fine`, whose mean is `mean`: the faster samples
/// are drawn from their distribution given the slower one (`mean + σ·(z_j − z̄)`, z standard
/// normal, which makes them independent with variance σ² when `mean` has variance σ²/m). So
/// the fast log averaged over the slow sample's interval is the slow log, and the angle the
/// gyro reports over that interval does not depend on the logging rate.
pub(crate) fn split_white(mean: f64, sigma_fine: f64, rng: &mut ChaCha8Rng, out: &mut [f64]) {
    for z in out.iter_mut() {
        *z = normal(rng);
    }
    let zbar = out.iter().sum::<f64>() / out.len() as f64;
    for z in out.iter_mut() {
        *z = mean + sigma_fine * (*z - zbar);
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
