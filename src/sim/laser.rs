//! The ring laser gyro of the `laser-gyro` profile: the gyro of Sukhanov (2011), docs/method.md §3.
//!
//! A laser gyro is switched on at t = 0 in the chamber, in equilibrium with the air, and warms
//! itself. Its log carries two temperature sensors and three state channels of the laser, and
//! its systematic drift is, by construction, exactly the generalised model of Sukhanov (11)
//! plus a static bias of the resonator temperature, so that a fit of that model on the
//! noise-free drift gives back the coefficients below.
//!
//! # Physics (the constants are the fields of [`LaserParams`], defaults in brackets)
//!
//! * **Housing** `T_h`: follows the chamber air through a first-order lag (`housing_tau_s`,
//!   15 min) and, powered, stands `housing_self_heating_c` (2 °C) above it:
//!   `dT_h/dt = (T_air + S_h − T_h)/τ_h`.
//! * **Resonator base** `T_r` (the glass-ceramic block, warmed by the discharge): follows the
//!   housing through `base_tau_s` (10 min) and stands `base_self_heating_c` (4 °C) above it:
//!   `dT_r/dt = (T_h + S_r − T_r)/τ_r`. After power-on at a constant chamber the base rises
//!   6 °C within about half an hour. Both lags are integrated exactly for an input linear over
//!   each step (at most 1 s).
//! * **Laser power** `P`, mW: `P20·(1 + c_P·(T_r − 20))·(1 − w_P·e^(−t/τ_P)) + wander` — it
//!   falls as the block warms (0.4 %/°C), settles after ignition (3 % in 5 min), and wanders
//!   (Gauss-Markov, 0.004 mW, 20 min).
//! * **Piezo-corrector voltage** `U`, V: the path-length control follows the expansion of the
//!   block, `U20 + k_U·(T_r − 20) + wander` (1.5 V/°C; Gauss-Markov wander 1.5 V, 30 min).
//! * **Dither amplitude** `A`, arcsec: the open-loop amplitude `D·g(T_h)·(1 + wander)` falls
//!   as the housing warms (`g = 1 + c_A·(T_h − 20)`, −0.2 %/°C; wander 0.3 %, 10 min), and a
//!   relay with hysteresis (Sukhanov's stabiliser) steps the drive D by ±0.4 arcsec whenever A
//!   leaves 400 ± 1.5 arcsec. A therefore hugs one edge of the band while the housing
//!   temperature moves and wanders inside it otherwise.
//! * **Drift**, °/h, with `ΔT = T_h − T_r` and every channel at its true value:
//!
//!   ```text
//!   Ω = K0(T_r) + B1·(1 − e^(−t/λ)) + B2·ΔT + B3·ΔT² + B4·(A − A_set) + B5·(P − P20) + B6·(U − U20)
//!   K0(T) = k0 + k1·(T − 20) + k2·(T − 20)²
//!   ```
//!
//!   B1 = 0.15 °/h, λ = 1800 s; B2 = 0.02 °/h/°C; B3 = 0.003 °/h/°C²; B4 = 0.02 °/h/arcsec
//!   (f1(A) = A − A_set: the exact f1 is lost in the paper's text, and over the ±1.5 arcsec the
//!   stabiliser allows any smooth f1 is linear); B5 = −0.6 °/h/mW (f2(P) = P); B6 = 0.0015 °/h/V
//!   (f3(U) = U); k0 = 0, k1 = 0.002 °/h/°C, k2 = 2·10⁻⁵ °/h/°C². The offsets P20, U20 and A_set
//!   only move the constant.
//! * **Logged values**: both temperatures through the sensor model of the fibre-optic gyro
//!   (white noise `sensor_noise_c`, quantised to `sensor_resolution_c`, separate random
//!   streams); P, U and A with a little white measurement noise, quantised to their
//!   resolutions. The gyro noise (ARW, Gauss-Markov, RRW) is the one of [`super::GyroParams`].

use serde::{Deserialize, Serialize};

use rand_chacha::ChaCha8Rng;

use super::Steps;
use super::noise::{self, GaussMarkov, GyroNoise, Sensor};
use super::profile::{GyroParams, Profile};
use super::run::{AxisSample, LaserSample, Sample};
use super::thermal::{Program, lag_step};
use crate::error::Invalid;

/// The constants of the simulated ring laser gyro (see the module doc for the equations).
///
/// Units are in the field names; the defaults are the gyro of the `laser-gyro` profile.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LaserParams {
    /// Time constant of the housing following the chamber air, s.
    pub housing_tau_s: f64,
    /// Steady rise of the powered housing above the air, °C.
    pub housing_self_heating_c: f64,
    /// Time constant of the resonator base following the housing, s.
    pub base_tau_s: f64,
    /// Steady rise of the resonator base above the housing (discharge heat), °C.
    pub base_self_heating_c: f64,
    /// λ: time constant of the self-heating drift term after power-on, s.
    pub self_heating_tau_s: f64,
    /// B1: amplitude of the self-heating drift term B1·(1 − e^(−t/λ)), °/h.
    pub b1_self_heating_dph: f64,
    /// B2: drift per °C of housing-minus-base difference ΔT, °/h per °C.
    pub b2_dph_per_c: f64,
    /// B3: drift per °C² of ΔT², °/h per °C².
    pub b3_dph_per_c2: f64,
    /// B4: drift per arcsec of dither amplitude above its set point, °/h per arcsec.
    pub b4_dph_per_arcsec: f64,
    /// B5: drift per mW of laser power above `laser_power_20c_mw`, °/h per mW.
    pub b5_dph_per_mw: f64,
    /// B6: drift per V of piezo voltage above `piezo_20c_v`, °/h per V.
    pub b6_dph_per_v: f64,
    /// k0: static bias at a base temperature of 20 °C, °/h.
    pub bias_20c_dph: f64,
    /// k1: linear coefficient of the static bias in the base temperature, °/h per °C.
    pub bias_slope_dph_per_c: f64,
    /// k2: quadratic coefficient of the static bias, °/h per °C².
    pub bias_curvature_dph_per_c2: f64,
    /// Settled laser power with the base at 20 °C, mW.
    pub laser_power_20c_mw: f64,
    /// Relative change of the laser power per °C of base temperature, 1/°C.
    pub laser_power_temp_coeff_per_c: f64,
    /// Relative shortfall of the laser power just after ignition, dimensionless.
    pub laser_power_warmup_fraction: f64,
    /// Time constant of that shortfall dying out, s.
    pub laser_power_warmup_tau_s: f64,
    /// Standard deviation of the laser power's own wander (Gauss-Markov), mW.
    pub laser_power_wander_mw: f64,
    /// Correlation time of that wander, s.
    pub laser_power_wander_corr_s: f64,
    /// White measurement noise of the logged laser power, mW.
    pub laser_power_noise_mw: f64,
    /// Resolution of the logged laser power, mW.
    pub laser_power_resolution_mw: f64,
    /// Piezo-corrector voltage with the base at 20 °C, V.
    pub piezo_20c_v: f64,
    /// Change of the piezo voltage per °C of base temperature, V per °C.
    pub piezo_slope_v_per_c: f64,
    /// Standard deviation of the piezo voltage's own wander (Gauss-Markov), V.
    pub piezo_wander_v: f64,
    /// Correlation time of that wander, s.
    pub piezo_wander_corr_s: f64,
    /// White measurement noise of the logged piezo voltage, V.
    pub piezo_noise_v: f64,
    /// Resolution of the logged piezo voltage, V.
    pub piezo_resolution_v: f64,
    /// Set point of the dither-amplitude stabiliser, arcsec.
    pub dither_setpoint_arcsec: f64,
    /// Half-width of the stabiliser's hysteresis band, arcsec.
    pub dither_band_arcsec: f64,
    /// Step of the drive, as amplitude at unit gain, each time the amplitude leaves the band,
    /// arcsec; smaller than the half-width, so that one step never jumps across the band.
    pub dither_drive_step_arcsec: f64,
    /// Relative change of the open-loop dither gain per °C of housing temperature, 1/°C.
    pub dither_gain_temp_coeff_per_c: f64,
    /// Standard deviation of the relative wander of the dither gain (Gauss-Markov).
    pub dither_wander_fraction: f64,
    /// Correlation time of that wander, s.
    pub dither_wander_corr_s: f64,
    /// White measurement noise of the logged dither amplitude, arcsec.
    pub dither_noise_arcsec: f64,
    /// Resolution of the logged dither amplitude, arcsec.
    pub dither_resolution_arcsec: f64,
}

impl Default for LaserParams {
    /// The laser gyro of the `laser-gyro` profile: on its run the noise-free drift spans about
    /// 0.45 °/h peak to peak (100-s moving average) with a standard deviation of about
    /// 0.13 °/h, the order of the residual RMS Sukhanov (2011) reports after a
    /// temperature-only calibration (0.12–0.18 °/h).
    fn default() -> Self {
        LaserParams {
            housing_tau_s: 900.0,
            housing_self_heating_c: 2.0,
            base_tau_s: 600.0,
            base_self_heating_c: 4.0,
            self_heating_tau_s: 1800.0,
            b1_self_heating_dph: 0.15,
            b2_dph_per_c: 0.02,
            b3_dph_per_c2: 0.003,
            b4_dph_per_arcsec: 0.02,
            b5_dph_per_mw: -0.6,
            b6_dph_per_v: 0.0015,
            bias_20c_dph: 0.0,
            bias_slope_dph_per_c: 0.002,
            bias_curvature_dph_per_c2: 2.0e-5,
            laser_power_20c_mw: 0.80,
            laser_power_temp_coeff_per_c: -0.004,
            laser_power_warmup_fraction: 0.03,
            laser_power_warmup_tau_s: 300.0,
            laser_power_wander_mw: 0.004,
            laser_power_wander_corr_s: 1200.0,
            laser_power_noise_mw: 0.0005,
            laser_power_resolution_mw: 0.0001,
            piezo_20c_v: 100.0,
            piezo_slope_v_per_c: 1.5,
            piezo_wander_v: 1.5,
            piezo_wander_corr_s: 1800.0,
            piezo_noise_v: 0.02,
            piezo_resolution_v: 0.01,
            dither_setpoint_arcsec: 400.0,
            dither_band_arcsec: 1.5,
            dither_drive_step_arcsec: 0.4,
            dither_gain_temp_coeff_per_c: -0.002,
            dither_wander_fraction: 0.003,
            dither_wander_corr_s: 600.0,
            dither_noise_arcsec: 0.05,
            dither_resolution_arcsec: 0.01,
        }
    }
}

impl LaserParams {
    /// The true systematic drift, °/h, for time since power-on `t_s`, housing and base
    /// temperatures, dither amplitude, laser power and piezo voltage (all true values): the
    /// equation of the module doc.
    #[allow(clippy::too_many_arguments)]
    pub fn drift_dph(
        &self,
        t_s: f64,
        housing_c: f64,
        base_c: f64,
        dither_arcsec: f64,
        power_mw: f64,
        piezo_v: f64,
    ) -> f64 {
        let d = base_c - 20.0;
        let dt = housing_c - base_c;
        self.bias_20c_dph
            + self.bias_slope_dph_per_c * d
            + self.bias_curvature_dph_per_c2 * d * d
            + self.self_heating_dph(t_s)
            + self.b2_dph_per_c * dt
            + self.b3_dph_per_c2 * dt * dt
            + self.b4_dph_per_arcsec * (dither_arcsec - self.dither_setpoint_arcsec)
            + self.b5_dph_per_mw * (power_mw - self.laser_power_20c_mw)
            + self.b6_dph_per_v * (piezo_v - self.piezo_20c_v)
    }

    /// The self-heating term B1·(1 − e^(−t/λ)), °/h, `t_s` seconds after power-on.
    pub fn self_heating_dph(&self, t_s: f64) -> f64 {
        self.b1_self_heating_dph * (1.0 - (-t_s.max(0.0) / self.self_heating_tau_s).exp())
    }

    /// Checks that every constant is usable, with a sentence naming the one that is not.
    pub fn check(&self) -> Result<(), Invalid> {
        let positive = [
            ("housing_tau_s", self.housing_tau_s),
            ("base_tau_s", self.base_tau_s),
            ("self_heating_tau_s", self.self_heating_tau_s),
            ("laser_power_20c_mw", self.laser_power_20c_mw),
            ("laser_power_warmup_tau_s", self.laser_power_warmup_tau_s),
            ("laser_power_wander_corr_s", self.laser_power_wander_corr_s),
            ("laser_power_resolution_mw", self.laser_power_resolution_mw),
            ("piezo_wander_corr_s", self.piezo_wander_corr_s),
            ("piezo_resolution_v", self.piezo_resolution_v),
            ("dither_setpoint_arcsec", self.dither_setpoint_arcsec),
            ("dither_band_arcsec", self.dither_band_arcsec),
            ("dither_drive_step_arcsec", self.dither_drive_step_arcsec),
            ("dither_wander_corr_s", self.dither_wander_corr_s),
            ("dither_resolution_arcsec", self.dither_resolution_arcsec),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(Invalid::new(
                    format!("laser.{name}"),
                    format!("must be a positive number, got {v}"),
                ));
            }
        }
        let finite = [
            ("housing_self_heating_c", self.housing_self_heating_c),
            ("base_self_heating_c", self.base_self_heating_c),
            ("b1_self_heating_dph", self.b1_self_heating_dph),
            ("b2_dph_per_c", self.b2_dph_per_c),
            ("b3_dph_per_c2", self.b3_dph_per_c2),
            ("b4_dph_per_arcsec", self.b4_dph_per_arcsec),
            ("b5_dph_per_mw", self.b5_dph_per_mw),
            ("b6_dph_per_v", self.b6_dph_per_v),
            ("bias_20c_dph", self.bias_20c_dph),
            ("bias_slope_dph_per_c", self.bias_slope_dph_per_c),
            ("bias_curvature_dph_per_c2", self.bias_curvature_dph_per_c2),
            (
                "laser_power_temp_coeff_per_c",
                self.laser_power_temp_coeff_per_c,
            ),
            (
                "laser_power_warmup_fraction",
                self.laser_power_warmup_fraction,
            ),
            ("piezo_20c_v", self.piezo_20c_v),
            ("piezo_slope_v_per_c", self.piezo_slope_v_per_c),
            (
                "dither_gain_temp_coeff_per_c",
                self.dither_gain_temp_coeff_per_c,
            ),
        ];
        for (name, v) in finite {
            if !v.is_finite() {
                return Err(Invalid::new(
                    format!("laser.{name}"),
                    format!("must be a finite number, got {v}"),
                ));
            }
        }
        let non_negative = [
            ("laser_power_wander_mw", self.laser_power_wander_mw),
            ("laser_power_noise_mw", self.laser_power_noise_mw),
            ("piezo_wander_v", self.piezo_wander_v),
            ("piezo_noise_v", self.piezo_noise_v),
            ("dither_wander_fraction", self.dither_wander_fraction),
            ("dither_noise_arcsec", self.dither_noise_arcsec),
        ];
        for (name, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Invalid::new(
                    format!("laser.{name}"),
                    format!("must be zero or positive, got {v}"),
                ));
            }
        }
        if self.dither_drive_step_arcsec >= self.dither_band_arcsec {
            return Err(Invalid::new(
                "laser.dither_drive_step_arcsec",
                format!(
                    "{} must be smaller than dither_band_arcsec ({}), or one step of the \
                     stabiliser jumps across its band",
                    self.dither_drive_step_arcsec, self.dither_band_arcsec
                ),
            ));
        }
        Ok(())
    }

    /// Open-loop dither gain at housing temperature `housing_c`, kept above 0.1 so that no
    /// temperature stops the dither or reverses it.
    fn dither_gain(&self, housing_c: f64) -> f64 {
        (1.0 + self.dither_gain_temp_coeff_per_c * (housing_c - 20.0)).max(0.1)
    }
}

/// Decimals that print a value quantised to `resolution` exactly (0.01 → 2), at most 9.
fn decimals_of(resolution: f64) -> usize {
    let d = (-resolution.log10() - 1e-9).ceil();
    if d.is_finite() {
        d.clamp(0.0, 9.0) as usize
    } else {
        0
    }
}

/// The dither-amplitude stabiliser: relay law with hysteresis on the drive.
#[derive(Debug, Clone, Copy)]
struct Dither {
    /// Drive, as the amplitude it gives at unit gain, arcsec.
    drive: f64,
}

impl Dither {
    /// The amplitude at the given gain and wander, after the relay has acted on it once.
    fn regulate(&mut self, l: &LaserParams, gain: f64) -> f64 {
        let amp = self.drive * gain;
        if amp > l.dither_setpoint_arcsec + l.dither_band_arcsec {
            self.drive -= l.dither_drive_step_arcsec;
        } else if amp < l.dither_setpoint_arcsec - l.dither_band_arcsec {
            self.drive += l.dither_drive_step_arcsec;
        }
        self.drive * gain
    }
}

/// The name, unit and decimals of the channels a laser gyro logs after `temp_chamber_c`.
pub(crate) fn channel_specs(
    p: &GyroParams,
    l: &LaserParams,
) -> Vec<(&'static str, &'static str, usize)> {
    vec![
        ("temp_housing_c", "°C", decimals_of(p.sensor_resolution_c)),
        (
            "laser_power_mw",
            "mW",
            decimals_of(l.laser_power_resolution_mw),
        ),
        ("piezo_v", "V", decimals_of(l.piezo_resolution_v)),
        (
            "dither_amp_arcsec",
            "arcsec",
            decimals_of(l.dither_resolution_arcsec),
        ),
    ]
}

/// The thermal and dither state of the laser gyro.
#[derive(Debug, Clone, Copy)]
struct State {
    housing: f64,
    base: f64,
    dither: Dither,
    /// Dither amplitude after the relay's last action, arcsec.
    amp: f64,
}

impl State {
    /// Advances from `ta` to `tb` (`h` = tb − ta) with the dither gain's wander at `wander`.
    fn advance(
        &mut self,
        l: &LaserParams,
        program: &Program,
        ta: f64,
        tb: f64,
        h: f64,
        wander: f64,
    ) {
        let s_h = l.housing_self_heating_c;
        let next = lag_step(
            self.housing,
            program.air_c(ta) + s_h,
            program.air_c(tb) + s_h,
            h,
            l.housing_tau_s,
        );
        let s_r = l.base_self_heating_c;
        self.base = lag_step(self.base, self.housing + s_r, next + s_r, h, l.base_tau_s);
        self.housing = next;
        self.amp = self
            .dither
            .regulate(l, dither_gain(l, self.housing, wander));
    }
}

/// The dither gain at housing temperature `housing` with relative wander `wander`.
fn dither_gain(l: &LaserParams, housing: f64, wander: f64) -> f64 {
    l.dither_gain(housing) * (1.0 + wander).max(0.1)
}

/// The random parts of the logged values: the base and housing sensors and the channels'
/// measurement noise.
struct Meters {
    base: Sensor,
    housing: Sensor,
    channels: ChaCha8Rng,
}

impl Meters {
    /// Fills the logged temperature and channels of `sample` (whose truth is set).
    fn read(&mut self, l: &LaserParams, sample: &mut Sample) {
        let truth = &sample.laser;
        sample.temp_c = self.base.read(truth.base_c);
        let rng = &mut self.channels;
        let mut measure =
            |x: f64, sigma: f64, res: f64| noise::quantise(x + sigma * noise::normal(rng), res);
        let logged = [
            self.housing.read(sample.housing_c),
            measure(
                truth.laser_power_mw,
                l.laser_power_noise_mw,
                l.laser_power_resolution_mw,
            ),
            measure(truth.piezo_v, l.piezo_noise_v, l.piezo_resolution_v),
            measure(
                truth.dither_amp_arcsec,
                l.dither_noise_arcsec,
                l.dither_resolution_arcsec,
            ),
        ];
        sample.channels.clear();
        sample.channels.extend_from_slice(&logged);
    }
}

/// Simulates the laser gyro `l` through the chamber program of `profile` (module doc),
/// logging `fine` samples per profile sample, and hands every sample to `sink` in time order.
/// `profile` has been checked.
pub(crate) fn run<E>(
    profile: &Profile,
    l: &LaserParams,
    fine: usize,
    seed: u64,
    progress: &dyn Fn(f64),
    sink: &mut dyn FnMut(&Sample) -> Result<(), E>,
) -> Result<(), E> {
    let p = &profile.gyro;
    let steps = Steps::of(profile, fine);
    let (dt, n, subs) = (steps.dt, steps.n, steps.subs);
    let (h, h_fine) = (steps.h, steps.h_fine);
    let (sqrt_fine, report_every) = (steps.sqrt_fine, steps.report_every);

    let program = Program::new(profile);
    let mut gyro_noise = GyroNoise::new(p, dt, seed);
    let mut split = noise::rng(seed, noise::bridge_stream(0));
    let mut fine_white = vec![0.0; fine];
    let mut meters = Meters {
        base: Sensor::new(p, seed),
        housing: Sensor::on_stream(p, seed, noise::HOUSING_SENSOR_STREAM),
        channels: noise::rng(seed, noise::CHANNEL_NOISE_STREAM),
    };
    let mut fine_meters = Meters {
        base: Sensor::on_stream(p, seed, noise::FINE_SENSOR_STREAM),
        housing: Sensor::on_stream(p, seed, noise::FINE_HOUSING_SENSOR_STREAM),
        channels: noise::rng(seed, noise::FINE_CHANNEL_NOISE_STREAM),
    };
    let mut wander_rng = noise::rng(seed, noise::WANDER_STREAM);
    let mut power_wander = GaussMarkov::new(
        l.laser_power_wander_mw,
        l.laser_power_wander_corr_s,
        dt,
        &mut wander_rng,
    );
    let mut piezo_wander =
        GaussMarkov::new(l.piezo_wander_v, l.piezo_wander_corr_s, dt, &mut wander_rng);
    let mut dither_wander = GaussMarkov::new(
        l.dither_wander_fraction,
        l.dither_wander_corr_s,
        dt,
        &mut wander_rng,
    );
    let mut dither = Dither {
        drive: l.dither_setpoint_arcsec / l.dither_gain(profile.start_c),
    };
    let amp = dither.regulate(l, dither_gain(l, profile.start_c, dither_wander.value()));
    let mut state = State {
        housing: profile.start_c,
        base: profile.start_c,
        dither,
        amp,
    };
    let mut sample = Sample {
        axes: vec![AxisSample::default()],
        ..Sample::default()
    };
    // Everything at time t in state st but the noise and the logged values.
    let observe = |sample: &mut Sample, t: f64, st: &State, power_w: f64, piezo_w: f64| {
        let base = st.base;
        let power = l.laser_power_20c_mw
            * (1.0 + l.laser_power_temp_coeff_per_c * (base - 20.0))
            * (1.0 - l.laser_power_warmup_fraction * (-t / l.laser_power_warmup_tau_s).exp())
            + power_w;
        let piezo = l.piezo_20c_v + l.piezo_slope_v_per_c * (base - 20.0) + piezo_w;
        sample.axes[0].thermal = l.drift_dph(t, st.housing, base, st.amp, power, piezo);
        sample.time_s = (t * 1e9).round() / 1e9;
        sample.chamber_c = program.air_c(t);
        sample.housing_c = st.housing;
        sample.coil_mean_c = base;
        sample.coil_inner_c = base;
        sample.laser = LaserSample {
            base_c: base,
            laser_power_mw: power,
            piezo_v: piezo,
            dither_amp_arcsec: st.amp,
            self_heating_dph: l.self_heating_dph(t),
        };
    };

    progress(0.0);
    for i in 0..n {
        let t = i as f64 * dt;
        if i > 0 {
            let t_prev = (i - 1) as f64 * dt;
            for k in 0..subs {
                let ta = t_prev + k as f64 * h;
                let tb = t_prev + (k + 1) as f64 * h;
                state.advance(l, &program, ta, tb, h, dither_wander.value());
            }
            power_wander.advance(&mut wander_rng);
            piezo_wander.advance(&mut wander_rng);
            dither_wander.advance(&mut wander_rng);
        }
        let (power_w, piezo_w) = (power_wander.value(), piezo_wander.value());
        let parts = gyro_noise.next_parts();
        observe(&mut sample, t, &state, power_w, piezo_w);
        meters.read(l, &mut sample);
        if fine == 1 {
            sample.axes[0].set_noise(parts.total());
            sink(&sample)?;
        } else {
            let sigma = gyro_noise.white_sigma() * sqrt_fine;
            noise::split_white(parts.white, sigma, &mut split, &mut fine_white);
            sample.axes[0].set_noise(parts.with_white(fine_white[0]));
            sink(&sample)?;
            if i + 1 < n {
                let mut branch = state;
                for (j, &white) in fine_white.iter().enumerate().skip(1) {
                    let ta = t + (j - 1) as f64 * h_fine;
                    let tb = t + j as f64 * h_fine;
                    branch.advance(l, &program, ta, tb, h_fine, dither_wander.value());
                    observe(&mut sample, tb, &branch, power_w, piezo_w);
                    fine_meters.read(l, &mut sample);
                    sample.axes[0].set_noise(parts.with_white(white));
                    sink(&sample)?;
                }
            }
        }
        if i % report_every == 0 && i > 0 {
            progress(i as f64 / n as f64);
        }
    }
    progress(1.0);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals_print_the_resolution() {
        assert_eq!(decimals_of(0.001), 3);
        assert_eq!(decimals_of(0.01), 2);
        assert_eq!(decimals_of(0.0001), 4);
        assert_eq!(decimals_of(1.0), 0);
        assert_eq!(decimals_of(0.5), 1);
        assert_eq!(decimals_of(f64::MIN_POSITIVE), 9);
    }

    #[test]
    fn default_laser_is_valid_and_a_bad_step_is_refused() {
        let l = LaserParams::default();
        l.check().unwrap();
        let bad = LaserParams {
            dither_drive_step_arcsec: 2.0,
            ..l.clone()
        };
        assert_eq!(
            bad.check().unwrap_err().field,
            "laser.dither_drive_step_arcsec"
        );
        let bad = LaserParams {
            self_heating_tau_s: 0.0,
            ..l
        };
        assert!(bad.check().is_err());
    }
}
