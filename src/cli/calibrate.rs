//! `driftlab calibrate`: fit a calibration (any model) to a log and save it: the log's one
//! gyro axis, or every axis of a unit (those `--axes` or a repeated `--rate-col` choose)
//! fitted with one read and one temperature processing into one file
//! ([`models::calibrate`]).

use super::calibrate_print;
use super::common::{self, CliError, LogArgs};
use driftlab::Log;
use driftlab::files::atomic::Batch;
use driftlab::files::calibration;
use driftlab::models::approx::{ApproxKind, ApproxSpec};
use driftlab::models::campaign::UnitPlan;
use driftlab::models::recipe::{CheckedRecipe, PlateauChoice, Recipe};
use driftlab::models::regression::{DelaySpec, FitSamples, LagSpec, RegressionSpec, terms};
use driftlab::models::{self, AxisPlan, ModelChoice, Preset};
use driftlab::signal::plateau::PlateauRange;
use std::path::{Path, PathBuf};

/// Arguments of `calibrate`. Options given here override those of `--recipe`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The chamber log to calibrate on; several logs are the runs of one campaign (runs of
    /// one gyro, fitted together: each run smoothed, differentiated and its plateaus found on
    /// its own; K0 from every run's plateaus, K1 and K2 from every run's ramps).
    #[arg(required = true, num_args = 1..)]
    pub log: Vec<PathBuf>,
    /// With several runs: estimate each run's turn-on offset (a constant of the run that no
    /// temperature explains), keep it out of K0, and report it.
    #[arg(long)]
    pub per_run_offset: bool,
    /// With several runs: plateaus share a temperature within this, degC (repeatability,
    /// hysteresis, and the runs that tie the turn-on offsets together). Default 1.
    #[arg(long, value_name = "DEGC")]
    pub temp_tolerance: Option<f64>,
    /// Where to write the calibration (JSON).
    #[arg(long, short)]
    pub out: PathBuf,
    /// Take every setting from a recipe file (JSON), or from the recipe inside a calibration file
    /// (of one axis: a single-axis calibration, or a unit's of one axis).
    #[arg(long, value_name = "FILE")]
    pub recipe: Option<PathBuf>,
    /// With --recipe naming a unit's calibration (of one axis or several), the axis of it whose
    /// recipe to take (its knots placed and set by hand among its choices): a log of one axis
    /// calibrated as that axis was.
    #[arg(long, value_name = "AXIS", requires = "recipe")]
    pub recipe_axis: Option<String>,
    /// Also write the recipe that was used (JSON), to re-run or edit later. A recipe holds
    /// Vakhrameev's settings and no model: refused with --model or --axis-model of another.
    #[arg(long, value_name = "FILE")]
    pub save_recipe: Option<PathBuf>,
    /// Gyro identifier (serial number) stored in the calibration.
    #[arg(long)]
    pub gyro_id: Option<String>,
    /// The model to fit (default vakhrameev): a preset (ieee952, yan-cross, yan-delayed,
    /// sukhanov, poly-t, pwl-t, coil-lag), a flight controller's form (px4, ardupilot), a
    /// polynomial in T of order N (poly-tN, N 1 to 9), a firmware script's own fit
    /// (px4-script, ardupilot-script) or `custom` with --terms. See `driftlab compare`.
    /// --filter, --smooth, --step-h and --plateau reach every model; the K approximations
    /// and dead-bands are Vakhrameev's and are refused for another model.
    #[arg(long, value_name = "NAME")]
    pub model: Option<String>,
    /// Terms of a custom model, comma-separated (see `driftlab compare --help`).
    #[arg(long, value_name = "TERMS")]
    pub terms: Option<String>,
    /// Delay of a custom model's temperature channels: none, SECONDS, auto or bands:N
    /// (default none).
    #[arg(long, value_name = "DELAY")]
    pub delay: Option<DelaySpec>,
    /// First-order lag of a custom model's T: none, SECONDS, auto or auto-t (default none).
    #[arg(long, value_name = "LAG")]
    pub lag: Option<LagSpec>,
    /// Samples a custom model is fitted on: all, plateaus or staged (default all; see
    /// `driftlab compare`).
    #[arg(long, value_name = "SAMPLES")]
    pub fit: Option<FitSamples>,
    /// A plateau as START:END in seconds (repeatable); replaces automatic detection.
    #[arg(long = "plateau", value_name = "START:END")]
    pub plateaus: Vec<PlateauRange>,
    /// Approximation of K0(T): linear, parabolic, pwl or spline.
    #[arg(long, value_name = "KIND")]
    pub k0: Option<ApproxKind>,
    /// Approximation of K1+ and K1− over Ṫ.
    #[arg(long, value_name = "KIND")]
    pub k1: Option<ApproxKind>,
    /// Approximation of K2+ and K2− over T̈.
    #[arg(long, value_name = "KIND")]
    pub k2: Option<ApproxKind>,
    /// Knots for pwl and spline approximations (all coefficients).
    #[arg(long, value_name = "N")]
    pub knots: Option<usize>,
    /// Centred moving-average window on Ω, s.
    #[arg(long, value_name = "S")]
    pub filter: Option<f64>,
    /// Causal moving-average window on T before differentiating, s.
    #[arg(long, value_name = "S")]
    pub smooth: Option<f64>,
    /// Derivative step H, s.
    #[arg(long = "step-h", value_name = "S")]
    pub step_h: Option<f64>,
    /// |Ṫ| dead-band for the K1 fits, °C/s (default: automatic).
    #[arg(long, value_name = "DEGC_PER_S")]
    pub deadband_tdot: Option<f64>,
    /// |T̈| dead-band for the K2 fits, °C/s² (default: automatic).
    #[arg(long, value_name = "DEGC_PER_S2")]
    pub deadband_tddot: Option<f64>,
    /// The gyro axes to calibrate, comma-separated: axis names (`gx`), rate columns
    /// (`gx_dps`) or the letter an axis name ends with (`x,y,z`). Default: every gyro axis of
    /// the log (a unit of several is written as one calibration file), or the one that
    /// --rate-col names.
    #[arg(long, value_name = "NAMES", value_delimiter = ',')]
    pub axes: Vec<String>,
    /// Another model for one axis of a unit, as AXIS=MODEL (repeatable): `gz=poly-t`.
    #[arg(long = "axis-model", value_name = "AXIS=MODEL")]
    pub axis_models: Vec<String>,
    /// Another recipe for one axis of a unit, as AXIS=FILE (repeatable; FILE a recipe, a
    /// calibration, or a unit's calibration whose axis of that name gives it): its Ω filter,
    /// approximations, knots, dead-bands, weighting and refinements; the T smoothing,
    /// derivative step, plateaus and gyro id are the unit's (said when the file sets others).
    /// Options given here still apply.
    #[arg(long = "axis-recipe", value_name = "AXIS=FILE")]
    pub axis_recipes: Vec<String>,
    /// Calibrate the log's accelerometer axes too, after its gyro axes (the columns whose
    /// names say so, or those --accel-col names): each a static model in T (poly-t3 unless
    /// --model or --axis-model gives another), about its mean, which its correction keeps.
    #[arg(long)]
    pub accel: bool,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub log_args: LogArgs,
}

impl Args {
    /// The recipe: the file's (or the defaults), overridden by the options given, checked.
    fn recipe(&self) -> Result<CheckedRecipe, CliError> {
        let base = match (&self.recipe, &self.recipe_axis) {
            (Some(p), Some(axis)) => unit_axis_recipe(p, axis)?,
            (Some(p), None) => calibration::read_recipe(p).map_err(|e| unit_as_recipe(p, e))?,
            (None, Some(_)) => {
                return Err(
                    "--recipe-axis names an axis of the unit's calibration --recipe \
                            gives; give --recipe"
                        .into(),
                );
            }
            (None, None) => Recipe::default(),
        };
        self.recipe_over(base, self.recipe_file().as_deref())
    }

    /// The file the recipe's settings are read from, as a message names it: `FILE`, or
    /// `FILE (axis AXIS)` with `--recipe-axis`; `None` for the defaults.
    fn recipe_file(&self) -> Option<String> {
        let file = self.recipe.as_ref()?.display();
        Some(match &self.recipe_axis {
            Some(axis) => format!("{file} (axis {axis})"),
            None => file.to_string(),
        })
    }

    /// `base` (read from the file `from` names, if any) overridden by the options given,
    /// checked; a refusal names where the value came from ([`Args::refused`]).
    pub(super) fn recipe_over(
        &self,
        mut r: Recipe,
        from: Option<&str>,
    ) -> Result<CheckedRecipe, CliError> {
        if let Some(id) = &self.gyro_id {
            r.gyro_id = id.clone();
        }
        if !self.plateaus.is_empty() {
            r.plateaus = PlateauChoice::Manual {
                ranges: self.plateaus.clone(),
            };
        }
        // By the engine's rules: another kind keeps the recipe's hand-placed knots while it has
        // knots, another count spreads them evenly again. Knots dropped so are told: they were
        // placed on purpose, and the option that drops them says nothing of them.
        let mut dropped = Vec::new();
        let mut set = |name: &str, spec: &mut ApproxSpec, kind: Option<(&str, ApproxKind)>| {
            let by_hand = spec.hand_knots();
            let mut by = Vec::new();
            if let Some((option, k)) = kind {
                *spec = spec.with_kind(k);
                by.push(format!("{option} {k}"));
            }
            if let Some(n) = self.knots {
                *spec = spec.with_knot_count(n);
                by.push(format!("--knots {n}"));
            }
            if by_hand && !spec.hand_knots() {
                dropped.push(format!(
                    "note: {}: {name}'s knots placed or set by hand{} are dropped",
                    by.join(", "),
                    from.map(|f| format!(" in {f}")).unwrap_or_default()
                ));
            }
        };
        set("K0", &mut r.k0, self.k0.map(|k| ("--k0", k)));
        set("K1+", &mut r.k1_plus, self.k1.map(|k| ("--k1", k)));
        set("K1−", &mut r.k1_minus, self.k1.map(|k| ("--k1", k)));
        set("K2+", &mut r.k2_plus, self.k2.map(|k| ("--k2", k)));
        set("K2−", &mut r.k2_minus, self.k2.map(|k| ("--k2", k)));
        for d in dropped {
            note!("{d}");
        }
        r.filter_s = self.filter.unwrap_or(r.filter_s);
        r.temp_smoothing_s = self.smooth.unwrap_or(r.temp_smoothing_s);
        r.step_h_s = self.step_h.unwrap_or(r.step_h_s);
        r.deadband_tdot = self.deadband_tdot.or(r.deadband_tdot);
        r.deadband_tddot = self.deadband_tddot.or(r.deadband_tddot);
        r.checked().map_err(|e| self.refused(e, from))
    }

    /// A setting the engine refused, named by where its value came from: the option when one
    /// given sets it (`filter_s (--filter): …`), else the file `from` names (`FILE: k0.at[0]:
    /// …`), whose value it is; a value of neither is a default, named by its option.
    fn refused(&self, e: driftlab::error::Invalid, from: Option<&str>) -> CliError {
        CliError::Message(self.in_source_words(&e, from))
    }

    /// [`Args::refused`]'s words, for a warning about a setting that was taken.
    fn in_source_words(&self, e: &driftlab::error::Invalid, from: Option<&str>) -> String {
        match from {
            Some(file) if !self.sets(&e.field) => format!("{file}: {e}"),
            _ => common::in_option_words(e),
        }
    }

    /// Whether an option given sets the recipe's `field` (as [`Args::recipe_over`] applies
    /// them): a curve's kind given by `--k0` keeps the file's knots placed by hand, so only
    /// its count is the option's (`--knots`).
    fn sets(&self, field: &str) -> bool {
        match field {
            "filter_s" => self.filter.is_some(),
            "temp_smoothing_s" => self.smooth.is_some(),
            "step_h_s" => self.step_h.is_some(),
            "deadband_tdot" => self.deadband_tdot.is_some(),
            "deadband_tddot" => self.deadband_tddot.is_some(),
            "gyro_id" => self.gyro_id.is_some(),
            f if f == "plateaus" || f.starts_with("plateaus.") => !self.plateaus.is_empty(),
            f if f.ends_with(".knots") => self.knots.is_some(),
            _ => false,
        }
    }
}

impl Args {
    /// The model asked for by --model, --terms, --delay, --lag and --fit; the options of a
    /// custom model are refused, by name, for any other.
    fn choice(&self) -> Result<ModelChoice, String> {
        self.choice_named(self.model.as_deref().unwrap_or("vakhrameev"))
    }

    /// The model `name` with the options of a custom model.
    pub(super) fn choice_named(&self, name: &str) -> Result<ModelChoice, String> {
        if name == "custom" {
            let terms = self
                .terms
                .as_deref()
                .ok_or("--model custom needs --terms")?;
            let mut spec = RegressionSpec::new(
                "custom",
                terms::parse_terms(terms).map_err(|e| e.to_string())?,
            );
            spec.delay = self.delay.clone().unwrap_or(DelaySpec::None);
            spec.lag = self.lag.clone().unwrap_or_default();
            spec.samples = self.fit.unwrap_or_default();
            spec.validate()?;
            return Ok(ModelChoice::Custom(spec));
        }
        let custom_only = [
            ("--terms", self.terms.is_some()),
            ("--delay", self.delay.is_some()),
            ("--lag", self.lag.is_some()),
            ("--fit", self.fit.is_some()),
        ];
        if let Some((option, _)) = custom_only.iter().find(|(_, given)| *given) {
            return Err(format!(
                "{option} goes with --model custom --terms ..., not with model {name}"
            ));
        }
        Ok(ModelChoice::Preset(
            Preset::from_name(name).map_err(|e| e.to_string())?,
        ))
    }

    /// Refuses the options `choice` cannot use, by name; returns a warning for each setting
    /// of the recipe file it will not read.
    pub(super) fn check_settings(
        &self,
        recipe: &Recipe,
        choice: &ModelChoice,
    ) -> Result<Vec<String>, String> {
        let name = choice.name();
        let vakhrameev_only = [
            ("--k0", self.k0.is_some()),
            ("--k1", self.k1.is_some()),
            ("--k2", self.k2.is_some()),
            ("--knots", self.knots.is_some()),
            ("--deadband-tdot", self.deadband_tdot.is_some()),
            ("--deadband-tddot", self.deadband_tddot.is_some()),
        ];
        if !choice.is_vakhrameev()
            && let Some((option, _)) = vakhrameev_only.iter().find(|(_, given)| *given)
        {
            return Err(format!(
                "{option}: it is a setting of the vakhrameev model, not of model {name}"
            ));
        }
        let no_plateaus = format!("model {name} is fitted over every sample and uses no plateaus");
        if !self.plateaus.is_empty() && !choice.uses_plateaus() {
            return Err(format!("--plateau: {no_plateaus}"));
        }
        let mut told: Vec<String> = models::settings_unused_by(recipe, choice)
            .into_iter()
            .map(|field| {
                let why = if field == "plateaus" {
                    no_plateaus.clone()
                } else {
                    format!("it is a setting of the vakhrameev model, not of model {name}")
                };
                format!("the recipe's {field} is not used: {why}")
            })
            .collect();
        if let Some(n) = self.knots
            && !recipe.specs().iter().any(|(_, s)| s.kind.has_knots())
        {
            told.push(format!(
                "--knots {n} is not used: none of K0, K1 and K2 is a pwl or spline curve \
                 (choose one with --k0, --k1 or --k2)"
            ));
        }
        Ok(told)
    }
}

/// One path for every calibration: the axes to fit (the log's one axis, or one a single
/// --rate-col names, is a unit of one unnamed axis, written as a version-1 file), fitted,
/// stamped with the log's name and SHA-256, saved, and printed.
pub fn run(a: Args) -> Result<(), CliError> {
    let mut reads = common::Reads::default();
    for (k, log) in a.log.iter().enumerate() {
        reads.add(
            if a.log.len() == 1 {
                "the log".to_string()
            } else {
                format!("run {} of the campaign", k + 1)
            },
            log,
        );
    }
    a.refuse_campaign_options()?;
    if let Some(r) = &a.recipe {
        reads.add("the recipe", r);
    }
    for v in &a.axis_recipes {
        let (axis, file) = pair("--axis-recipe", v)?;
        reads.add(
            format!("the recipe of axis {axis} (--axis-recipe)"),
            Path::new(file),
        );
    }
    let mut outputs = vec![("--out", a.out.as_path())];
    if let Some(save) = &a.save_recipe {
        outputs.push(("--save-recipe", save.as_path()));
    }
    common::refuse_outputs(&outputs, &reads)?;
    let recipe = a.recipe()?;
    let choice = a.choice()?;
    a.refuse_saving_a_model(&choice)?;
    let mut warnings = a.check_settings(&recipe, &choice)?;
    // Vakhrameev's model reads the three calibration columns only; the others are neither
    // parsed nor held.
    let all_vakhrameev = choice.is_vakhrameev() && a.axis_models_all_vakhrameev()?;
    if a.log.len() > 1
        && let PlateauChoice::Manual { .. } = recipe.plateaus
    {
        return Err(CliError::Message(format!(
            "{}: plateaus given by hand (the recipe's `plateaus`) with several runs: each run's \
             plateaus are found on its own time; calibrate on a recipe that finds them",
            a.recipe_file().unwrap_or_else(|| "the recipe".into())
        )));
    }
    let accel = a.accel_asked()?;
    let mut runs = a.read_runs(all_vakhrameev && accel.is_none())?;
    if let Some(ask) = &accel {
        a.log_args.take_accelerometers(&mut runs.log, ask)?;
    }
    // The axes of a unit, each with its plan; a log of one axis is a unit of one unnamed axis.
    // The `--axis-recipe` each axis's recipe came from, by axis name, for the fit's refusals.
    let mut axis_files: Vec<(String, String)> = Vec::new();
    let (plans, saved_recipe, axis_warnings) = match a.with_accelerometers(
        common::chosen_axes(&a.axes, &a.log_args, &runs.log)?,
        &runs.log,
    )? {
        Some(axes) => {
            let (plans, axis_warnings) =
                a.plans(&runs.log, &axes, &recipe, &choice, &mut axis_files)?;
            let saved = a.recipe_to_save(&plans)?;
            (plans, saved, axis_warnings)
        }
        None => {
            a.refuse_per_axis_options()?;
            (
                vec![AxisPlan::unnamed(choice, recipe.clone())],
                recipe.clone(),
                Vec::new(),
            )
        }
    };
    common::status(&match plans.as_slice() {
        [one] if one.name.is_empty() => "fitting ...".to_string(),
        [_] => "fitting 1 axis ...".to_string(),
        p => format!("fitting {} axes ...", p.len()),
    });
    let plan = UnitPlan {
        recipe,
        plans,
        campaign: a.campaign_options(),
        keep: models::Keep::Figures,
    };
    let merit = plan.merit();
    let recipe_file = a.recipe_file();
    let fitted = models::campaign::calibrate_runs(&mut runs, &plan).map_err(|e| {
        common::fit_failed(&runs.log.source, &e, &|i| {
            // An axis's setting refused: named by its `--axis-recipe` when that gave it.
            let on_axis = i
                .field
                .strip_prefix("axis ")
                .and_then(|r| r.split_once(": "));
            match on_axis {
                Some((axis, field)) if !a.sets(field) => {
                    match axis_files.iter().find(|(n, _)| n == axis) {
                        Some((_, v)) => {
                            format!("axis {axis}: --axis-recipe {v}: {field}: {}", i.reason)
                        }
                        None => a.in_source_words(i, recipe_file.as_deref()),
                    }
                }
                _ => a.in_source_words(i, recipe_file.as_deref()),
            }
        })
    })?;
    // What joining the runs left out (a channel some runs lack) or could not check (which
    // drone-log gyro a CSV run is), the settings the log makes odd, then each axis's own.
    warnings.extend(fitted.warnings.iter().cloned());
    warnings.extend(
        fitted
            .settings_told
            .iter()
            .map(|w| a.in_source_words(w, recipe_file.as_deref())),
    );
    warnings.extend(axis_warnings);
    let unit = &fitted.unit;
    // Both files are written before either is put in place: a recipe that cannot be
    // written leaves the old calibration as it was.
    let mut outputs = Batch::new();
    calibration::stage_unit(&mut outputs, &a.out, unit).map_err(|e| e.to_string())?;
    if let Some(p) = &a.save_recipe {
        let text =
            serde_json::to_string_pretty(saved_recipe.recipe()).map_err(|e| e.to_string())? + "\n";
        outputs
            .stage_bytes(p, text.as_bytes())
            .map_err(|e| e.to_string())?;
    }
    outputs.commit().map_err(|e| e.to_string())?;
    let printed = calibrate_print::Printed {
        out: &a.out,
        fitted: &fitted.fit.axes,
        tolerance_c: plan.campaign.tolerance_c,
        unit,
        warnings: &warnings,
        window_s: merit.window_s,
    };
    match (unit.is_unit(), a.json) {
        (false, true) => printed.single_json(),
        (false, false) => printed.single_text(),
        (true, true) => printed.unit_json(),
        (true, false) => printed.unit_text(),
    }
}

/// The file name of a path, for messages and the calibration's source.
pub fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}

/// The per-axis options of a unit: `--axis-model`, `--axis-recipe`.
impl Args {
    /// Refuses `--axis-model` and `--axis-recipe` for a single-axis calibration, by name.
    fn refuse_per_axis_options(&self) -> Result<(), CliError> {
        for (option, given) in [
            ("--axis-model", !self.axis_models.is_empty()),
            ("--axis-recipe", !self.axis_recipes.is_empty()),
        ] {
            if given {
                return Err(format!(
                    "{option}: this calibrates one axis (the log has one, or --rate-col names \
                     one); give --model or --recipe, or calibrate several axes with --axes"
                )
                .into());
            }
        }
        Ok(())
    }

    /// Whether every `--axis-model` is Vakhrameev's (the log's other columns are then not
    /// read).
    fn axis_models_all_vakhrameev(&self) -> Result<bool, CliError> {
        for v in &self.axis_models {
            let (_, model) = pair("--axis-model", v)?;
            if self.choice_named(model)? != ModelChoice::Preset(Preset::Vakhrameev) {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The plans of every axis: the command's model and recipe, or an axis's own; and a
    /// warning for each setting an axis's model will not read.
    fn plans(
        &self,
        log: &Log,
        axes: &[String],
        recipe: &CheckedRecipe,
        choice: &ModelChoice,
        axis_files: &mut Vec<(String, String)>,
    ) -> Result<(Vec<AxisPlan>, Vec<String>), CliError> {
        let mut plans: Vec<AxisPlan> = axes
            .iter()
            .map(|name| AxisPlan {
                name: name.clone(),
                choice: self.choice_for(log, name, choice),
                recipe: recipe.clone(),
            })
            .collect();
        let mut given = Given::default();
        for v in &self.axis_models {
            let (asked, model) = pair("--axis-model", v)?;
            let name = axis_of("--axis-model", asked, log, axes)?;
            given.once("--axis-model", &name, v)?;
            let choice = self
                .choice_named(model)
                .map_err(|e| format!("--axis-model {v}: {e}"))?;
            if let Some(p) = plans.iter_mut().find(|p| p.name == name) {
                p.choice = choice;
            }
        }
        let mut axis_notes = Vec::new();
        for v in &self.axis_recipes {
            let (asked, file) = pair("--axis-recipe", v)?;
            let name = axis_of("--axis-recipe", asked, log, axes)?;
            given.once("--axis-recipe", &name, v)?;
            let base =
                calibration::read_axis_recipe(Path::new(file), &name).map_err(|e| e.to_string())?;
            let (own, dropped) = self
                .recipe_over(base, Some(&format!("--axis-recipe {v}")))?
                .into_recipe()
                .as_axis_of(recipe);
            if !dropped.is_empty() {
                axis_notes.push(format!(
                    "axis {name}: --axis-recipe {file} sets {}, which the axes of a unit share: \
                     the unit's are used (give them to the unit: --smooth, --step-h, --plateau, \
                     --gyro-id, or its --recipe)",
                    dropped.join(", ")
                ));
            }
            let own = own
                .checked()
                .map_err(|e| format!("--axis-recipe {v}: {e}"))?;
            if let Some(p) = plans.iter_mut().find(|p| p.name == name) {
                p.recipe = own;
            }
            axis_files.push((name, v.clone()));
        }
        let mut warnings = axis_notes;
        for p in plans
            .iter()
            .filter(|p| !self.accel_by_default(log, p, &given))
        {
            let w = self
                .check_settings(&p.recipe, &p.choice)
                .map_err(|e| format!("axis {}: {e}", p.name))?;
            warnings.extend(w.into_iter().map(|w| format!("axis {}: {w}", p.name)));
        }
        Ok((plans, warnings))
    }

    /// Refuses `--save-recipe` when a model other than Vakhrameev's is fitted (`--model`, or
    /// an axis's `--axis-model`), naming the option and the model. A recipe file holds the
    /// settings of Vakhrameev's model and has no field for a model (its fields are closed, and
    /// a file with one would not load where recipes are read today), so `--recipe` of it
    /// would make a Vakhrameev calibration: another calibration than the one it was saved
    /// with, with nothing said.
    fn refuse_saving_a_model(&self, choice: &ModelChoice) -> Result<(), CliError> {
        let Some(save) = &self.save_recipe else {
            return Ok(());
        };
        let mut given = Vec::new();
        if !choice.is_vakhrameev() {
            let mut option = format!("--model {}", choice.name());
            if let Some(terms) = &self.terms {
                option.push_str(&format!(" --terms {terms}"));
            }
            let settings: Vec<&str> = [
                ("--delay", self.delay.is_some()),
                ("--lag", self.lag.is_some()),
                ("--fit", self.fit.is_some()),
            ]
            .iter()
            .filter(|(_, given)| *given)
            .map(|(flag, _)| *flag)
            .collect();
            if !settings.is_empty() {
                option.push_str(&format!(" with its {}", settings.join(", ")));
            }
            given.push((choice.name().to_string(), option));
        }
        for v in &self.axis_models {
            let (_, model) = pair("--axis-model", v)?;
            let axis_choice = self
                .choice_named(model)
                .map_err(|e| format!("--axis-model {v}: {e}"))?;
            if !axis_choice.is_vakhrameev() {
                given.push((axis_choice.name().to_string(), format!("--axis-model {v}")));
            }
        }
        let Some((name, option)) = given.first() else {
            return Ok(());
        };
        Err(format!(
            "--save-recipe {}: a recipe holds the settings of model vakhrameev and names no \
             model, so --recipe of it would make a vakhrameev calibration, not one of model \
             {name} ({option}); leave out --save-recipe, and give {option} again where the \
             calibration is to be made again",
            save.display()
        )
        .into())
    }

    /// The recipe `--save-recipe` writes for a unit: the one every axis shares.
    fn recipe_to_save(&self, plans: &[AxisPlan]) -> Result<CheckedRecipe, CliError> {
        let first = &plans[0].recipe;
        if let Some(p) = &self.save_recipe
            && plans.iter().any(|q| q.recipe != *first)
        {
            return Err(format!(
                "--save-recipe {}: the axes have recipes of their own; the calibration file \
                 holds each axis's recipe",
                p.display()
            )
            .into());
        }
        Ok(first.clone())
    }
}

/// The axes a per-axis option has given a value to, each with the value as given, so that
/// the same axis given twice (`gx=poly-t` and `x=ieee952`) is refused rather than the last
/// taken, as `--axes gx,gx` is.
#[derive(Default)]
pub(super) struct Given<'a> {
    seen: Vec<(&'static str, String, &'a str)>,
}

impl<'a> Given<'a> {
    /// Whether `option` gave axis `name` a value.
    pub(super) fn gave(&self, option: &str, name: &str) -> bool {
        self.seen.iter().any(|(o, n, _)| *o == option && n == name)
    }

    /// Records `option` `value` for axis `name`, or refuses it naming both values.
    fn once(&mut self, option: &'static str, name: &str, value: &'a str) -> Result<(), CliError> {
        if let Some((_, _, first)) = self.seen.iter().find(|(o, n, _)| *o == option && n == name) {
            return Err(format!(
                "{option} {first} and {option} {value} both give axis {name}: give it once"
            )
            .into());
        }
        self.seen.push((option, name.to_string(), value));
        Ok(())
    }
}

/// `AXIS=VALUE` split, or a message naming `option`.
fn pair<'a>(option: &str, v: &'a str) -> Result<(&'a str, &'a str), CliError> {
    match v.split_once('=') {
        Some((axis, value)) if !axis.trim().is_empty() && !value.trim().is_empty() => {
            Ok((axis.trim(), value.trim()))
        }
        _ => Err(format!("{option} \"{v}\": give AXIS=VALUE, e.g. gz=poly-t").into()),
    }
}

/// The axis of `axes` an `AXIS=…` option means.
fn axis_of(option: &str, asked: &str, log: &Log, axes: &[String]) -> Result<String, CliError> {
    match log.find_axis(asked) {
        Some(name) if axes.contains(&name) => Ok(name),
        _ => Err(format!(
            "{option} {asked}=…: not an axis being calibrated (axes: {})",
            axes.join(", ")
        )
        .into()),
    }
}

/// Why `--recipe FILE` was refused, with the ways a unit's calibration is given when `FILE` is
/// one: `--recipe` takes one recipe for every axis, a unit holds one per axis, which
/// `--axis-recipe AXIS=FILE` takes on a log of several axes, and `--recipe-axis AXIS` takes one
/// of on a log of one (where `--axis-recipe` is refused).
fn unit_as_recipe(path: &std::path::Path, e: driftlab::error::Error) -> CliError {
    let shown = path.display();
    match calibration::load_unit(path) {
        Ok(unit) if unit.axes.len() > 1 => {
            let each: Vec<String> = unit
                .axes
                .iter()
                .map(|a| format!("--axis-recipe {}={shown}", a.name))
                .collect();
            format!(
                "{e}: give each axis its recipe from it with {}; on a log of one axis, take one \
                 axis's recipe with --recipe {shown} --recipe-axis {}",
                each.join(" "),
                unit.axes[0].name
            )
            .into()
        }
        _ => e.to_string().into(),
    }
}

/// The recipe of the axis `axis` of the unit's calibration at `path` (`--recipe FILE
/// --recipe-axis AXIS`), a unit of any number of named axes. A file that cannot be read as
/// one is refused with what is wrong with it (file, line and column, or the field); a file
/// that reads as one recipe (a recipe, a single-axis calibration) is refused by name, for
/// `--recipe` takes its one recipe alone.
fn unit_axis_recipe(path: &std::path::Path, axis: &str) -> Result<Recipe, CliError> {
    let recipe = calibration::read_axis_recipe(path, axis)
        .map_err(|e| CliError::from(format!("--recipe-axis {axis}: {e}")))?;
    match calibration::load_unit(path) {
        Ok(unit) if unit.is_unit() => Ok(recipe),
        _ => Err(format!(
            "--recipe-axis {axis}: {} is no unit's calibration: it holds one recipe, which \
             --recipe takes without --recipe-axis",
            path.display()
        )
        .into()),
    }
}
