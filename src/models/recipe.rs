//! Every choice an engineer makes for a calibration, apart from what gets fitted.
//!
//! A recipe is plain data: filters and derivative step in seconds, dead-bands, plateaus (found
//! automatically or given as time ranges) and the approximation of each coefficient. Fitting is
//! a pure function of (log, recipe), so the same recipe file gives the same calibration from the
//! command line, the workbench or a batch script.

use crate::error::Invalid;
use crate::models::approx::{ApproxKind, ApproxSpec};
pub use crate::signal::plateau::PlateauChoice;
use crate::signal::plateau::PlateauRange;
use serde::{Deserialize, Serialize};

/// All settings of a Vakhrameev calibration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Recipe {
    /// Identifier of the gyro (serial number), copied into the calibration file.
    pub gyro_id: String,
    /// Centred moving average applied to Ω before the pointwise coefficients and in the
    /// figures of merit, s (the paper: 100 recording intervals).
    pub filter_s: f64,
    /// Causal moving average applied to T before differentiating, s.
    pub temp_smoothing_s: f64,
    /// Step H of the backward derivative, s.
    pub step_h_s: f64,
    /// |Ṫ| below which a point is left out of the K1 fits, °C/s; `None`: a fifth of the
    /// 95th percentile of |Ṫ| outside plateaus.
    pub deadband_tdot: Option<f64>,
    /// |T̈| below which a point is left out of the K2 fits, °C/s²; `None`: a fifth of the
    /// 95th percentile of |T̈| outside plateaus.
    pub deadband_tddot: Option<f64>,
    /// How the plateaus that define K0(T) are chosen.
    pub plateaus: PlateauChoice,
    /// Approximation of K0 over T. A pwl or spline K0's knot count is a maximum: its knots
    /// not placed by hand go to the plateaus' distinct temperatures
    /// (`vakhrameev::knots_at_temperatures`).
    pub k0: ApproxSpec,
    /// Approximation of K1+ over Ṫ (thermal acceleration, Ṫ·T̈ > 0).
    pub k1_plus: ApproxSpec,
    /// Approximation of K1− over Ṫ (thermal deceleration, Ṫ·T̈ < 0).
    pub k1_minus: ApproxSpec,
    /// Approximation of K2+ over T̈.
    pub k2_plus: ApproxSpec,
    /// Approximation of K2− over T̈.
    pub k2_minus: ApproxSpec,
    /// How the pointwise coefficients are weighed in the least-squares fits.
    pub weighting: Weighting,
    /// Extra passes after the paper's K1-then-K2 fit: each refits K1 with the fitted K2 term
    /// taken out of Ω, then K2 with the new K1 (0: the paper's method exactly).
    pub refinements: usize,
}

/// Weighing of the pointwise coefficients K1 = r/Ṫ and K2 = r/T̈ in their fits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Weighting {
    /// Every ratio counts alike, as the paper fits them. Ratios at small Ṫ (T̈) carry the
    /// noise of Ω divided by a small number and can dominate the fit.
    Ratio,
    /// Each ratio weighted by its denominator squared: the fit then minimises the error of the
    /// predicted drift itself, K·Ṫ against Ω − K0, which is what the correction is judged on.
    Drift,
}

impl Default for Recipe {
    /// Defaults that give usable Ṫ and T̈ on a 1 Hz log with 0.001 °C resolution: T smoothed over
    /// 60 s and differentiated with H = 30 s keeps the quantisation noise of T̈ near 1e-6 °C/s²,
    /// well below the ~3e-5 °C/s² of a 1 °C/min ramp starting or stopping over ten minutes.
    fn default() -> Self {
        Recipe {
            gyro_id: String::new(),
            filter_s: 100.0,
            temp_smoothing_s: 60.0,
            step_h_s: 30.0,
            deadband_tdot: None,
            deadband_tddot: None,
            plateaus: PlateauChoice::default(),
            k0: ApproxSpec::of(ApproxKind::Parabolic),
            k1_plus: ApproxSpec::of(ApproxKind::Linear),
            k1_minus: ApproxSpec::of(ApproxKind::Linear),
            k2_plus: ApproxSpec::of(ApproxKind::Linear),
            k2_minus: ApproxSpec::of(ApproxKind::Linear),
            weighting: Weighting::Drift,
            refinements: 2,
        }
    }
}

/// The longest filter, T smoothing or derivative step a recipe may ask for, s: about eleven
/// and a half days, longer than any chamber run. A window of 10⁹ s is a typing error, and a
/// fit would average the whole log into one value with it.
pub const MAX_WINDOW_S: f64 = 1e6;

/// The longest gyro identifier (serial number) a recipe may hold, characters.
pub const MAX_GYRO_ID_CHARS: usize = 200;

/// The shortest filter, T smoothing, derivative step or window a setting may hold, s: no gyro
/// log is sampled faster than 1 MHz, so a shorter one (1e-300 s) is a typing slip.
pub const MIN_WINDOW_S: f64 = 1e-6;

/// A recipe whose numbers have been checked ([`Recipe::validate`]): what the model layer's fits
/// take, so that a recipe is checked once, where a face makes it from options or a file, and
/// every stage after trusts it. Read it as a [`Recipe`] (it dereferences to one); change it by
/// taking the recipe out ([`CheckedRecipe::into_recipe`]) and checking it again.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedRecipe(Recipe);

impl CheckedRecipe {
    /// The recipe.
    pub fn recipe(&self) -> &Recipe {
        &self.0
    }

    /// The recipe, to change and check again.
    pub fn into_recipe(self) -> Recipe {
        self.0
    }
}

impl Default for CheckedRecipe {
    /// The default recipe, whose numbers pass the checks (a test holds it).
    fn default() -> Self {
        CheckedRecipe(Recipe::default())
    }
}

impl std::ops::Deref for CheckedRecipe {
    type Target = Recipe;
    fn deref(&self) -> &Recipe {
        &self.0
    }
}

impl TryFrom<Recipe> for CheckedRecipe {
    type Error = Invalid;
    fn try_from(r: Recipe) -> Result<CheckedRecipe, Invalid> {
        r.checked()
    }
}

impl Recipe {
    /// This recipe as one axis's of a unit whose recipe is `unit`: the axes share the log's
    /// temperature stages (T smoothing, derivative step, plateaus) and the unit's gyro id, so
    /// those are the unit's; the rest (Ω filter, approximations, knots, dead-bands,
    /// weighting, refinements) stays this recipe's. Returns the names of the fields this
    /// recipe set otherwise, with the value it set, for the face to say they were not used.
    pub fn as_axis_of(mut self, unit: &Recipe) -> (Recipe, Vec<String>) {
        let mut dropped = Vec::new();
        if self.temp_smoothing_s != unit.temp_smoothing_s {
            dropped.push(format!(
                "temp_smoothing_s {}",
                crate::number::readable(self.temp_smoothing_s)
            ));
        }
        if self.step_h_s != unit.step_h_s {
            dropped.push(format!(
                "step_h_s {}",
                crate::number::readable(self.step_h_s)
            ));
        }
        if self.plateaus != unit.plateaus {
            dropped.push("plateaus".to_string());
        }
        if self.gyro_id != unit.gyro_id {
            dropped.push(format!("gyro_id {:?}", self.gyro_id));
        }
        self.temp_smoothing_s = unit.temp_smoothing_s;
        self.step_h_s = unit.step_h_s;
        self.plateaus = unit.plateaus.clone();
        self.gyro_id = unit.gyro_id.clone();
        (self, dropped)
    }

    /// The recipe checked ([`Recipe::validate`]) and carried as such.
    ///
    /// # Errors
    /// The first setting that fails, named.
    pub fn checked(self) -> Result<CheckedRecipe, Invalid> {
        self.validate()?;
        Ok(CheckedRecipe(self))
    }

    /// Checks the numbers once, so fitting can trust them; the message names the setting.
    pub fn validate(&self) -> Result<(), Invalid> {
        let positive = |name: &str, v: f64| {
            if !(v.is_finite() && v > 0.0) {
                Err(Invalid::new(
                    name,
                    format!(
                        "must be a positive number of seconds, got {}",
                        crate::number::readable(v)
                    ),
                ))
            } else if v < MIN_WINDOW_S {
                Err(too_short(name, v))
            } else if v > MAX_WINDOW_S {
                Err(Invalid::new(
                    name,
                    format!(
                        "{} s is longer than any chamber run: at most {} s (11.6 days)",
                        crate::number::readable(v),
                        crate::number::readable(MAX_WINDOW_S)
                    ),
                ))
            } else {
                Ok(())
            }
        };
        // A serial number is copied into every output and printed on the terminal: no
        // character in it may steer a terminal, start a line or reorder text, and two that
        // print alike must be one (no invisible or blank character, no space around it).
        if let Some(why) = crate::text::id_fault(&self.gyro_id) {
            return Err(Invalid::new(
                "gyro_id",
                format!("{why}: a serial number is printable text, with no space around it"),
            ));
        }
        if self.gyro_id.chars().count() > MAX_GYRO_ID_CHARS {
            return Err(Invalid::new(
                "gyro_id",
                format!(
                    "is {} characters long: a serial number has at most {MAX_GYRO_ID_CHARS}",
                    self.gyro_id.chars().count()
                ),
            ));
        }
        positive("filter_s", self.filter_s)?;
        positive("temp_smoothing_s", self.temp_smoothing_s)?;
        positive("step_h_s", self.step_h_s)?;
        // A dead-band wider than any chamber's rates leaves both sets empty: K1± and K2± come
        // out as zeros over nothing, and the figures' axes reach the dead-band.
        for (name, v, most, unit) in [
            (
                "deadband_tdot",
                self.deadband_tdot,
                MAX_DEADBAND_TDOT,
                "°C/s",
            ),
            (
                "deadband_tddot",
                self.deadband_tddot,
                MAX_DEADBAND_TDDOT,
                "°C/s²",
            ),
        ] {
            if let Some(v) = v
                && !(v.is_finite() && (0.0..=most).contains(&v))
            {
                return Err(Invalid::new(
                    name,
                    format!(
                        "must be a number from 0 to {} {unit} (no thermal chamber moves \
                         faster), got {}",
                        crate::number::readable(most),
                        crate::number::readable(v)
                    ),
                ));
            }
        }
        if self.refinements > 20 {
            return Err(Invalid::new(
                "refinements",
                format!("must be at most 20, got {}", self.refinements),
            ));
        }
        // Checked on every curve, with knots or not: a number no curve could take is a slip
        // wherever it stands.
        for (k, (name, spec)) in self.specs().into_iter().enumerate() {
            if !(2..=64).contains(&spec.knots) {
                return Err(Invalid::new(
                    format!("{name}.knots"),
                    format!("must be between 2 and 64, got {}", spec.knots),
                ));
            }
            check_hand_knots(name, spec)?;
            check_hand_reach(k, name, spec)?;
        }
        match &self.plateaus {
            PlateauChoice::Auto(o) => o.validate()?,
            PlateauChoice::Manual { ranges } => {
                if ranges.len() > MAX_MANUAL_PLATEAUS {
                    return Err(Invalid::new(
                        "plateaus.ranges",
                        format!(
                            "{} plateaus: a chamber program holds tens, and a calibration of \
                             more than {MAX_MANUAL_PLATEAUS} could not be saved and read back",
                            ranges.len()
                        ),
                    ));
                }
                for r in ranges {
                    if !(r.start_s.is_finite() && r.end_s.is_finite() && r.start_s < r.end_s) {
                        return Err(Invalid::new(
                            "plateaus.ranges",
                            format!("plateau {} must have a start before its end", show_range(r)),
                        ));
                    }
                }
                check_disjoint(ranges)?;
            }
        }
        Ok(())
    }

    /// Checks the recipe's windows against the log it is to be fitted on: a filter, T
    /// smoothing or derivative step longer than the whole log leaves nothing to fit.
    ///
    /// # Errors
    /// The setting, with its value and the log's span.
    pub fn check_against(&self, log: &crate::log::Log) -> Result<(), Invalid> {
        let span = crate::judge::options::log_span_s(log);
        for (name, v) in [
            ("filter_s", self.filter_s),
            ("temp_smoothing_s", self.temp_smoothing_s),
            ("step_h_s", self.step_h_s),
        ] {
            if v > span {
                return Err(Invalid::new(
                    name,
                    format!(
                        "{} s is longer than the log {} ({} s)",
                        crate::number::readable(v),
                        log.source,
                        crate::number::readable(span)
                    ),
                ));
            }
        }
        check_history(self.temp_smoothing_s, self.step_h_s, log)
    }

    /// The filter, T smoothing and derivative step that are shorter than `dt_s`, the sampling
    /// interval of the log they are used on: each is taken as one sample, which the
    /// engineer should hear (a burst log's means 300 s apart take the default 100-s filter
    /// as none).
    pub fn one_sample_windows(&self, dt_s: f64, log_name: &str) -> Vec<Invalid> {
        [
            ("filter_s", self.filter_s),
            ("temp_smoothing_s", self.temp_smoothing_s),
            ("step_h_s", self.step_h_s),
        ]
        .into_iter()
        .filter_map(|(name, v)| crate::judge::options::one_sample(name, v, dt_s, log_name))
        .collect()
    }

    /// The plateaus given by hand that reach past either end of `log` (a typing slip, a
    /// time in ms, a range saved from a longer run): each is taken only over the samples it
    /// covers, and its length as typed would hide how fast T moves over what it covers, so
    /// the engineer hears of each, named with the log's span.
    pub fn plateaus_beyond(&self, log: &crate::log::Log) -> Vec<Invalid> {
        let (Some(&first), Some(&last)) = (log.time_s.first(), log.time_s.last()) else {
            return Vec::new();
        };
        let PlateauChoice::Manual { ranges } = &self.plateaus else {
            return Vec::new();
        };
        let slack = log.nominal_dt_s();
        let r = crate::number::readable;
        ranges
            .iter()
            .filter(|p| p.start_s < first - slack || p.end_s > last + slack)
            .filter(|p| p.end_s >= first && p.start_s <= last)
            .take(8)
            .map(|p| {
                Invalid::new(
                    "plateaus",
                    format!(
                        "plateau {}:{} s reaches past the log {} ({} .. {} s): it is taken \
                         over {} .. {} s; check the range",
                        r(p.start_s),
                        r(p.end_s),
                        log.source,
                        r(first),
                        r(last),
                        r(p.start_s.max(first)),
                        r(p.end_s.min(last))
                    ),
                )
            })
            .collect()
    }

    /// The five approximation choices with their names.
    pub fn specs(&self) -> [(&'static str, &ApproxSpec); 5] {
        [
            ("k0", &self.k0),
            ("k1_plus", &self.k1_plus),
            ("k1_minus", &self.k1_minus),
            ("k2_plus", &self.k2_plus),
            ("k2_minus", &self.k2_minus),
        ]
    }

    /// This recipe without any knot placed or set by hand (each curve's knots fitted and
    /// equally spaced again): what carries over to another log, whose rates the hand-placed
    /// knots were not made for.
    pub fn without_hand_knots(mut self) -> Recipe {
        for spec in [
            &mut self.k0,
            &mut self.k1_plus,
            &mut self.k1_minus,
            &mut self.k2_plus,
            &mut self.k2_minus,
        ] {
            *spec = spec.without_hand_knots();
        }
        self
    }
}

/// Refuses knots placed or set by hand that no curve can take ([`ApproxSpec::check_knots`]:
/// the field named `k1_plus.at` or `k1_plus.values`), and hand-set values beyond the largest
/// rate a gyro log may plausibly hold (`k1_plus.values[2]`), as the workbench's sessions
/// always refused them.
fn check_hand_knots(name: &str, spec: &ApproxSpec) -> Result<(), Invalid> {
    use crate::log::mapping_check::MAX_PLAUSIBLE_RATE_DPH;
    use crate::number::readable;
    spec.check_knots()
        .map_err(|e| Invalid::new(format!("{name}.{}", e.field()), e.to_string()))?;
    if let Some((j, v)) = spec
        .values
        .iter()
        .flatten()
        .enumerate()
        .find(|(_, v)| v.abs() > MAX_PLAUSIBLE_RATE_DPH)
    {
        return Err(Invalid::new(
            format!("{name}.values[{j}]"),
            format!(
                "{}: a knot value is a finite number of at most {} in magnitude (10⁴ °/s, the \
                 largest rate a gyro log may plausibly hold)",
                readable(*v),
                readable(MAX_PLAUSIBLE_RATE_DPH)
            ),
        ));
    }
    Ok(())
}

/// Refuses knots placed by hand beyond what a chamber takes the curve's argument to
/// ([`CHAMBER_REACH`](crate::models::vakhrameev::CHAMBER_REACH): the temperatures a log may
/// hold for K0, 30 °C/min for K1±, that rate reversed in a minute for K2±): no sample of a log
/// lies there, and a K0 knot at 1e300 °C made a calibration that `calibrate` wrote and
/// `report` could not draw. `k` is the curve's place in [`Recipe::specs`].
fn check_hand_reach(k: usize, name: &str, spec: &ApproxSpec) -> Result<(), Invalid> {
    let (lo, hi) = crate::models::vakhrameev::CHAMBER_REACH[k];
    let unit = ["°C", "°C/s", "°C/s²"][k.div_ceil(2)];
    let Some((j, x)) = spec
        .at
        .iter()
        .flatten()
        .enumerate()
        .find(|(_, x)| !(lo..=hi).contains(*x))
    else {
        return Ok(());
    };
    let readable = crate::number::readable;
    Err(Invalid::new(
        format!("{name}.at[{j}]"),
        format!(
            "{} {unit} lies beyond what a chamber reaches ({} … {} {unit}): no sample of a log \
             is there for the knot to be fitted to",
            readable(*x),
            readable(lo),
            readable(hi)
        ),
    ))
}

/// Refuses a T smoothing and derivative step whose history (the smoothing and four steps,
/// before a sample has both rates of T) is more than half of `log`: most of its samples would
/// be warm-up, corrected by K0(T) alone, and judged on the few left (a 30000-s smoothing on a
/// 40200-s log left a quarter, all beyond the calibrated ranges). Every model that reads
/// rates of T takes it with the same words; the field named is the larger part.
///
/// # Errors
/// An [`Invalid`] naming `temp_smoothing_s` or `step_h_s`.
pub fn check_history(
    temp_smoothing_s: f64,
    step_h_s: f64,
    log: &crate::log::Log,
) -> Result<(), Invalid> {
    let span = crate::judge::options::log_span_s(log);
    let history = temp_smoothing_s + 4.0 * step_h_s;
    if history > 0.5 * span {
        let (field, v) = if temp_smoothing_s >= 4.0 * step_h_s {
            ("temp_smoothing_s", temp_smoothing_s)
        } else {
            ("step_h_s", step_h_s)
        };
        return Err(Invalid::new(
            field,
            format!(
                "{} s makes the rates of T need {} s of history (the T smoothing and four \
                 derivative steps), more than half of the log {} ({} s): most of it would be \
                 warm-up",
                crate::number::readable(v),
                crate::number::readable(history),
                log.source,
                crate::number::readable(span)
            ),
        ));
    }
    Ok(())
}

/// The refusal of a window shorter than [`MIN_WINDOW_S`], named `field`.
pub(crate) fn too_short(field: &str, v: f64) -> Invalid {
    Invalid::new(
        field,
        format!(
            "{} s is shorter than any sampling interval: at least {} s",
            crate::number::readable(v),
            crate::number::readable(MIN_WINDOW_S)
        ),
    )
}

/// A plateau range as the command line and a recipe write it, `START:END` in seconds.
/// The widest dead-band on Ṫ, °C/s: 1 °C/s is 60 °C a minute, beyond any thermal chamber, so a
/// wider one leaves the K1 sets empty.
pub const MAX_DEADBAND_TDOT: f64 = 1.0;

/// The widest dead-band on T̈, °C/s².
pub const MAX_DEADBAND_TDDOT: f64 = 1.0;

/// The most plateaus a recipe may give by hand: a chamber program holds tens; each is a point
/// of K0 and a line of the calibration file, whose size is bounded (16 MiB) so that every
/// calibration written can be read back.
pub const MAX_MANUAL_PLATEAUS: usize = 4096;

fn show_range(r: &PlateauRange) -> String {
    format!(
        "{}:{}",
        crate::number::readable(r.start_s),
        crate::number::readable(r.end_s)
    )
}

/// Refuses two manual plateaus that share a sample: the same range given twice would count
/// as two K0 points of one hold (a parabola through three temperatures reported as a fit of
/// four, its warning of a curve through every point lost), and ranges that overlap average
/// the samples they share twice. The ranges are inclusive, so touching ones share the sample
/// at their common end. Both are named, in the order given.
fn check_disjoint(ranges: &[PlateauRange]) -> Result<(), Invalid> {
    let mut order: Vec<usize> = (0..ranges.len()).collect();
    order.sort_by(|&a, &b| {
        ranges[a]
            .start_s
            .total_cmp(&ranges[b].start_s)
            .then(a.cmp(&b))
    });
    // Sorted by start, a range overlaps an earlier one exactly when it starts at or before
    // the latest end so far: that range is the one to name beside it.
    let mut reach: Option<usize> = None;
    for &k in &order {
        if let Some(j) = reach
            && ranges[k].start_s <= ranges[j].end_s
        {
            let (first, second) = (j.min(k), j.max(k));
            let (a, b) = (&ranges[first], &ranges[second]);
            let reason = if a == b {
                format!(
                    "plateau {} is given twice (numbers {} and {}): one hold would count as \
                     two K0 points; give each hold once",
                    show_range(a),
                    first + 1,
                    second + 1
                )
            } else {
                format!(
                    "plateaus {} (number {}) and {} (number {}) overlap: the samples they \
                     share would count in two K0 points; give each hold once, as one range",
                    show_range(a),
                    first + 1,
                    show_range(b),
                    second + 1
                )
            };
            return Err(Invalid::new("plateaus.ranges", reason));
        }
        if reach.is_none_or(|j| ranges[k].end_s > ranges[j].end_s) {
            reach = Some(k);
        }
    }
    Ok(())
}
