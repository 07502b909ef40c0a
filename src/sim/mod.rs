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
//! * **Several axes** ([`AxisParams`], `--axes 3`): one housing and one winding model, so one
//!   thermal field; each axis turns it into drift with its own K0(T), Shupe, stress and
//!   asymmetry constants (other signs and sizes) and has its own noise from its own stream.
//!   Each axis's drift is the formula above with its constants ([`axes`](SimRun::axes) holds
//!   it split into its K0, Shupe and stress parts). Accelerometers ([`AccelParams`],
//!   `--accel`) read gravity with a small dependence on the housing temperature.
//!
//! Magnitudes (reference gyro, `calibration` profile): the drift smoothed by a centred
//! 100-sample moving average spans about 1.6 °/h peak to peak (Vakhrameev 2017: 1.68 °/h); the
//! noise smoothed the same way about 0.13 °/h. Every random part (each axis's gyro noise, each
//! sensor, the split of the noise over faster samples, the host's stamps) has its own ChaCha
//! stream of the one seed, so that adding one never reshuffles another.
//!
//! # Profiles
//!
//! [`profile_names`] lists the built-in chamber programs: the calibration run of Vakhrameev
//! (2017) and held-out runs of the same FOG (other plateaus and rates, no plateaus, 2 °C/min
//! ramps), Yan's (2019) three square-wave tests (`yan-steps-low`, `-mid`, `-high`) and his
//! full-range run at 0.5 °C/min (`yan-full-range`), and a laser gyro with two temperature
//! sensors, self-heating and extra channels (`laser-gyro`; physics in [`LaserParams`]).
//!
//! # Campaigns
//!
//! [`campaign_names`] lists the built-in campaigns, several runs of one gyro (one calibration
//! fitted on all of them, bias repeatability, thermal hysteresis): each run a profile, a seed and
//! a turn-on offset, a constant bias that [`simulate_campaign`] adds to every axis's output and
//! truth. The simulated gyro has no static thermal hysteresis ([`campaign`](mod@campaign)).
//!
//! # Noise floor
//!
//! [`SimRun::noise_only`] (and [`simulate_noise_only`]) gives the same run with every
//! deterministic drift term zero: the output is the gyro noise alone, sample for sample the
//! noise of the full run of that seed, and the temperatures and channels are unchanged. It is
//! the simulator's own floor: filtered like the drift, it is what a perfect correction would
//! leave. `omega_dph` of the full run minus that of the noise-only run is `thermal_dph`, to the
//! rounding of one addition. It combines with every logging option below.
//!
//! # Logging
//!
//! [`Logging`] says what the logger records of a run (the gyro does not care): the sampling
//! rate (`--rate-hz`; a whole multiple of the profile's rate is the same gyro and thermal
//! history sampled faster, see [`Logging::rate_hz`] for how), outages that remove samples
//! (`--gap`), bursts outside which nothing is written (`--bursts`), and the stamps of a host
//! that reads the samples in batches (`--jitter`, [`HostJitter`]): the true sampling stays
//! regular and the data are those of the regular run, only the time column changes. The
//! random parts of the logging have their own streams of the seed, so a run is still named by
//! its profile, seed and options.
//!
//! # Writing
//!
//! [`CsvDialect`] says how the log is written: driftlab's own columns, or a test stand's (ms,
//! deg/s named `gx_dps;gy_dps;gz_dps`, `;`, decimal comma, a `#` line naming the stand), a raw
//! int16 temperature register beside the real temperature, and the names and units of
//! [`RateNames`] and the rate unit. [`SimRun::write_csv_as`] writes a collected run;
//! [`write_simulated_csv`] writes a run as it is simulated, without holding it (a 10-h log at
//! 1 kHz is 36 million samples), to the same bytes. The first `#` line after the stand's is
//! the `driftlab simulate` command that makes the file again.

mod axes;
pub mod campaign;
mod dialect;
mod error;
mod fog;
mod laser;
mod logging;
mod mems;
mod noise;
mod profile;
mod run;
mod thermal;

use std::io::Write;
use std::path::Path;

use crate::log::{Channel, ColumnInfo, ColumnRole, Log};

pub use axes::{AccelParams, AxisParams, default_accelerometers, default_axes};
pub use campaign::{
    Campaign, CampaignRun, RunOfCampaign, campaign, campaign_names, simulate_campaign,
};
pub use dialect::{
    AccelUnit, CsvDialect, DialectPreset, ESTIMATED_TEMP_COLUMN, RAW_TEMP_COLUMN,
    RAW_TEMP_COUNTS_PER_C, RAW_TEMP_OFFSET_C, RateNames, STAND_LINE, parse_decimal_mark,
    parse_separator, raw_temp_counts, raw_temp_to_c,
};
pub use error::{SimError, UnknownChoice};
pub use laser::LaserParams;
pub use logging::{Bursts, Gap, HostJitter, Logging};
pub use profile::{GyroParams, Profile, Segment, profile, profile_names};
pub use thermal::Coil;

use dialect::{Row, Shape, Writer};
use run::Plan;

/// Longest physics step, s: a log sampled slower than 1 Hz is still integrated every second
/// or finer, so the thermal state does not depend on the sampling rate.
const MAX_PHYSICS_STEP_S: f64 = 1.0;

/// The time steps of a run: the sample interval `dt` and the count `n` of samples, the
/// physics' `subs` sub-steps of `h` per sample (none longer than [`MAX_PHYSICS_STEP_S`]), and
/// the `h_fine` steps of the fine sensor model (`fine` per sample, whose white noise is
/// scaled by `sqrt_fine`), and how many samples pass between two progress reports.
struct Steps {
    dt: f64,
    n: usize,
    subs: usize,
    h: f64,
    h_fine: f64,
    sqrt_fine: f64,
    report_every: usize,
}

impl Steps {
    fn of(profile: &Profile, fine: usize) -> Steps {
        let dt = 1.0 / profile.sample_rate_hz;
        let subs = ((dt / MAX_PHYSICS_STEP_S).ceil() as usize).max(1);
        let n = profile.sample_count();
        Steps {
            dt,
            n,
            subs,
            h: dt / subs as f64,
            h_fine: dt / fine as f64,
            sqrt_fine: (fine as f64).sqrt(),
            report_every: (n / 200).max(1),
        }
    }
}

/// Scale of the smooth sign used by the heating/cooling asymmetry, °C of weighted gradient.
const ASYMMETRY_SCALE_C: f64 = 0.5;

/// Everything about a written log besides the profile and the seed: what `driftlab simulate`
/// takes after `--profile` and `--seed` (the unit's axes and accelerometers are in the
/// profile, [`Profile::with_axes`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SimOptions {
    /// Write the noise alone ([`SimRun::noise_only`]).
    pub noise_only: bool,
    /// What the logger records.
    pub logging: Logging,
    /// How the log is written.
    pub dialect: CsvDialect,
}

/// One simulated run: what the test stand would log, plus the truth behind it.
///
/// All columns have one value per recorded sample and are aligned with `time_s` (those of a
/// part the run does not have are empty).
#[derive(Debug, Clone, Default)]
pub struct SimRun {
    /// Name of the profile that was run, written into the CSV comment.
    pub profile: String,
    /// Seed of the noise, written into the CSV comment.
    pub seed: u64,
    /// Sampling rate of the log, Hz (the profile's, or `--rate-hz`).
    pub sample_rate_hz: f64,
    /// How the run was logged (written into the CSV comment as its options).
    pub logging: Logging,
    /// True sampling instant of each sample, s since the start of the program (rounded to
    /// 1 ns so it prints exactly). Samples the logger left out (gaps, bursts) are not here.
    pub time_s: Vec<f64>,
    /// The host's time stamps when logged with jitter ([`HostJitter`]): what the time column
    /// of the CSV holds instead of `time_s`. `None` without jitter.
    pub stamp_s: Option<Vec<f64>>,
    /// Chamber air temperature (the program), °C.
    pub chamber_c: Vec<f64>,
    /// Calibration temperature sensor on the coil frame, °C, quantised to its resolution.
    pub temp_c: Vec<f64>,
    /// Raw gyro output of the first (or only) axis, °/h: `thermal_dph + noise_dph`.
    pub omega_dph: Vec<f64>,
    /// Noise-free thermal drift including the static bias K0 of the first axis, °/h: what a
    /// perfect calibration would predict.
    pub thermal_dph: Vec<f64>,
    /// The noise alone of the first axis, °/h: the floor a correction cannot go below.
    pub noise_dph: Vec<f64>,
    /// True housing (frame) temperature, °C, without sensor noise or quantisation.
    pub housing_c: Vec<f64>,
    /// Fibre-weighted mean temperature of the winding, °C (what K0 is a function of).
    pub coil_mean_c: Vec<f64>,
    /// Temperature of the innermost layer of the winding, °C (the most delayed one).
    /// For a laser gyro, `coil_mean_c` and `coil_inner_c` are both the true resonator-base
    /// temperature (the block has no winding).
    pub coil_inner_c: Vec<f64>,
    /// Fibre-weighted radial temperature difference of the winding, °C (Σ wᵢ·Tᵢ, positive when
    /// the outside is warmer): the field of the stress term. Empty for a laser gyro.
    pub coil_gradient_c: Vec<f64>,
    /// Fibre-weighted radial difference of heating rates, °C/s (Σ wᵢ·Ṫᵢ): the field of the
    /// Shupe term. Empty for a laser gyro.
    pub coil_rate_gradient_c_per_s: Vec<f64>,
    /// Every gyro axis of a fibre-optic run with its truth, the first being `omega_dph`,
    /// `thermal_dph` and `noise_dph` again (one axis, `x`, for a single gyro). Empty for a
    /// laser gyro, whose truth is in `laser`.
    pub axes: Vec<SimAxis>,
    /// The accelerometers, if the unit has any.
    pub accelerometers: Vec<SimAccel>,
    /// Logged channels written after `temp_chamber_c`, in column order: for a laser gyro
    /// `temp_housing_c`, `laser_power_mw`, `piezo_v`, `dither_amp_arcsec`; none for a FOG.
    pub channels: Vec<SimChannel>,
    /// Truth behind a laser-gyro run; `None` for a FOG.
    pub laser: Option<LaserTruth>,
    /// True for a noise-only run ([`SimRun::noise_only`]): `thermal_dph` is zero and
    /// `omega_dph` is `noise_dph`. Written into the CSV comment as `--noise-only`.
    pub noise_only: bool,
    /// The run's place in a campaign, with the turn-on offset its output and truth hold
    /// ([`simulate_campaign`]); `None` for a run of one profile.
    pub campaign: Option<RunOfCampaign>,
}

/// One gyro axis of a fibre-optic run, sample by sample, °/h.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SimAxis {
    /// Axis name (`x`, `y`, `z`).
    pub name: String,
    /// Output: `thermal_dph + noise_dph`.
    pub omega_dph: Vec<f64>,
    /// Noise-free drift: `static_dph + shupe_dph + stress_dph` (to the rounding of the sum).
    pub thermal_dph: Vec<f64>,
    /// The noise alone.
    pub noise_dph: Vec<f64>,
    /// K0 of the axis at the fibre-weighted mean coil temperature.
    pub static_dph: Vec<f64>,
    /// Shupe term S·Σwᵢ·Ṫᵢ, times the heating/cooling asymmetry factor.
    pub shupe_dph: Vec<f64>,
    /// Thermal-stress term G·Σwᵢ·Tᵢ·K(T)/K20, times the asymmetry factor.
    pub stress_dph: Vec<f64>,
}

/// One accelerometer of a run, sample by sample, g.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SimAccel {
    /// Axis name (`x`, `y`, `z`).
    pub name: String,
    /// Logged reading: noise included, quantised.
    pub values_g: Vec<f64>,
    /// Noise-free reading.
    pub true_g: Vec<f64>,
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
    match simulate_logged(profile, seed, &Logging::default(), progress) {
        Ok(run) => run,
        Err(e) => panic!("invalid profile {:?}: {e}", profile.name),
    }
}

/// Simulates `profile` with seed `seed` as `logging` records it (rate, gaps, bursts, host
/// stamps), calling `progress` as [`simulate_with_progress`] does. With the default logging
/// it is [`simulate_with_progress`].
///
/// # Errors
/// A profile or an option that cannot be simulated, with the sentence naming it.
pub fn simulate_logged(
    profile: &Profile,
    seed: u64,
    logging: &Logging,
    progress: &dyn Fn(f64),
) -> Result<SimRun, SimError> {
    let plan = Plan::new(profile, logging)?;
    let run = plan.collect(seed, logging, progress);
    plan.check_recorded(logging, run.len())?;
    Ok(run)
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

/// Simulates `profile` with seed `seed` and writes it to `path` as `options` say, atomically,
/// one sample at a time: the bytes of [`simulate_logged`] then ([`SimRun::noise_only`] and)
/// [`SimRun::write_csv_as`], without holding the run. Returns the number of rows written.
///
/// # Errors
/// An option that cannot be simulated or written (before anything is written), or the write.
pub fn write_simulated_csv(
    profile: &Profile,
    seed: u64,
    options: &SimOptions,
    path: &Path,
    progress: &dyn Fn(f64),
) -> Result<usize, SimError> {
    options.dialect.check()?;
    let plan = Plan::new(profile, &options.logging)?;
    let shape = plan.shape();
    let command = command_line(
        &profile.name,
        seed,
        options.noise_only,
        &shape,
        &options.logging,
        &options.dialect,
    );
    let mut rows = 0;
    let mut too_few = false;
    let fill = |w: &mut dyn Write| {
        let mut writer = Writer::new(&options.dialect);
        writer.head(w, &shape, &command)?;
        let mut rates = Vec::with_capacity(shape.axes.len());
        let mut accel = Vec::with_capacity(shape.accels.len());
        let mut sink = |s: &run::Sample, stamp: Option<f64>| {
            rates.clear();
            let rate = |a: &run::AxisSample| if options.noise_only { a.noise } else { a.omega };
            rates.extend(s.axes.iter().map(rate));
            accel.clear();
            accel.extend(s.accel.iter().map(|a| a.value_g));
            rows += 1;
            let row = Row {
                time_s: stamp.unwrap_or(s.time_s),
                rates_dph: &rates,
                accel_g: &accel,
                temp_c: s.temp_c,
                chamber_c: s.chamber_c,
                channels: &s.channels,
            };
            writer.row(w, &row, &shape)
        };
        plan.drive(seed, &options.logging, progress, &mut sink)?;
        // Checked before the file is put in place: a log of fewer than two samples is not
        // written at all (the error below says why).
        if rows < 2 {
            too_few = true;
            return Err(std::io::Error::other("too few samples recorded"));
        }
        Ok(())
    };
    let written = if plan.samples() > 1_000_000 {
        crate::files::atomic::write_big_with(path, fill)
    } else {
        crate::files::atomic::write_with(path, fill)
    };
    if too_few {
        plan.check_recorded(&options.logging, rows)?;
    }
    written.map_err(|source| SimError::Write {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(rows)
}

/// The `driftlab simulate` command that makes a log, as its first `#` line says it.
fn command_line(
    profile: &str,
    seed: u64,
    noise_only: bool,
    shape: &Shape,
    logging: &Logging,
    dialect: &CsvDialect,
) -> String {
    let mut words = vec![format!(
        "driftlab simulate --profile {profile} --seed {seed}"
    )];
    if noise_only {
        words.push("--noise-only".into());
    }
    // A profile whose unit is its own (`mems-imu`) is made again without the options that
    // build a unit of another profile's gyro.
    let own = profile::profile(profile);
    if shape.axes.len() > 1 && own.as_ref().is_none_or(|p| p.axes.is_empty()) {
        words.push(format!("--axes {}", shape.axes.len()));
    }
    if !shape.accels.is_empty() && own.as_ref().is_none_or(|p| p.accelerometers.is_empty()) {
        words.push("--accel".into());
    }
    words.extend(logging.args());
    words.extend(dialect.args());
    words.join(" ")
}

impl SimRun {
    /// This run with every deterministic drift term zero: `thermal_dph` (and every axis's
    /// drift and its parts, and a laser gyro's self-heating term) set to 0, `omega_dph` =
    /// `noise_dph`, everything else unchanged (temperatures, channels, accelerometers, stamps),
    /// marked `noise_only` so its CSV says so (a campaign run's turn-on offset, a
    /// deterministic term, is taken out too). The simulator's own noise floor: the same noise
    /// samples as the full run, so that the full output minus this one is the drift.
    pub fn noise_only(&self) -> SimRun {
        let mut run = self.clone();
        run.omega_dph.clone_from(&run.noise_dph);
        run.thermal_dph.iter_mut().for_each(|x| *x = 0.0);
        for a in &mut run.axes {
            a.omega_dph.clone_from(&a.noise_dph);
            for col in [
                &mut a.thermal_dph,
                &mut a.static_dph,
                &mut a.shupe_dph,
                &mut a.stress_dph,
            ] {
                col.iter_mut().for_each(|x| *x = 0.0);
            }
        }
        if let Some(l) = &mut run.laser {
            l.self_heating_dph.iter_mut().for_each(|x| *x = 0.0);
        }
        if let Some(c) = &mut run.campaign {
            // The offset is a deterministic term too: the noise alone holds none.
            c.turn_on_offset_dph = 0.0;
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

    /// The command that makes this run in driftlab's dialect, as the CSV's first line says it
    /// (without `--out`).
    pub fn command(&self) -> String {
        self.command_as(&CsvDialect::driftlab())
    }

    /// The command that makes this run written in `dialect` (without `--out`). A campaign's
    /// run is made by `driftlab simulate --campaign NAME`, which writes every run of it (the
    /// file's name says which).
    pub fn command_as(&self, dialect: &CsvDialect) -> String {
        if let Some(c) = &self.campaign {
            let mut words = vec![format!("driftlab simulate --campaign {}", c.campaign)];
            words.extend(dialect.args());
            return words.join(" ");
        }
        command_line(
            &self.profile,
            self.seed,
            self.noise_only,
            &self.shape(),
            &self.logging,
            dialect,
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

    /// The gyro axis named `name` (`x`, `y`, `z`) of a fibre-optic run.
    pub fn axis(&self, name: &str) -> Option<&SimAxis> {
        self.axes.iter().find(|a| a.name == name)
    }

    /// The time column as logged: the host stamps when there are any, else the true times.
    pub fn logged_time_s(&self) -> &[f64] {
        self.stamp_s.as_deref().unwrap_or(&self.time_s)
    }

    fn shape(&self) -> Shape {
        Shape {
            axes: if self.axes.is_empty() {
                vec!["x".to_string()]
            } else {
                self.axes.iter().map(|a| a.name.clone()).collect()
            },
            accels: self.accelerometers.iter().map(|a| a.name.clone()).collect(),
            temp_column: self.temp_column(),
            channels: self
                .channels
                .iter()
                .map(|c| (c.name.clone(), c.decimals))
                .collect(),
        }
    }

    /// The rate of axis `k` at sample `i`, °/h.
    fn rate(&self, k: usize, i: usize) -> f64 {
        if k == 0 {
            self.omega_dph[i]
        } else {
            self.axes[k].omega_dph[i]
        }
    }

    /// The run as the engine's [`Log`], the way ingest reads its CSV in driftlab's dialect:
    /// time (the host stamps, if any), the rate of the first axis and the sensor temperature as
    /// the calibration columns, then by name, in column order, the other axes' rates (°/h),
    /// the accelerometers (g), the chamber air `temp_chamber_c` and the run's
    /// [`channels`](SimRun::channels) (with their units, which the CSV header only carries as
    /// the last word of the name). The truth columns are not part of a log.
    pub fn to_log(&self, source: &str) -> Log {
        let mut log = Log::from_columns(
            source,
            self.logged_time_s().to_vec(),
            self.omega_dph.clone(),
            self.temp_c.clone(),
        );
        let shape = self.shape();
        let dialect = CsvDialect::driftlab();
        let names = Writer::new(&dialect).columns(&shape);
        let n_axes = shape.axes.len();
        let n_accel = shape.accels.len();
        let mut columns: Vec<(ColumnRole, String)> = Vec::with_capacity(names.len());
        for (i, name) in names.iter().enumerate() {
            let (role, unit, values) = if i == 0 {
                (ColumnRole::Time, "s", None)
            } else if i == 1 {
                (ColumnRole::Rate, "deg/h", None)
            } else if i <= n_axes {
                (
                    ColumnRole::Extra,
                    "deg/h",
                    Some(self.axes[i - 1].omega_dph.clone()),
                )
            } else if i <= n_axes + n_accel {
                let a = &self.accelerometers[i - 1 - n_axes];
                (ColumnRole::Extra, "g", Some(a.values_g.clone()))
            } else if i == n_axes + n_accel + 1 {
                (ColumnRole::Temperature, "°C", None)
            } else if i == n_axes + n_accel + 2 {
                (ColumnRole::Extra, "°C", Some(self.chamber_c.clone()))
            } else {
                let c = &self.channels[i - n_axes - n_accel - 3];
                (ColumnRole::Extra, c.unit.as_str(), Some(c.values.clone()))
            };
            if let Some(values) = values {
                log.extra.push(Channel {
                    name: name.clone(),
                    unit: unit.to_string(),
                    values,
                });
            }
            columns.push((role, unit.to_string()));
        }
        log.info.has_header = true;
        log.info.columns = names
            .into_iter()
            .zip(columns)
            .enumerate()
            .map(|(i, (name, (role, unit)))| ColumnInfo {
                index: i + 1,
                name,
                role,
                unit,
            })
            .collect();
        log
    }

    /// Writes the run as a test-stand CSV in driftlab's dialect, atomically: a `# driftlab
    /// simulate --profile NAME --seed N` comment (with `--noise-only` for a noise-only run and
    /// the run's other options), the header `time_s,omega_dph,temp_c,temp_chamber_c` (a laser
    /// gyro: `temp_base_c` for `temp_c`, then its [`channels`](SimRun::channels); several axes:
    /// `omega_x_dph,omega_y_dph,...`, then any accelerometers), then one row a sample (time
    /// exact, rate to 0.0001 °/h, temperatures to 0.001 °C, channels to their resolution).
    pub fn write_csv(&self, path: &Path) -> std::io::Result<()> {
        self.write_csv_as(path, &CsvDialect::driftlab())
    }

    /// Writes the run as [`write_csv`](SimRun::write_csv) does, in `dialect`.
    ///
    /// # Errors
    /// The write's, or `InvalidInput` for a dialect that [`CsvDialect::check`] refuses.
    pub fn write_csv_as(&self, path: &Path, dialect: &CsvDialect) -> std::io::Result<()> {
        dialect
            .check()
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidInput, e))?;
        crate::files::atomic::write_with(path, |w| self.write_csv_to(w, dialect))
    }

    fn write_csv_to(&self, w: &mut dyn Write, dialect: &CsvDialect) -> std::io::Result<()> {
        let shape = self.shape();
        let mut writer = Writer::new(dialect);
        writer.head(w, &shape, &self.command_as(dialect))?;
        let time = self.logged_time_s();
        let mut rates = vec![0.0; shape.axes.len()];
        let mut accel = vec![0.0; shape.accels.len()];
        let mut channels = vec![0.0; shape.channels.len()];
        for (i, &time_s) in time.iter().enumerate() {
            for (k, r) in rates.iter_mut().enumerate() {
                *r = self.rate(k, i);
            }
            for (a, v) in self.accelerometers.iter().zip(&mut accel) {
                *v = a.values_g[i];
            }
            for (c, v) in self.channels.iter().zip(&mut channels) {
                *v = c.values.get(i).copied().unwrap_or(f64::NAN);
            }
            let row = Row {
                time_s,
                rates_dph: &rates,
                accel_g: &accel,
                temp_c: self.temp_c[i],
                chamber_c: self.chamber_c[i],
                channels: &channels,
            };
            writer.row(w, &row, &shape)?;
        }
        Ok(())
    }
}
