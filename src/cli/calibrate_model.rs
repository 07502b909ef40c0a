//! `driftlab calibrate --model NAME`: fit a model other than Vakhrameev's and save it.

use super::calibrate::{Args, file_name};
use super::common;
use driftlab::files::calibration;
use driftlab::judge::metrics::{Evaluation, MeritOptions};
use driftlab::models::fitted::{self, DriftModel};
use driftlab::models::presets::ModelChoice;
use driftlab::models::recipe::Recipe;

pub fn run(a: &Args, recipe: &Recipe) -> Result<(), String> {
    let name = a.model.as_deref().unwrap_or("custom");
    let customs: Vec<String> = a.terms.iter().cloned().collect();
    let models: Vec<String> = if name == "custom" {
        Vec::new()
    } else {
        vec![name.to_string()]
    };
    if name != "custom" && a.terms.is_some() {
        return Err(format!(
            "--terms goes with --model custom, not --model {name}"
        ));
    }
    if name == "custom" && a.terms.is_none() {
        return Err("--model custom needs --terms".into());
    }
    let choice: ModelChoice = super::compare::choices(
        &models,
        &customs,
        &super::compare::CustomOptions {
            delay: &a.delay,
            lag: &a.lag,
            fit: &a.fit,
        },
    )?
    .into_iter()
    .next()
    .ok_or("no model chosen")?;
    let log = a.log_args.read(&a.log)?;
    common::status("fitting ...");
    let mut model =
        fitted::fit(&log, &choice, recipe).map_err(|e| format!("{}: {e}", a.log.display()))?;
    model.source_mut().name = file_name(&a.log);
    model.source_mut().sha256 = calibration::sha256_file(&a.log).map_err(|e| e.to_string())?;
    calibration::save_model(&a.out, &model).map_err(|e| e.to_string())?;
    let opts = MeritOptions {
        filter_s: recipe.filter_s,
        ..MeritOptions::default()
    };
    let correction = model.correct(&log).map_err(|e| e.to_string())?;
    let eval = Evaluation::of_correction(&log, &correction, &opts);
    if a.json {
        let body = match &model {
            DriftModel::Regression(r) => serde_json::to_value(&r.model),
            DriftModel::Vakhrameev(c) => serde_json::to_value(c),
        }
        .map_err(|e| e.to_string())?;
        return common::print_json(&serde_json::json!({
            "calibration": a.out,
            "model": body,
            "in_sample": eval,
        }));
    }
    if let DriftModel::Regression(r) = &model {
        let m = &r.model;
        println!(
            "Model {} on {}: {} samples, RMS residual {:.4} deg/h, R² {:.3}",
            m.spec.name, r.source.name, m.stats.n, m.stats.rmse, m.stats.r2
        );
        println!("  {:<22} {:>14} {:>12}", "term", "coefficient", "std error");
        for ((n, c), e) in m.names.iter().zip(&m.coefficients).zip(&m.std_errors) {
            println!("  {n:<22} {c:>14.6e} {e:>12.2e}");
        }
        if let Some(l) = m.lambda_s {
            println!("  self-heating λ = {l:.0} s");
        }
        if let Some(l) = m.lag_s {
            if m.lag_per_c == 0.0 {
                println!("  lag of T τ = {l:.0} s");
            } else {
                println!(
                    "  lag of T τ = {l:.0} s at 20 degC, τ20/(1 + {:.4}·(T − 20)) elsewhere",
                    m.lag_per_c
                );
            }
        }
        for p in &m.delay.points {
            println!("  delay τd = {:.0} s at {:.1} degC", p[1], p[0]);
        }
        for c in m.searches.iter().filter(|c| c.at_edge) {
            println!(
                "  note: the best {} ({:.0}) is at the end of the searched range",
                c.parameter, c.best
            );
        }
    }
    println!();
    println!("In-sample (fitted and evaluated on {}):", file_name(&a.log));
    common::print_evaluation(&eval);
    println!();
    println!("Calibration written to {}", a.out.display());
    Ok(())
}
