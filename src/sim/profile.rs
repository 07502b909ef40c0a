//! Test programs for the chamber and the one simulated gyro they all run on.

use serde::{Deserialize, Serialize};

use crate::error::Invalid;

use super::axes::{AccelParams, AxisParams, default_accelerometers, default_axes};
use super::laser::LaserParams;
use super::noise::MAX_AXES;

/// A chamber test: the temperature program, the sampling, and the gyro under test.
///
/// Everything a run depends on besides the seed, so that a profile plus a seed names one log.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Profile {
    /// Short name, as given to `driftlab simulate --profile`; written into the CSV comment.
    pub name: String,
    /// One sentence on what the run is for, shown when the profiles are listed.
    pub description: String,
    /// Sampling rate of the recorded log, Hz (the papers record at 1 Hz).
    pub sample_rate_hz: f64,
    /// Chamber air temperature at t = 0, °C; the gyro starts in equilibrium at it.
    pub start_c: f64,
    /// The chamber program, run in order from `start_c`.
    pub program: Vec<Segment>,
    /// The gyro under test (the same for every built-in profile). For a laser-gyro profile
    /// only its noise and temperature-sensor constants are used.
    pub gyro: GyroParams,
    /// A ring laser gyro instead of the fibre-optic one: its two-sensor thermal model,
    /// self-heating after power-on, extra logged channels and drift coefficients
    /// ([`LaserParams`]). `None` (the default, and what a profile file without the field
    /// reads as) runs the fibre-optic gyro of `gyro`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub laser: Option<LaserParams>,
    /// The gyro axes of a multi-axis unit (an IMU), each answering the one thermal field of
    /// `gyro` with its own constants ([`AxisParams`]). Empty (the default, and what a profile
    /// file without the field reads as): the single gyro of `gyro`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub axes: Vec<AxisParams>,
    /// Accelerometers on the housing, logged beside the rates; none by default.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub accelerometers: Vec<AccelParams>,
}

/// One step of the chamber program.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Segment {
    /// Keep the air at the current temperature for `duration_s` seconds (a plateau, when the
    /// gyro has time to settle).
    Hold {
        /// Length of the hold, s.
        duration_s: f64,
    },
    /// Drive the air linearly from the current temperature to `to_c` at `rate_c_per_min`.
    Ramp {
        /// Target air temperature, °C.
        to_c: f64,
        /// Absolute ramp rate, °C/min (positive whichever way the ramp goes).
        rate_c_per_min: f64,
    },
}

/// The physical constants of the simulated gyro, its housing and its sensors.
///
/// Units are in the field names so that a profile file reads without a manual. The defaults
/// (`GyroParams::default()`) are driftlab's reference gyro, tuned so that a calibration run
/// resembles the published ones (docs/method.md §1, §3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GyroParams {
    /// Time constant of the housing following the chamber air (first-order lag), s.
    pub housing_tau_s: f64,
    /// Inner radius of the fibre winding, m.
    pub coil_inner_radius_m: f64,
    /// Outer radius of the fibre winding (where the housing drives it), m.
    pub coil_outer_radius_m: f64,
    /// Number of radial finite-volume layers of the winding.
    pub coil_layers: usize,
    /// Thermal diffusivity of the potted winding at 20 °C, m²/s.
    pub coil_diffusivity_20c_m2_per_s: f64,
    /// Relative rise of the diffusivity per °C: K(T) = K20·(1 + α·(T − 20)), 1/°C.
    pub coil_diffusivity_coeff_per_c: f64,
    /// Static zero bias K0 at 20 °C, °/h.
    pub bias_20c_dph: f64,
    /// Linear coefficient of K0 around 20 °C, °/h per °C.
    pub bias_slope_dph_per_c: f64,
    /// Quadratic coefficient of K0 around 20 °C, °/h per °C².
    pub bias_curvature_dph_per_c2: f64,
    /// Shupe coefficient: drift per unit of fibre-weighted radial difference of heating rates,
    /// °/h per (°C/s).
    pub shupe_dph_per_c_per_s: f64,
    /// Thermal-stress coefficient: drift per unit of fibre-weighted radial temperature
    /// difference at 20 °C, °/h per °C; scaled by K(T)/K20 so that it follows the heat flux.
    pub stress_dph_per_c: f64,
    /// Relative asymmetry of the transient drift: ×(1 + a) when the winding is heated from
    /// outside, ×(1 − a) when cooled, dimensionless.
    pub heating_asymmetry: f64,
    /// Angle random walk (white rate noise), °/√h.
    pub arw_deg_per_sqrt_h: f64,
    /// Standard deviation of the correlated (first-order Gauss-Markov) bias, °/h.
    pub bias_instability_dph: f64,
    /// Correlation time of the Gauss-Markov bias, s.
    pub bias_correlation_s: f64,
    /// Rate random walk, °/h per √h.
    pub rrw_dph_per_sqrt_h: f64,
    /// White noise of the temperature sensor before quantisation, °C.
    pub sensor_noise_c: f64,
    /// Resolution of the temperature sensor, °C.
    pub sensor_resolution_c: f64,
}

impl Default for GyroParams {
    /// driftlab's reference gyro: coil lag ≈ 930/550/330 s at −35/0/+55 °C, near Yan's (2019)
    /// 863/547/309 s; filtered drift ≈ 1.6 °/h peak to peak on the calibration run, as
    /// Vakhrameev's (2017) 1.68 °/h; filtered noise ≈ 0.13 °/h peak to peak.
    fn default() -> Self {
        GyroParams {
            housing_tau_s: 720.0,
            coil_inner_radius_m: 0.030,
            coil_outer_radius_m: 0.042,
            coil_layers: 16,
            coil_diffusivity_20c_m2_per_s: 1.52e-7,
            coil_diffusivity_coeff_per_c: 0.010,
            bias_20c_dph: 0.0,
            bias_slope_dph_per_c: 0.003,
            bias_curvature_dph_per_c2: 8.0e-5,
            shupe_dph_per_c_per_s: 280.0,
            stress_dph_per_c: 0.56,
            heating_asymmetry: 0.15,
            arw_deg_per_sqrt_h: 0.003,
            bias_instability_dph: 0.006,
            bias_correlation_s: 600.0,
            rrw_dph_per_sqrt_h: 0.001,
            sensor_noise_c: 0.0003,
            sensor_resolution_c: 0.001,
        }
    }
}

impl GyroParams {
    /// The true static bias K0(T) of this gyro at coil temperature `temp_c`, °/h: the curve a
    /// K0 fit on plateaus is judged against.
    pub fn static_bias_dph(&self, temp_c: f64) -> f64 {
        let d = temp_c - 20.0;
        self.bias_20c_dph + self.bias_slope_dph_per_c * d + self.bias_curvature_dph_per_c2 * d * d
    }

    /// Thermal diffusivity of the winding at `temp_c`, m²/s, kept above 5 % of K20 so that an
    /// extreme temperature cannot stop diffusion or make it negative.
    pub fn diffusivity_m2_per_s(&self, temp_c: f64) -> f64 {
        let k20 = self.coil_diffusivity_20c_m2_per_s;
        (k20 * (1.0 + self.coil_diffusivity_coeff_per_c * (temp_c - 20.0))).max(0.05 * k20)
    }

    /// Checks that every constant is usable, so that a hand-written profile fails with a
    /// sentence instead of NaN columns.
    pub fn check(&self) -> Result<(), Invalid> {
        let positive = [
            ("housing_tau_s", self.housing_tau_s),
            ("coil_inner_radius_m", self.coil_inner_radius_m),
            (
                "coil_diffusivity_20c_m2_per_s",
                self.coil_diffusivity_20c_m2_per_s,
            ),
            ("bias_correlation_s", self.bias_correlation_s),
            ("sensor_resolution_c", self.sensor_resolution_c),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(Invalid::new(
                    format!("gyro.{name}"),
                    format!("must be a positive number, got {v}"),
                ));
            }
        }
        let finite = [
            (
                "coil_diffusivity_coeff_per_c",
                self.coil_diffusivity_coeff_per_c,
            ),
            ("bias_20c_dph", self.bias_20c_dph),
            ("bias_slope_dph_per_c", self.bias_slope_dph_per_c),
            ("bias_curvature_dph_per_c2", self.bias_curvature_dph_per_c2),
            ("shupe_dph_per_c_per_s", self.shupe_dph_per_c_per_s),
            ("stress_dph_per_c", self.stress_dph_per_c),
            ("heating_asymmetry", self.heating_asymmetry),
        ];
        for (name, v) in finite {
            if !v.is_finite() {
                return Err(Invalid::new(
                    format!("gyro.{name}"),
                    format!("must be a finite number, got {v}"),
                ));
            }
        }
        let non_negative = [
            ("arw_deg_per_sqrt_h", self.arw_deg_per_sqrt_h),
            ("bias_instability_dph", self.bias_instability_dph),
            ("rrw_dph_per_sqrt_h", self.rrw_dph_per_sqrt_h),
            ("sensor_noise_c", self.sensor_noise_c),
        ];
        for (name, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Invalid::new(
                    format!("gyro.{name}"),
                    format!("must be zero or positive, got {v}"),
                ));
            }
        }
        if !(self.coil_outer_radius_m.is_finite()
            && self.coil_outer_radius_m > self.coil_inner_radius_m)
        {
            return Err(Invalid::new(
                "gyro.coil_outer_radius_m",
                format!(
                    "{} must exceed coil_inner_radius_m ({})",
                    self.coil_outer_radius_m, self.coil_inner_radius_m
                ),
            ));
        }
        if !(2..=1000).contains(&self.coil_layers) {
            return Err(Invalid::new(
                "gyro.coil_layers",
                format!("must be between 2 and 1000, got {}", self.coil_layers),
            ));
        }
        Ok(())
    }
}

impl Profile {
    /// This profile run by a unit of `n` gyro axes (1 to 3): `driftlab simulate --axes N`. The
    /// first axis is the profile's own gyro, the others those of [`default_axes`]; one axis is
    /// the single gyro again.
    ///
    /// # Errors
    /// When `n` is not 1, 2 or 3, or the profile is a laser gyro's (it has one axis).
    pub fn with_axes(mut self, n: usize) -> Result<Profile, Invalid> {
        if self.laser.is_some() {
            return Err(Invalid::new(
                "--axes",
                format!(
                    "profile {} is a ring laser gyro, which has one axis; the multi-axis unit \
                     is a fibre-optic IMU (any other profile)",
                    self.name
                ),
            ));
        }
        if !self.axes.is_empty() {
            return Err(Invalid::new(
                "--axes",
                format!(
                    "profile {} is a unit of {} gyro axes of its own; --axes makes a unit of \
                     the fibre-optic gyro of another profile",
                    self.name,
                    self.axes.len()
                ),
            ));
        }
        let mut axes = default_axes(n)?;
        axes[0] = AxisParams::of_gyro("x", &self.gyro);
        self.axes = if n == 1 { Vec::new() } else { axes };
        Ok(self)
    }

    /// This profile with the three accelerometers of [`default_accelerometers`] on the housing:
    /// `driftlab simulate --accel`.
    ///
    /// # Errors
    /// When the profile is a laser gyro's.
    pub fn with_accelerometers(mut self) -> Result<Profile, Invalid> {
        if self.laser.is_some() {
            return Err(Invalid::new(
                "--accel",
                format!(
                    "profile {} is a ring laser gyro without accelerometers; they come with \
                     the fibre-optic unit (any other profile)",
                    self.name
                ),
            ));
        }
        if !self.accelerometers.is_empty() {
            return Err(Invalid::new(
                "--accel",
                format!(
                    "profile {} has {} accelerometers of its own; --accel puts the fibre-optic \
                     unit's on another profile",
                    self.name,
                    self.accelerometers.len()
                ),
            ));
        }
        self.accelerometers = default_accelerometers();
        Ok(self)
    }

    /// The gyro axes the run simulates: `axes`, or the single gyro of `gyro` named `x`.
    pub fn unit_axes(&self) -> Vec<AxisParams> {
        if self.axes.is_empty() {
            vec![AxisParams::of_gyro("x", &self.gyro)]
        } else {
            self.axes.clone()
        }
    }

    /// Total length of the program, s.
    pub fn duration_s(&self) -> f64 {
        let mut temp = self.start_c;
        let mut total = 0.0;
        for seg in &self.program {
            total += seg.duration_from(temp);
            if let Segment::Ramp { to_c, .. } = *seg {
                temp = to_c;
            }
        }
        total
    }

    /// Number of samples a run of this profile records (both ends included).
    pub fn sample_count(&self) -> usize {
        (self.duration_s() * self.sample_rate_hz + 1e-9).floor() as usize + 1
    }

    /// Checks the program and the gyro, so that callers that build profiles by hand (a GUI
    /// editor, a profile file) can refuse a bad one with a sentence before simulating.
    pub fn check(&self) -> Result<(), Invalid> {
        if !(self.sample_rate_hz.is_finite() && self.sample_rate_hz > 0.0) {
            return Err(Invalid::new(
                "sample_rate_hz",
                format!("must be a positive number, got {}", self.sample_rate_hz),
            ));
        }
        if !self.start_c.is_finite() {
            return Err(Invalid::new(
                "start_c",
                format!("must be finite, got {}", self.start_c),
            ));
        }
        for (i, seg) in self.program.iter().enumerate() {
            match *seg {
                Segment::Hold { duration_s } => {
                    if !(duration_s.is_finite() && duration_s >= 0.0) {
                        return Err(Invalid::new(
                            format!("segment {}", i + 1),
                            format!("hold duration_s must be zero or positive, got {duration_s}"),
                        ));
                    }
                }
                Segment::Ramp {
                    to_c,
                    rate_c_per_min,
                } => {
                    if !to_c.is_finite() {
                        return Err(Invalid::new(
                            format!("segment {}", i + 1),
                            format!("ramp to_c must be finite, got {to_c}"),
                        ));
                    }
                    if !(rate_c_per_min.is_finite() && rate_c_per_min > 0.0) {
                        return Err(Invalid::new(
                            format!("segment {}", i + 1),
                            format!("ramp rate_c_per_min must be positive, got {rate_c_per_min}"),
                        ));
                    }
                }
            }
        }
        let samples = self.duration_s() * self.sample_rate_hz;
        if samples > 1e9 {
            return Err(Invalid::new(
                "sample_rate_hz",
                format!("the run would record {samples:.0} samples; more than 10⁹ is refused"),
            ));
        }
        if self.sample_count() < 2 {
            return Err(Invalid::new(
                "sample_rate_hz",
                format!(
                    "{} Hz records one sample over the {} s program: a log needs at least two",
                    crate::number::readable(self.sample_rate_hz),
                    crate::number::readable(self.duration_s())
                ),
            ));
        }
        self.gyro.check()?;
        if self.laser.is_some() && !(self.axes.is_empty() && self.accelerometers.is_empty()) {
            return Err(Invalid::new(
                if self.axes.is_empty() {
                    "accelerometers"
                } else {
                    "axes"
                },
                "a laser-gyro profile has one axis and no accelerometers: axes and \
                 accelerometers are for the fibre-optic unit",
            ));
        }
        for (field, n) in [
            ("axes", self.axes.len()),
            ("accelerometers", self.accelerometers.len()),
        ] {
            if n > MAX_AXES {
                return Err(Invalid::new(
                    field,
                    format!("a unit has at most {MAX_AXES} axes, got {n}"),
                ));
            }
        }
        let mut names = std::collections::HashSet::new();
        for a in &self.axes {
            a.check()?;
            if !names.insert(a.name.as_str()) {
                return Err(Invalid::new(
                    "axes",
                    format!("two gyro axes are named {:?}", a.name),
                ));
            }
        }
        let mut names = std::collections::HashSet::new();
        for a in &self.accelerometers {
            a.check()?;
            if !names.insert(a.name.as_str()) {
                return Err(Invalid::new(
                    "accelerometers",
                    format!("two accelerometers are named {:?}", a.name),
                ));
            }
        }
        match &self.laser {
            Some(l) => l.check(),
            None => Ok(()),
        }
    }
}

impl Segment {
    /// How long the segment lasts when it starts at air temperature `from_c`, s.
    pub fn duration_from(&self, from_c: f64) -> f64 {
        match *self {
            Segment::Hold { duration_s } => duration_s,
            Segment::Ramp {
                to_c,
                rate_c_per_min,
            } => (to_c - from_c).abs() / rate_c_per_min * 60.0,
        }
    }
}

/// Names of the built-in profiles, in the order a listing shows them.
pub fn profile_names() -> &'static [&'static str] {
    &[
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
    ]
}

fn hold_min(minutes: f64) -> Segment {
    Segment::Hold {
        duration_s: minutes * 60.0,
    }
}

fn ramp(to_c: f64, rate_c_per_min: f64) -> Segment {
    Segment::Ramp {
        to_c,
        rate_c_per_min,
    }
}

/// A built-in profile by name, or `None` for an unknown name (callers list `profile_names`).
pub fn profile(name: &str) -> Option<Profile> {
    let (description, start_c, program) = match name {
        "calibration" => (
            "Cyclic calibration run as Vakhrameev (2017): plateaus at 20, 60, -50, 20 °C \
             (2 h, 2 h, 2 h, 1.5 h), 1 °C/min ramps, about 11 h at 1 Hz.",
            20.0,
            vec![
                hold_min(120.0),
                ramp(60.0, 1.0),
                hold_min(120.0),
                ramp(-50.0, 1.0),
                hold_min(120.0),
                ramp(20.0, 1.0),
                hold_min(90.0),
            ],
        ),
        "validation" => (
            "Held-out run of the same gyro: plateaus at 0, 40, -30 °C (1.5 h each), ramps at \
             0.5 and 1.5 °C/min, about 10.5 h at 1 Hz.",
            20.0,
            vec![
                hold_min(60.0),
                ramp(0.0, 0.5),
                hold_min(90.0),
                ramp(40.0, 1.5),
                hold_min(90.0),
                ramp(-30.0, 0.5),
                hold_min(90.0),
                ramp(20.0, 1.5),
                hold_min(60.0),
            ],
        ),
        "no-plateaus" => (
            "Continuous cycling between -40 and +50 °C at 0.7 to 1.2 °C/min with no holds, \
             about 6.8 h at 1 Hz: nothing to fit K0 on.",
            20.0,
            vec![
                ramp(50.0, 1.0),
                ramp(-40.0, 0.8),
                ramp(50.0, 1.2),
                ramp(-40.0, 0.7),
                ramp(20.0, 1.0),
            ],
        ),
        "fast-ramps" => (
            "Ramps at 2 °C/min (twice the calibration rate) between 60 and -50 °C with short \
             holds (30 to 45 min), about 4.3 h at 1 Hz.",
            20.0,
            vec![
                hold_min(30.0),
                ramp(60.0, 2.0),
                hold_min(45.0),
                ramp(-50.0, 2.0),
                hold_min(45.0),
                ramp(20.0, 2.0),
                hold_min(30.0),
            ],
        ),
        "square-steps" => (
            "The three square-wave bands of Yan (2019) in one run, high band lowered to \
             40/60 °C to stay in the calibrated range: -25/-45, 10/-10, 40/60 °C, 3 h holds, \
             20 min ramps at 1 °C/min, about 30 h at 1 Hz (the paper's tests: yan-steps-*).",
            -25.0,
            vec![
                hold_min(180.0),
                ramp(-45.0, 1.0),
                hold_min(180.0),
                ramp(-25.0, 1.0),
                hold_min(180.0),
                ramp(10.0, 1.0),
                hold_min(180.0),
                ramp(-10.0, 1.0),
                hold_min(180.0),
                ramp(10.0, 1.0),
                hold_min(180.0),
                ramp(40.0, 1.0),
                hold_min(180.0),
                ramp(60.0, 1.0),
                hold_min(180.0),
                ramp(40.0, 1.0),
                hold_min(180.0),
            ],
        ),
        "yan-steps-low" => (
            "Yan (2019) square-wave test, low band: -25 -> -45 -> -25 °C, 180 min holds, \
             20 min ramps at 1 °C/min, about 9.7 h at 1 Hz.",
            -25.0,
            yan_steps(-25.0, -45.0),
        ),
        "yan-steps-mid" => (
            "Yan (2019) square-wave test, middle band: 10 -> -10 -> 10 °C, 180 min holds, \
             20 min ramps at 1 °C/min, about 9.7 h at 1 Hz.",
            10.0,
            yan_steps(10.0, -10.0),
        ),
        "yan-steps-high" => (
            "Yan (2019) square-wave test, high band: 45 -> 65 -> 45 °C, 180 min holds, \
             20 min ramps at 1 °C/min, about 9.7 h at 1 Hz (65 °C: 5 °C above the \
             calibration run).",
            45.0,
            yan_steps(45.0, 65.0),
        ),
        "yan-full-range" => (
            "Yan (2019) full-range check at 0.5 °C/min: -25 °C 1 h, to -45, 2 h, to 65, 2 h, \
             to 25, 0.5 h; about 11.2 h at 1 Hz.",
            -25.0,
            vec![
                hold_min(60.0),
                ramp(-45.0, 0.5),
                hold_min(120.0),
                ramp(65.0, 0.5),
                hold_min(120.0),
                ramp(25.0, 0.5),
                hold_min(30.0),
            ],
        ),
        "laser-gyro" => (
            "Ring laser gyro as Sukhanov (2011), powered on at t = 0: self-heating (λ = 30 min), \
             housing and resonator-base sensors, laser power, piezo voltage and dither \
             amplitude logged; 20 °C 2 h, 0.5 °C/min to 50, 1.5 h, to -10, 1.5 h, to 20, 1 h; \
             10 h at 1 Hz.",
            20.0,
            vec![
                hold_min(120.0),
                ramp(50.0, 0.5),
                hold_min(90.0),
                ramp(-10.0, 0.5),
                hold_min(90.0),
                ramp(20.0, 0.5),
                hold_min(60.0),
            ],
        ),
        "mems-imu" => (
            "A six-axis MEMS IMU (a flight controller's: three gyros, three accelerometers \
             reading 1 g on z) soaked at -20 °C, then 1 °C/min to 60 °C with 45-min holds at \
             -20, 0, 20, 40 and 60 °C; accelerometer biases known cubics in T, z's scale \
             factor -150 ppm/°C; about 5.1 h at 1 Hz.",
            -20.0,
            vec![
                hold_min(45.0),
                ramp(0.0, 1.0),
                hold_min(45.0),
                ramp(20.0, 1.0),
                hold_min(45.0),
                ramp(40.0, 1.0),
                hold_min(45.0),
                ramp(60.0, 1.0),
                hold_min(45.0),
            ],
        ),
        _ => return None,
    };
    let mems = name == "mems-imu";
    Some(Profile {
        name: name.to_string(),
        description: description.to_string(),
        sample_rate_hz: 1.0,
        start_c,
        program,
        gyro: if mems {
            super::mems::board()
        } else {
            GyroParams::default()
        },
        laser: (name == "laser-gyro").then(LaserParams::default),
        axes: if mems {
            super::mems::gyros()
        } else {
            Vec::new()
        },
        accelerometers: if mems {
            super::mems::accelerometers()
        } else {
            Vec::new()
        },
    })
}

/// One square-wave test of Yan (2019) as the paper programs the chamber: hold `from_c` for
/// 180 min, ramp to `to_c` in 20 min, hold 180 min, ramp back in 20 min, hold 180 min.
fn yan_steps(from_c: f64, to_c: f64) -> Vec<Segment> {
    // The paper: 20 °C in 20 min, "about 1.0 °C/min".
    let rate = (to_c - from_c).abs() / 20.0;
    vec![
        hold_min(180.0),
        ramp(to_c, rate),
        hold_min(180.0),
        ramp(from_c, rate),
        hold_min(180.0),
    ]
}
