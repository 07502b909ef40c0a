//! driftlab's own simulator of a motionless fibre-optic gyro (FOG) in a thermal chamber, and
//! of a ring laser gyro for the `laser-gyro` profile ([`LaserParams`], Sukhanov 2011).
//!
//! It makes test logs whose truth is known, so that every calibration method of the workbench
//! (docs/method.md) can be exercised and judged without a chamber: the noise-free thermal drift and
//! the noise are returned beside the raw output. A profile plus a seed names one log: the
//! random numbers come from `ChaCha8Rng::seed_from_u64(seed)`, the same on every machine.
//!
//! # Physics
//!
//! * **Chamber air** follows the program exactly: linear ramps at the given rate, holds.
//! * **Housing** (the coil frame) follows the air through a first-order lag
//!   (`housing_tau_s`, 12 min), integrated exactly for an input linear over each step.
//! * **Fibre winding** (12 mm thick between radii 30 and 42 mm): 1-D radial heat diffusion,
//!   `∂T/∂t = (1/r)·∂/∂r(r·K(T)·∂T/∂r)`, in `coil_layers` (16) finite volumes between the
//!   spool (adiabatic) and the outer surface, which the housing holds. The diffusivity rises
//!   with temperature, `K(T) = K20·(1 + α·(T − 20))` (K20 = 1.52·10⁻⁷ m²/s, α = 0.010/°C), so
//!   heat reaches the inner layers sooner when warm: the innermost layer lags a small step of
//!   the housing by about 930 s around −35 °C, 550 s around 0 °C and 330 s around +55 °C
//!   (time to half-step), close to the drift delays Yan (2019) fitted for his low, middle and
//!   high band: 863, 547 and 309 s (docs/method.md §3). Explicit steps, sub-divided as stability
//!   needs ([`Coil`]).
//! * **Temperature sensor** on the coil frame: the housing temperature plus a little white
//!   noise (`sensor_noise_c`), quantised to `sensor_resolution_c` (0.001 °C). It leads the
//!   winding during transients, which is why the drift depends on its Ṫ and T̈.
//! * **Thermal drift** (`thermal_dph`), with fibre weights `w_i` = fibre share of layer `i`
//!   times its centred radial position (−1 inner … +1 outer), `Σ w_i = 0`:
//!
//!   ```text
//!   thermal = K0(T_coil) + (S·Σ w_i·Ṫ_i + G·f(T)·Σ w_i·T_i) · (1 + a·tanh(Σ w_i·T_i / 0.5 °C))
//!   K0(T)   = b0 + b1·(T − 20) + b2·(T − 20)²        (≈ 0.3 °/h over −50…+60 °C)
//!   ```
//!
//!   The Shupe term `S·Σ w_i·Ṫ_i` is the weighted difference of heating rates across the
//!   winding: it appears when the rate of the frame changes (start and end of a ramp, so it
//!   follows T̈ of the sensor through the diffusion lag) and has opposite signs in the
//!   accelerating and the decelerating phase — the + and − sets of docs/method.md §1. On a steady
//!   ramp every layer heats at the same rate and the Shupe term vanishes; what remains is the
//!   thermal-stress term `G·Σ w_i·T_i` of the radial gradient, which in a steady ramp is
//!   proportional to Ṫ (the gradient a ramp of rate Ṫ sustains is about Ṫ·d²/2K). The stress
//!   follows the heat flux through the winding, conductivity times gradient, hence the factor
//!   f(T) = K(T)/K20: on a steady ramp the flux, and so this term, does not depend on the
//!   temperature the ramp passes through, although the gradient does. The factor
//!   `(1 + a·…)` makes heating from outside give a slightly larger drift than cooling.
//!   `K0` is taken at the fibre-weighted mean coil temperature.
//! * **Noise** (`noise_dph`): white noise from the angle random walk (`arw_deg_per_sqrt_h`,
//!   0.18 °/h per sample at 1 Hz), a first-order Gauss-Markov bias (`bias_instability_dph`,
//!   `bias_correlation_s`) started in its stationary state, and a tiny rate random walk.
//!   `omega_dph = thermal_dph + noise_dph` exactly.
//!
//! Magnitudes (reference gyro, `calibration` profile): the drift smoothed by a centred
//! 100-sample moving average spans about 1.6 °/h peak to peak (Vakhrameev 2017: 1.68 °/h); the
//! noise smoothed the same way about 0.13 °/h. Gyro noise and sensor noise come from two
//! ChaCha streams of the one seed.
//!
//! # Profiles
//!
//! [`profile_names`] lists the built-in chamber programs: the calibration run of Vakhrameev
//! (2017) and held-out runs of the same FOG (other plateaus and rates, no plateaus, 2 °C/min
//! ramps), Yan's (2019) three square-wave tests (`yan-steps-low`, `-mid`, `-high`) and his
//! full-range run at 0.5 °C/min (`yan-full-range`), and a laser gyro with two temperature
//! sensors, self-heating and extra channels (`laser-gyro`; physics in [`LaserParams`]).
//!
//! # Noise floor
//!
//! [`SimRun::noise_only`] (and [`simulate_noise_only`]) gives the same run with every
//! deterministic drift term zero: the output is the gyro noise alone, sample for sample the
//! noise of the full run of that seed, and the temperatures and channels are unchanged. It is
//! the simulator's own floor: filtered like the drift, it is what a perfect correction would
//! leave. `omega_dph` of the full run minus that of the noise-only run is `thermal_dph`, to the
//! rounding of one addition.

mod laser;
mod noise;
mod profile;
mod thermal;

use std::io::Write;
use std::path::Path;

use crate::log::{Channel, ColumnInfo, ColumnRole, Log};

pub use laser::LaserParams;
pub use profile::{GyroParams, Profile, Segment, profile, profile_names};
pub use thermal::Coil;

/// Longest physics step, s: a log sampled slower than 1 Hz is still integrated every second
/// or finer, so the thermal state does not depend on the sampling rate.
const MAX_PHYSICS_STEP_S: f64 = 1.0;

/// Scale of the smooth sign used by the heating/cooling asymmetry, °C of weighted gradient.
const ASYMMETRY_SCALE_C: f64 = 0.5;

/// One simulated run: what the test stand would log, plus the truth behind it.
///
/// All columns have one value per sample and are aligned with `time_s`.
#[derive(Debug, Clone, Default)]
pub struct SimRun {
    /// Name of the profile that was run, written into the CSV comment.
    pub profile: String,
    /// Seed of the noise, written into the CSV comment.
    pub seed: u64,
    /// Time since the start of the program, s (rounded to 1 ns so it prints exactly).
    pub time_s: Vec<f64>,
    /// Chamber air temperature (the program), °C.
    pub chamber_c: Vec<f64>,
    /// Calibration temperature sensor on the coil frame, °C, quantised to its resolution.
    pub temp_c: Vec<f64>,
    /// Raw gyro output, °/h: `thermal_dph + noise_dph`.
    pub omega_dph: Vec<f64>,
    /// Noise-free thermal drift including the static bias K0, °/h: what a perfect
    /// calibration would predict.
    pub thermal_dph: Vec<f64>,
    /// The noise alone, °/h: the floor a correction cannot go below.
    pub noise_dph: Vec<f64>,
    /// True housing (frame) temperature, °C, without sensor noise or quantisation.
    pub housing_c: Vec<f64>,
    /// Fibre-weighted mean temperature of the winding, °C (what K0 is a function of).
    pub coil_mean_c: Vec<f64>,
    /// Temperature of the innermost layer of the winding, °C (the most delayed one).
    /// For a laser gyro, `coil_mean_c` and `coil_inner_c` are both the true resonator-base
    /// temperature (the block has no winding).
    pub coil_inner_c: Vec<f64>,
    /// Logged channels written after `temp_chamber_c`, in column order: for a laser gyro
    /// `temp_housing_c`, `laser_power_mw`, `piezo_v`, `dither_amp_arcsec`; none for a FOG.
    pub channels: Vec<SimChannel>,
    /// Truth behind a laser-gyro run; `None` for a FOG.
    pub laser: Option<LaserTruth>,
    /// True for a noise-only run ([`SimRun::noise_only`]): `thermal_dph` is zero and
    /// `omega_dph` is `noise_dph`. Written into the CSV comment as `--noise-only`.
    pub noise_only: bool,
}

/// One logged channel of a simulated run besides time, rate and the two temperatures every run
/// has, as the CSV holds it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SimChannel {
    /// Column name, with the unit as its last word (`laser_power_mw`).
    pub name: String,
    /// Unit, for [`SimRun::to_log`].
    pub unit: String,
    /// Decimals written to the CSV: the values are quantised to them, so they read back
    /// exactly.
    pub decimals: usize,
    /// One value a sample.
    pub values: Vec<f64>,
}

impl SimChannel {
    pub(crate) fn new(name: &str, unit: &str, decimals: usize, values: Vec<f64>) -> SimChannel {
        SimChannel {
            name: name.to_string(),
            unit: unit.to_string(),
            decimals,
            values,
        }
    }
}

/// What a laser-gyro run's drift is made of, sample by sample (see [`LaserParams`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LaserTruth {
    /// True resonator-base temperature, °C (the logged `temp_base_c` is its sensor).
    pub base_c: Vec<f64>,
    /// True laser power, mW, before measurement noise.
    pub laser_power_mw: Vec<f64>,
    /// True piezo-corrector voltage, V.
    pub piezo_v: Vec<f64>,
    /// True dither amplitude, arcsec.
    pub dither_amp_arcsec: Vec<f64>,
    /// The self-heating term B1·(1 − e^(−t/λ)) of the drift, °/h.
    pub self_heating_dph: Vec<f64>,
}

/// Simulates `profile` with noise seed `seed`.
///
/// # Panics
/// When `profile.check()` fails; callers holding a hand-made profile check it first.
pub fn simulate(profile: &Profile, seed: u64) -> SimRun {
    simulate_with_progress(profile, seed, &|_| {})
}

/// As [`simulate`], calling `progress` with the fraction done (0 to 1) about every 0.5 % of
/// the run, so a GUI or a progress bar can follow a long simulation.
///
/// # Panics
/// When `profile.check()` fails.
pub fn simulate_with_progress(profile: &Profile, seed: u64, progress: &dyn Fn(f64)) -> SimRun {
    if let Err(e) = profile.check() {
        panic!("invalid profile {:?}: {e}", profile.name);
    }
    if let Some(l) = &profile.laser {
        return laser::simulate(profile, l, seed, progress);
    }
    let p = &profile.gyro;
    let dt = 1.0 / profile.sample_rate_hz;
    let n = profile.sample_count();
    let subs = ((dt / MAX_PHYSICS_STEP_S).ceil() as usize).max(1);
    let h = dt / subs as f64;

    let program = thermal::Program::new(profile);
    let mut coil = Coil::new(p, profile.start_c);
    let mut housing = profile.start_c;
    let mut gyro_noise = noise::GyroNoise::new(p, dt, seed);
    let mut sensor = noise::Sensor::new(p, seed);

    let mut run = SimRun {
        profile: profile.name.clone(),
        seed,
        ..SimRun::default()
    };
    for col in [
        &mut run.time_s,
        &mut run.chamber_c,
        &mut run.temp_c,
        &mut run.omega_dph,
        &mut run.thermal_dph,
        &mut run.noise_dph,
        &mut run.housing_c,
        &mut run.coil_mean_c,
        &mut run.coil_inner_c,
    ] {
        col.reserve_exact(n);
    }

    let report_every = (n / 200).max(1);
    progress(0.0);
    for i in 0..n {
        let t = i as f64 * dt;
        if i > 0 {
            let t_prev = (i - 1) as f64 * dt;
            for k in 0..subs {
                let ta = t_prev + k as f64 * h;
                let tb = t_prev + (k + 1) as f64 * h;
                let next = thermal::lag_step(
                    housing,
                    program.air_c(ta),
                    program.air_c(tb),
                    h,
                    p.housing_tau_s,
                );
                coil.step(housing, next, h);
                housing = next;
            }
        }
        let thermal = thermal_drift(p, &mut coil, housing);
        let noise = gyro_noise.next();
        run.time_s.push((t * 1e9).round() / 1e9);
        run.chamber_c.push(program.air_c(t));
        run.temp_c.push(sensor.read(housing));
        run.thermal_dph.push(thermal);
        run.noise_dph.push(noise);
        run.omega_dph.push(thermal + noise);
        run.housing_c.push(housing);
        run.coil_mean_c.push(coil.mean_c());
        run.coil_inner_c.push(coil.layers_c()[0]);
        if i % report_every == 0 && i > 0 {
            progress(i as f64 / n as f64);
        }
    }
    progress(1.0);
    run
}

/// The noise-free drift of the gyro in its current thermal state, °/h (see the module doc).
fn thermal_drift(p: &GyroParams, coil: &mut Coil, housing_c: f64) -> f64 {
    let gradient = coil.gradient_c();
    let rate_gradient = coil.rate_gradient_c_per_s(housing_c);
    // The stress follows the heat flux through the winding (conductivity × gradient): on a
    // steady ramp the flux is set by the heat the coil must take up, Ṫ times its capacity,
    // whatever the temperature; the gradient itself grows as the diffusivity falls.
    let flux_factor = p.diffusivity_m2_per_s(coil.mean_c()) / p.coil_diffusivity_20c_m2_per_s;
    let transient =
        p.shupe_dph_per_c_per_s * rate_gradient + p.stress_dph_per_c * gradient * flux_factor;
    let asymmetry = 1.0 + p.heating_asymmetry * (gradient / ASYMMETRY_SCALE_C).tanh();
    p.static_bias_dph(coil.mean_c()) + transient * asymmetry
}

/// The run of `profile` with seed `seed` with every deterministic drift term zero: the gyro
/// noise alone, exactly the `noise_dph` of [`simulate`] with the same arguments, beside the
/// same temperatures and channels. See [`SimRun::noise_only`].
///
/// # Panics
/// When `profile.check()` fails.
pub fn simulate_noise_only(profile: &Profile, seed: u64) -> SimRun {
    simulate(profile, seed).noise_only()
}

impl SimRun {
    /// This run with every deterministic drift term zero: `thermal_dph` (and a laser gyro's
    /// self-heating term) set to 0, `omega_dph` = `noise_dph`, everything else unchanged,
    /// marked `noise_only` so its CSV says so. The simulator's own noise floor: the same noise
    /// samples as the full run, so that the full output minus this one is the drift.
    pub fn noise_only(&self) -> SimRun {
        let mut run = self.clone();
        run.omega_dph.clone_from(&run.noise_dph);
        run.thermal_dph.iter_mut().for_each(|x| *x = 0.0);
        if let Some(l) = &mut run.laser {
            l.self_heating_dph.iter_mut().for_each(|x| *x = 0.0);
        }
        run.noise_only = true;
        run
    }

    /// Name of the calibration temperature column: `temp_c` for a FOG, `temp_base_c` (the
    /// resonator-base sensor) for a laser gyro. It is the first temperature column of the CSV,
    /// so ingest takes it as the calibration temperature.
    pub fn temp_column(&self) -> &'static str {
        if self.laser.is_some() {
            "temp_base_c"
        } else {
            "temp_c"
        }
    }

    /// The command that makes this run, as the CSV's first line says it (without `--out`).
    pub fn command(&self) -> String {
        format!(
            "driftlab simulate --profile {} --seed {}{}",
            self.profile,
            self.seed,
            if self.noise_only { " --noise-only" } else { "" }
        )
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    /// True when the run has no samples.
    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }

    /// The run as the engine's [`Log`], the way ingest reads its CSV: time, rate and sensor
    /// temperature as the calibration columns, the chamber air as the extra channel
    /// `temp_chamber_c`, then the run's [`channels`](SimRun::channels) by name (with their
    /// units, which the CSV header only carries as the last word of the name). The truth
    /// columns are not part of a log.
    pub fn to_log(&self, source: &str) -> Log {
        let mut log = Log::from_columns(
            source,
            self.time_s.clone(),
            self.omega_dph.clone(),
            self.temp_c.clone(),
        );
        log.extra.push(Channel {
            name: "temp_chamber_c".to_string(),
            unit: "°C".to_string(),
            values: self.chamber_c.clone(),
        });
        for c in &self.channels {
            log.extra.push(Channel {
                name: c.name.clone(),
                unit: c.unit.clone(),
                values: c.values.clone(),
            });
        }
        log.info.has_header = true;
        let fixed = [
            ("time_s", ColumnRole::Time, "s"),
            ("omega_dph", ColumnRole::Rate, "deg/h"),
            (self.temp_column(), ColumnRole::Temperature, "°C"),
            ("temp_chamber_c", ColumnRole::Extra, "°C"),
        ];
        log.info.columns = fixed
            .into_iter()
            .chain(
                self.channels
                    .iter()
                    .map(|c| (c.name.as_str(), ColumnRole::Extra, c.unit.as_str())),
            )
            .enumerate()
            .map(|(i, (name, role, unit))| ColumnInfo {
                index: i + 1,
                name: name.to_string(),
                role,
                unit: unit.to_string(),
            })
            .collect();
        log
    }

    /// Writes the run as a test-stand CSV, atomically: a `# driftlab simulate --profile NAME
    /// --seed N` comment (with `--noise-only` for a noise-only run), the header
    /// `time_s,omega_dph,temp_c,temp_chamber_c` (a laser gyro: `temp_base_c` for `temp_c`, then
    /// its [`channels`](SimRun::channels)), then one row a sample (time exact, rate to
    /// 0.0001 °/h, temperatures to 0.001 °C, channels to their resolution).
    pub fn write_csv(&self, path: &Path) -> std::io::Result<()> {
        crate::files::atomic::write_with(path, |w| self.write_csv_to(w))
    }

    fn write_csv_to(&self, w: &mut dyn Write) -> std::io::Result<()> {
        writeln!(w, "# {}", self.command())?;
        write!(w, "time_s,omega_dph,{},temp_chamber_c", self.temp_column())?;
        for c in &self.channels {
            write!(w, ",{}", c.name)?;
        }
        writeln!(w)?;
        for i in 0..self.len() {
            // Display of f64 is the shortest text that reads back to the same number.
            write!(
                w,
                "{},{:.4},{:.3},{:.3}",
                self.time_s[i], self.omega_dph[i], self.temp_c[i], self.chamber_c[i]
            )?;
            for c in &self.channels {
                let v = c.values.get(i).copied().unwrap_or(f64::NAN);
                write!(w, ",{:.*}", c.decimals, v)?;
            }
            writeln!(w)?;
        }
        Ok(())
    }
}
