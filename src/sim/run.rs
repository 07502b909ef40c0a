//! One run from profile to samples: the plan for the logging rate, the samples handed out one
//! at a time (so that a long fast log is written without being held), the logger's choice of
//! samples and stamps, and the collection into a [`SimRun`].

use std::convert::Infallible;

use crate::error::Invalid;

use super::axes::AccelParams;
use super::dialect::Shape;
use super::logging::{Logging, Stamper};
use super::profile::Profile;
use super::{LaserTruth, SimAccel, SimAxis, SimChannel, SimRun, fog, laser};

/// Where a run's recorded samples go, each with its host stamp (`None` without jitter).
pub(crate) type Sink<'a, E> = dyn FnMut(&Sample, Option<f64>) -> Result<(), E> + 'a;

/// Most samples a run may log.
const MAX_SAMPLES: f64 = 1e9;

/// One sample of every quantity of a run, true and logged, in engine units.
#[derive(Debug, Clone, Default)]
pub(crate) struct Sample {
    /// True sampling instant, s, rounded to 1 ns.
    pub(crate) time_s: f64,
    pub(crate) chamber_c: f64,
    /// The calibration temperature sensor's reading, °C.
    pub(crate) temp_c: f64,
    pub(crate) housing_c: f64,
    pub(crate) coil_mean_c: f64,
    pub(crate) coil_inner_c: f64,
    /// Fibre-weighted radial gradient and difference of heating rates (FOG only).
    pub(crate) coil_gradient_c: f64,
    pub(crate) coil_rate_gradient_c_per_s: f64,
    /// Every gyro axis (one for a single gyro and the laser gyro).
    pub(crate) axes: Vec<AxisSample>,
    pub(crate) accel: Vec<AccelSample>,
    /// Logged channels after `temp_chamber_c` (laser gyro).
    pub(crate) channels: Vec<f64>,
    /// Truth of a laser gyro (unused for a FOG).
    pub(crate) laser: LaserSample,
}

/// One axis of one sample, °/h.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct AxisSample {
    pub(crate) omega: f64,
    pub(crate) thermal: f64,
    pub(crate) noise: f64,
    /// The parts of a FOG axis's drift: K0 at the coil temperature, Shupe and stress terms
    /// (with the heating/cooling asymmetry).
    pub(crate) static_dph: f64,
    pub(crate) shupe_dph: f64,
    pub(crate) stress_dph: f64,
}

impl AxisSample {
    /// Sets the noise of a sample whose drift is set, and so its output.
    pub(crate) fn set_noise(&mut self, noise: f64) {
        self.noise = noise;
        self.omega = self.thermal + noise;
    }
}

/// One accelerometer of one sample, g.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct AccelSample {
    pub(crate) value_g: f64,
    pub(crate) true_g: f64,
}

impl AccelSample {
    /// Sets the logged value of a sample whose truth is set, with white noise `white`.
    pub(crate) fn set_noise(&mut self, white: f64, a: &AccelParams) {
        self.value_g = super::noise::quantise(self.true_g + white, a.resolution_g);
    }
}

/// The truth of a laser gyro at one sample.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LaserSample {
    pub(crate) base_c: f64,
    pub(crate) laser_power_mw: f64,
    pub(crate) piezo_v: f64,
    pub(crate) dither_amp_arcsec: f64,
    pub(crate) self_heating_dph: f64,
}

/// How a run is integrated for its logging rate.
#[derive(Debug, Clone)]
pub(crate) struct Plan {
    /// The profile the physics runs: the given one, or it at the logging rate when that is not
    /// a whole multiple of the profile's.
    pub(crate) profile: Profile,
    /// Samples logged per sample of `profile` (1, or the multiple).
    pub(crate) fine: usize,
    /// Logging rate, Hz.
    pub(crate) rate_hz: f64,
}

impl Plan {
    /// Checks `profile` and `logging` and plans the run, with a sentence naming what is wrong.
    pub(crate) fn new(profile: &Profile, logging: &Logging) -> Result<Plan, Invalid> {
        profile.check()?;
        let base = profile.sample_rate_hz;
        let rate = logging.rate_hz.unwrap_or(base);
        logging.check(rate)?;
        let ratio = rate / base;
        let whole = ratio.round();
        let plan = if whole >= 1.0 && (ratio - whole).abs() <= 1e-9 * ratio {
            Plan {
                profile: profile.clone(),
                fine: whole as usize,
                rate_hz: rate,
            }
        } else {
            let mut p = profile.clone();
            p.sample_rate_hz = rate;
            p.check().map_err(|e| {
                // The profile's rate is the logging rate here: the option that set it is named.
                let reason = if e.field == "sample_rate_hz" {
                    e.reason
                } else {
                    e.to_string()
                };
                Invalid::new(
                    format!("--rate-hz {}", crate::number::readable(rate)),
                    reason,
                )
            })?;
            Plan {
                profile: p,
                fine: 1,
                rate_hz: rate,
            }
        };
        let samples = (plan.profile.sample_count() - 1) as f64 * plan.fine as f64 + 1.0;
        if samples > MAX_SAMPLES {
            return Err(Invalid::new(
                format!("--rate-hz {}", crate::number::readable(rate)),
                format!("the run would record {samples:.0} samples; more than 10⁹ is refused"),
            ));
        }
        logging.check_within((plan.samples() - 1) as f64 / plan.rate_hz)?;
        Ok(plan)
    }

    /// Refuses a run whose logger recorded fewer than two of its samples: bursts shorter than
    /// a sampling step, or gaps over the whole program, leave a log no command can read (one
    /// sample has no step), as a rate too slow for two samples is refused before the run.
    pub(crate) fn check_recorded(&self, logging: &Logging, recorded: usize) -> Result<(), Invalid> {
        if recorded >= 2 {
            return Ok(());
        }
        Err(Invalid::new(
            logging.leaving_out(),
            format!(
                "the logger would record {recorded} of the run's {} samples ({} s at {} Hz): \
                 a log needs at least two",
                self.samples(),
                crate::number::readable(self.profile.duration_s()),
                crate::number::readable(self.rate_hz)
            ),
        ))
    }

    /// Samples the run takes before the logger leaves any out.
    pub(crate) fn samples(&self) -> usize {
        (self.profile.sample_count() - 1) * self.fine + 1
    }

    /// What the run writes besides time, rates and temperatures.
    pub(crate) fn shape(&self) -> Shape {
        let p = &self.profile;
        Shape {
            axes: p.unit_axes().into_iter().map(|a| a.name).collect(),
            accels: p.accelerometers.iter().map(|a| a.name.clone()).collect(),
            temp_column: if p.laser.is_some() {
                "temp_base_c"
            } else {
                "temp_c"
            },
            channels: match &p.laser {
                Some(l) => laser::channel_specs(&p.gyro, l)
                    .into_iter()
                    .map(|(name, _, decimals)| (name.to_string(), decimals))
                    .collect(),
                None => Vec::new(),
            },
        }
    }

    /// Runs the plan with seed `seed`, handing every sample the logger records to `sink` with
    /// its host stamp (`None` without jitter).
    pub(crate) fn drive<E>(
        &self,
        seed: u64,
        logging: &Logging,
        progress: &dyn Fn(f64),
        sink: &mut Sink<'_, E>,
    ) -> Result<(), E> {
        let mut stamper = logging.jitter.as_ref().map(|j| Stamper::new(j, seed));
        let mut logged = |s: &Sample| {
            if !logging.records(s.time_s) {
                return Ok(());
            }
            let stamp = stamper.as_mut().map(|st| st.stamp(s.time_s));
            sink(s, stamp)
        };
        match &self.profile.laser {
            Some(l) => laser::run(&self.profile, l, self.fine, seed, progress, &mut logged),
            None => fog::run(&self.profile, self.fine, seed, progress, &mut logged),
        }
    }

    /// Runs the plan and collects every recorded sample into a [`SimRun`].
    pub(crate) fn collect(&self, seed: u64, logging: &Logging, progress: &dyn Fn(f64)) -> SimRun {
        let p = &self.profile;
        let mut run = SimRun {
            profile: p.name.clone(),
            seed,
            sample_rate_hz: self.rate_hz,
            logging: logging.clone(),
            stamp_s: logging.jitter.as_ref().map(|_| Vec::new()),
            ..SimRun::default()
        };
        let fog = p.laser.is_none();
        if fog {
            run.axes = p
                .unit_axes()
                .into_iter()
                .map(|a| SimAxis {
                    name: a.name,
                    ..SimAxis::default()
                })
                .collect();
            run.accelerometers = p
                .accelerometers
                .iter()
                .map(|a| SimAccel {
                    name: a.name.clone(),
                    ..SimAccel::default()
                })
                .collect();
        } else {
            run.laser = Some(LaserTruth::default());
        }
        if let Some(l) = &p.laser {
            run.channels = laser::channel_specs(&p.gyro, l)
                .into_iter()
                .map(|(name, unit, decimals)| SimChannel::new(name, unit, decimals, Vec::new()))
                .collect();
        }
        // Every sample is kept unless the logger leaves some out: reserve for all of them.
        if logging.gaps.is_empty() && logging.bursts.is_none() {
            run.reserve(self.samples());
        }
        let mut push = |s: &Sample, stamp: Option<f64>| -> Result<(), Infallible> {
            run.push(s, stamp);
            Ok(())
        };
        match self.drive(seed, logging, progress, &mut push) {
            Ok(()) => {}
            Err(never) => match never {},
        }
        run
    }
}

impl SimRun {
    fn reserve(&mut self, n: usize) {
        for col in [
            &mut self.time_s,
            &mut self.chamber_c,
            &mut self.temp_c,
            &mut self.omega_dph,
            &mut self.thermal_dph,
            &mut self.noise_dph,
            &mut self.housing_c,
            &mut self.coil_mean_c,
            &mut self.coil_inner_c,
        ] {
            col.reserve_exact(n);
        }
        if let Some(s) = &mut self.stamp_s {
            s.reserve_exact(n);
        }
        if self.laser.is_none() {
            self.coil_gradient_c.reserve_exact(n);
            self.coil_rate_gradient_c_per_s.reserve_exact(n);
        }
        for a in &mut self.axes {
            for col in [
                &mut a.omega_dph,
                &mut a.thermal_dph,
                &mut a.noise_dph,
                &mut a.static_dph,
                &mut a.shupe_dph,
                &mut a.stress_dph,
            ] {
                col.reserve_exact(n);
            }
        }
        for a in &mut self.accelerometers {
            a.values_g.reserve_exact(n);
            a.true_g.reserve_exact(n);
        }
        for c in &mut self.channels {
            c.values.reserve_exact(n);
        }
        if let Some(l) = &mut self.laser {
            for col in [
                &mut l.base_c,
                &mut l.laser_power_mw,
                &mut l.piezo_v,
                &mut l.dither_amp_arcsec,
                &mut l.self_heating_dph,
            ] {
                col.reserve_exact(n);
            }
        }
    }

    fn push(&mut self, s: &Sample, stamp: Option<f64>) {
        let first = s.axes[0];
        self.time_s.push(s.time_s);
        self.chamber_c.push(s.chamber_c);
        self.temp_c.push(s.temp_c);
        self.omega_dph.push(first.omega);
        self.thermal_dph.push(first.thermal);
        self.noise_dph.push(first.noise);
        self.housing_c.push(s.housing_c);
        self.coil_mean_c.push(s.coil_mean_c);
        self.coil_inner_c.push(s.coil_inner_c);
        if let (Some(stamps), Some(t)) = (&mut self.stamp_s, stamp) {
            stamps.push(t);
        }
        for (a, v) in self.axes.iter_mut().zip(&s.axes) {
            a.omega_dph.push(v.omega);
            a.thermal_dph.push(v.thermal);
            a.noise_dph.push(v.noise);
            a.static_dph.push(v.static_dph);
            a.shupe_dph.push(v.shupe_dph);
            a.stress_dph.push(v.stress_dph);
        }
        for (a, v) in self.accelerometers.iter_mut().zip(&s.accel) {
            a.values_g.push(v.value_g);
            a.true_g.push(v.true_g);
        }
        for (c, &v) in self.channels.iter_mut().zip(&s.channels) {
            c.values.push(v);
        }
        match &mut self.laser {
            Some(l) => {
                let v = &s.laser;
                l.base_c.push(v.base_c);
                l.laser_power_mw.push(v.laser_power_mw);
                l.piezo_v.push(v.piezo_v);
                l.dither_amp_arcsec.push(v.dither_amp_arcsec);
                l.self_heating_dph.push(v.self_heating_dph);
            }
            None => {
                self.coil_gradient_c.push(s.coil_gradient_c);
                self.coil_rate_gradient_c_per_s
                    .push(s.coil_rate_gradient_c_per_s);
            }
        }
    }
}
