//! `driftlab calibrate` on a log of several gyro axes: every axis (or those `--axes` or a
//! repeated `--rate-col` choose) fitted with one read and one temperature processing, into one
//! calibration file ([`models::calibrate_unit`]).

use super::calibrate::{Args, file_name};
use super::calibrate_print;
use super::common::{self, CliError, figure, ratio};
use driftlab::Log;
use driftlab::files::calibration;
use driftlab::judge::metrics::MeritOptions;
use driftlab::log::ingest::Input;
use driftlab::models::CheckedRecipe;
use driftlab::models::{self, AxisModel, AxisPlan, DriftModel, ModelChoice, UnitCalibration};

/// The axes to calibrate as one unit ([`common::chosen_axes`]), or `None` for a single-axis
/// calibration as driftlab has always made it: a log with one gyro axis, or one axis named by
/// a single `--rate-col`.
///
/// # Errors
/// An `--axes` entry that names no axis of the log.
pub fn axes_to_fit(a: &Args, log: &Log) -> Result<Option<Vec<String>>, CliError> {
    common::chosen_axes(&a.axes, &a.log_args, log)
}

/// Refuses `--axis-model` and `--axis-recipe` for a single-axis calibration, by name.
pub fn refuse_per_axis_options(a: &Args) -> Result<(), CliError> {
    for (option, given) in [
        ("--axis-model", !a.axis_models.is_empty()),
        ("--axis-recipe", !a.axis_recipes.is_empty()),
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

/// Whether every `--axis-model` is Vakhrameev's (the log's other columns are then not read).
pub fn axis_models_all_vakhrameev(a: &Args) -> Result<bool, CliError> {
    for v in &a.axis_models {
        let (_, model) = pair("--axis-model", v)?;
        if a.choice_named(model)? != ModelChoice::Preset(models::Preset::Vakhrameev) {
            return Ok(false);
        }
    }
    Ok(true)
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

/// The plans of every axis: the command's model and recipe, or an axis's own.
fn plans(
    a: &Args,
    log: &Log,
    axes: &[String],
    recipe: &CheckedRecipe,
    choice: &ModelChoice,
) -> Result<(Vec<AxisPlan>, Vec<String>), CliError> {
    let mut plans: Vec<AxisPlan> = axes
        .iter()
        .map(|name| AxisPlan {
            name: name.clone(),
            choice: choice.clone(),
            recipe: recipe.clone(),
        })
        .collect();
    for v in &a.axis_models {
        let (asked, model) = pair("--axis-model", v)?;
        let name = axis_of("--axis-model", asked, log, axes)?;
        let choice = a
            .choice_named(model)
            .map_err(|e| format!("--axis-model {v}: {e}"))?;
        if let Some(p) = plans.iter_mut().find(|p| p.name == name) {
            p.choice = choice;
        }
    }
    for v in &a.axis_recipes {
        let (asked, file) = pair("--axis-recipe", v)?;
        let name = axis_of("--axis-recipe", asked, log, axes)?;
        let base =
            calibration::read_recipe(std::path::Path::new(file)).map_err(|e| e.to_string())?;
        let mut own = a.recipe_over(base)?.into_recipe();
        // The unit's T settings: an axis's recipe keeps its approximations and dead-bands.
        own.temp_smoothing_s = recipe.temp_smoothing_s;
        own.step_h_s = recipe.step_h_s;
        own.plateaus = recipe.plateaus.clone();
        own.gyro_id = recipe.gyro_id.clone();
        let own = own
            .checked()
            .map_err(|e| format!("--axis-recipe {v}: {e}"))?;
        if let Some(p) = plans.iter_mut().find(|p| p.name == name) {
            p.recipe = own;
        }
    }
    let mut warnings = Vec::new();
    for p in &plans {
        let w = a
            .check_settings(&p.recipe, &p.choice)
            .map_err(|e| format!("axis {}: {e}", p.name))?;
        warnings.extend(w.into_iter().map(|w| format!("axis {}: {w}", p.name)));
    }
    Ok((plans, warnings))
}

/// Calibrates `axes` of `log` into one unit file and prints what each axis got.
pub fn run(
    a: &Args,
    mut log: Log,
    input: &Input,
    axes: &[String],
    (recipe, choice, mut warnings): (CheckedRecipe, ModelChoice, Vec<String>),
    merit: &MeritOptions,
) -> Result<(), CliError> {
    let (plans, axis_warnings) = plans(a, &log, axes, &recipe, &choice)?;
    warnings.extend(axis_warnings);
    let save_recipe = match &a.save_recipe {
        Some(p) => {
            let first = &plans[0].recipe;
            if plans.iter().any(|q| q.recipe != *first) {
                return Err(format!(
                    "--save-recipe {}: the axes have recipes of their own; the calibration file \
                     holds each axis's recipe",
                    p.display()
                )
                .into());
            }
            Some((p, first.clone()))
        }
        None => None,
    };
    common::status(&format!("fitting {} axes ...", plans.len()).replace("1 axes", "1 axis"));
    let (fitted, sha256) = std::thread::scope(|scope| {
        let sha = scope.spawn(|| calibration::sha256_input(input).map_err(|e| e.to_string()));
        let fitted = models::calibrate_unit(&mut log, &plans, merit);
        let sha256 = sha
            .join()
            .unwrap_or_else(|_| Err("the hashing thread failed".to_string()));
        (fitted, sha256)
    });
    let fitted = fitted.map_err(|e| common::fit_failed(&log.source, &e))?;
    let sha256 = sha256?;
    let name = file_name(&a.log);
    let mut unit = UnitCalibration {
        axes: Vec::with_capacity(fitted.len()),
    };
    let created = fitted
        .first()
        .map(|f| created_of(&f.calibrated.model))
        .unwrap_or_default();
    for f in &fitted {
        let mut model = f.calibrated.model.clone();
        model.source_mut().name = name.clone();
        model.source_mut().sha256 = sha256.clone();
        set_created(&mut model, &created);
        unit.axes.push(AxisModel {
            name: f.name.clone(),
            rate_column: f.rate_column.clone(),
            model,
        });
    }
    calibration::save_unit(&a.out, &unit).map_err(|e| e.to_string())?;
    if let Some((p, r)) = save_recipe {
        let text = serde_json::to_string_pretty(r.recipe()).map_err(|e| e.to_string())? + "\n";
        driftlab::files::atomic::write_bytes(p, text.as_bytes())
            .map_err(|e| format!("{}: {e}", p.display()))?;
    }
    if a.json {
        let axes: Vec<serde_json::Value> = fitted
            .iter()
            .zip(&unit.axes)
            .map(|(f, ax)| {
                let mut v = serde_json::json!({
                    "name": f.name,
                    "rate_column": f.rate_column,
                    "model_name": ax.model.name(),
                    "in_sample": f.calibrated.in_sample,
                    "warnings": f.calibrated.warnings,
                });
                if let (Some(o), serde_json::Value::Object(body)) =
                    (v.as_object_mut(), calibrate_print::model_json(&ax.model))
                {
                    o.extend(body);
                }
                v
            })
            .collect();
        return common::print_json(&serde_json::json!({
            "calibration": a.out,
            "warnings": warnings,
            "axes": axes,
        }));
    }
    for w in &warnings {
        note!("warning: {w}");
    }
    for (f, ax) in fitted.iter().zip(&unit.axes) {
        out!(
            "=== Axis {}{} — model {} ===",
            f.name,
            if f.rate_column.is_empty() || f.rate_column == f.name {
                String::new()
            } else {
                format!(" (column {})", f.rate_column)
            },
            ax.model.name()
        )?;
        let axis_warnings: Vec<String> = f
            .calibrated
            .warnings
            .iter()
            .map(|w| format!("axis {}: {w}", f.name))
            .collect();
        match &ax.model {
            DriftModel::Vakhrameev(cal) => {
                calibrate_print::vakhrameev_summary(cal, &axis_warnings)?
            }
            DriftModel::Regression(r) => {
                calibrate_print::regression_summary(r)?;
                for w in &axis_warnings {
                    note!("warning: {w}");
                }
            }
        }
        out!()?;
        out!(
            "In-sample, axis {} (calibrated and evaluated on {name}):",
            f.name
        )?;
        common::print_evaluation(&f.calibrated.in_sample, merit.window_s)?;
        out!()?;
    }
    print_unit_summary(&fitted, &unit, &name, merit.window_s)?;
    out!()?;
    out!(
        "Calibration of {} ({}) written to {}",
        match unit.axes.len() {
            1 => "1 axis".to_string(),
            n => format!("{n} axes"),
        },
        unit.axis_names().join(", "),
        a.out.display()
    )?;
    Ok(())
}

/// One line per axis: the in-sample figures, raw against corrected.
fn print_unit_summary(
    fitted: &[models::CalibratedAxis],
    unit: &UnitCalibration,
    log_name: &str,
    window_s: f64,
) -> Result<(), CliError> {
    let w = driftlab::judge::options::window_label(window_s);
    out!("Unit summary, in-sample on {log_name} (deg/h; raw -> corrected, raw/cor):")?;
    out!(
        "  {:<8} {:<12} {:>30} {:>30} {:>30}",
        "axis",
        "model",
        "peak-to-peak",
        "std",
        format!("max |{w} mean|")
    )?;
    for (f, ax) in fitted.iter().zip(&unit.axes) {
        let c = &f.calibrated.in_sample.comparison;
        let cell =
            |raw: f64, cor: f64, r: f64| format!("{} -> {} {}", figure(raw), figure(cor), ratio(r));
        out!(
            "  {:<8} {:<12} {:>30} {:>30} {:>30}",
            f.name,
            ax.model.name(),
            cell(c.raw.p2p_dph, c.corrected.p2p_dph, c.p2p_ratio),
            cell(c.raw.std_dph, c.corrected.std_dph, c.std_ratio),
            cell(
                c.raw.win_mean_max_abs_dph,
                c.corrected.win_mean_max_abs_dph,
                c.win_mean_ratio
            )
        )?;
    }
    Ok(())
}

fn created_of(model: &DriftModel) -> String {
    match model {
        DriftModel::Vakhrameev(c) => c.created.clone(),
        DriftModel::Regression(r) => r.created.clone(),
    }
}

/// One date for the unit: the axes are fitted within a second or two of each other.
fn set_created(model: &mut DriftModel, created: &str) {
    match model {
        DriftModel::Vakhrameev(c) => c.created = created.to_string(),
        DriftModel::Regression(r) => r.created = created.to_string(),
    }
}
