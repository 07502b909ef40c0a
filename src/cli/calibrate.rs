//! `driftlab calibrate`: fit a calibration to a log and save it.

use super::common::{self, LogArgs};
use driftlab::files::calibration;
use driftlab::judge::metrics::{Evaluation, MeritOptions};
use driftlab::models::approx::{ApproxKind, ApproxSpec};
use driftlab::models::recipe::{PlateauChoice, Recipe};
use driftlab::models::vakhrameev::{self, Calibration};
use driftlab::signal::plateau::PlateauRange;
use std::path::{Path, PathBuf};

/// Arguments of `calibrate`. Options given here override those of `--recipe`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The chamber log to calibrate on.
    pub log: PathBuf,
    /// Where to write the calibration (JSON).
    #[arg(long, short)]
    pub out: PathBuf,
    /// Take every setting from a recipe file (JSON), or from the recipe inside a calibration file.
    #[arg(long, value_name = "FILE")]
    pub recipe: Option<PathBuf>,
    /// Also write the recipe that was used (JSON), to re-run or edit later.
    #[arg(long, value_name = "FILE")]
    pub save_recipe: Option<PathBuf>,
    /// Gyro identifier (serial number) stored in the calibration.
    #[arg(long)]
    pub gyro_id: Option<String>,
    /// The model to fit (default vakhrameev): a preset (ieee952, yan-cross, yan-delayed,
    /// sukhanov, poly-t, pwl-t) or `custom` with --terms. See `driftlab compare`.
    #[arg(long, value_name = "NAME")]
    pub model: Option<String>,
    /// Terms of a custom model, comma-separated (see `driftlab compare --help`).
    #[arg(long, value_name = "TERMS")]
    pub terms: Option<String>,
    /// Delay of a custom model's temperature channels: none, SECONDS, auto or bands:N.
    #[arg(long, value_name = "DELAY", default_value = "none")]
    pub delay: String,
    /// First-order lag of a custom model's T: none, SECONDS or auto.
    #[arg(long, value_name = "LAG", default_value = "none")]
    pub lag: String,
    /// Samples a custom model is fitted on: all, plateaus or staged (see `driftlab compare`).
    #[arg(long, value_name = "SAMPLES", default_value = "all")]
    pub fit: String,
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
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub log_args: LogArgs,
}

/// Reads a recipe file, or the recipe of a calibration file.
fn read_recipe(path: &Path) -> Result<Recipe, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    if text.contains(&format!("\"{}\"", calibration::FORMAT)) {
        return calibration::from_json(path, &text)
            .map(|c| c.recipe)
            .map_err(|e| e.to_string());
    }
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

impl Args {
    /// The recipe: the file's (or the defaults), overridden by the options given.
    fn recipe(&self) -> Result<Recipe, String> {
        let mut r = match &self.recipe {
            Some(p) => read_recipe(p)?,
            None => Recipe::default(),
        };
        if let Some(id) = &self.gyro_id {
            r.gyro_id = id.clone();
        }
        if !self.plateaus.is_empty() {
            r.plateaus = PlateauChoice::Manual {
                ranges: self.plateaus.clone(),
            };
        }
        let set = |spec: &mut ApproxSpec, kind: Option<ApproxKind>| {
            if let Some(k) = kind {
                spec.kind = k;
            }
            if let Some(n) = self.knots {
                spec.knots = n;
            }
        };
        set(&mut r.k0, self.k0);
        set(&mut r.k1_plus, self.k1);
        set(&mut r.k1_minus, self.k1);
        set(&mut r.k2_plus, self.k2);
        set(&mut r.k2_minus, self.k2);
        r.filter_s = self.filter.unwrap_or(r.filter_s);
        r.temp_smoothing_s = self.smooth.unwrap_or(r.temp_smoothing_s);
        r.step_h_s = self.step_h.unwrap_or(r.step_h_s);
        r.deadband_tdot = self.deadband_tdot.or(r.deadband_tdot);
        r.deadband_tddot = self.deadband_tddot.or(r.deadband_tddot);
        r.validate()?;
        Ok(r)
    }
}

pub fn run(a: Args) -> Result<(), String> {
    let recipe = a.recipe()?;
    if a.model.as_deref().is_some_and(|m| m != "vakhrameev") || a.terms.is_some() {
        return super::calibrate_model::run(&a, &recipe);
    }
    let log = a.log_args.read_columns(&a.log)?;
    common::status("fitting ...");
    // The file's hash is taken beside the fit, whose stages are partly sequential.
    let (fitted, sha256) = std::thread::scope(|scope| {
        let sha = scope.spawn(|| calibration::sha256_file(&a.log).map_err(|e| e.to_string()));
        let fitted = vakhrameev::calibrate(&log, &recipe);
        let sha256 = sha
            .join()
            .unwrap_or_else(|_| Err("the hashing thread failed".to_string()));
        (fitted, sha256)
    });
    // Only the calibration and the derivatives (for the in-sample figures) are kept: no point
    // sets and no filtered Ω, which on a 10⁷-sample log are hundreds of MB.
    let vakhrameev::Calibrated {
        calibration: mut cal,
        deriv,
        warnings,
    } = fitted.map_err(|e| format!("{}: {e}", a.log.display()))?;
    cal.source.name = file_name(&a.log);
    cal.source.sha256 = sha256?;
    calibration::save(&a.out, &cal).map_err(|e| e.to_string())?;
    if let Some(p) = &a.save_recipe {
        let text = serde_json::to_string_pretty(&recipe).map_err(|e| e.to_string())? + "\n";
        driftlab::files::atomic::write_bytes(p, text.as_bytes())
            .map_err(|e| format!("{}: {e}", p.display()))?;
    }
    let opts = MeritOptions {
        filter_s: recipe.filter_s,
        ..MeritOptions::default()
    };
    // In-sample: the derivatives of the fit are the ones the calibration computes on this log;
    // the corrected rate alone is all the figures read.
    let c = cal.corrected_rate_with(&log, &deriv);
    drop(deriv);
    let eval = Evaluation::of_rate(&log, &c.cor_dph, c.ready_from, c.outside_fraction, &opts);
    if a.json {
        return common::print_json(&serde_json::json!({
            "calibration": a.out,
            "plateaus": cal.plateaus,
            "approximations": cal.approximations().iter().map(|(n, ap)| serde_json::json!({
                "name": n, "kind": ap.kind(), "x_min": ap.x_min(), "x_max": ap.x_max(), "stats": ap.stats()
            })).collect::<Vec<_>>(),
            "resolved": cal.resolved,
            "in_sample": eval,
            "warnings": warnings,
        }));
    }
    print_summary(&cal, &warnings);
    println!();
    println!(
        "In-sample (calibrated and evaluated on {}):",
        cal.source.name
    );
    common::print_evaluation(&eval);
    println!();
    println!("Calibration written to {}", a.out.display());
    Ok(())
}

fn print_summary(cal: &Calibration, warnings: &[String]) {
    let r = &cal.resolved;
    println!(
        "Log {}: {} samples, {:.2} h, step {} s",
        cal.source.name,
        cal.source.samples,
        cal.source.duration_s / 3600.0,
        r.dt_s
    );
    println!(
        "Filter {} samples, T smoothing {} samples, H = {} samples; dead-bands |Tdot| {:.3e} degC/s, |Tddot| {:.3e} degC/s^2",
        r.filter_samples, r.smooth_samples, r.step_samples, r.deadband_tdot, r.deadband_tddot
    );
    println!();
    println!("Plateaus (K0 points):");
    println!(
        "  {:>10} {:>10} {:>9} {:>11} {:>9} {:>8}",
        "start_s", "end_s", "T_degC", "Omega_dph", "std_dph", "samples"
    );
    for p in &cal.plateaus {
        println!(
            "  {:>10.0} {:>10.0} {:>9.3} {:>11.4} {:>9.4} {:>8}",
            p.range.start_s, p.range.end_s, p.temp_c, p.omega_dph, p.omega_std_dph, p.samples
        );
    }
    println!();
    println!("Approximations:");
    println!(
        "  {:<11} {:<10} {:>12} {:>12} {:>8} {:>11} {:>7}",
        "", "kind", "x_min", "x_max", "n", "rmse", "R2"
    );
    for (name, ap) in cal.approximations() {
        let s = ap.stats();
        println!(
            "  {:<11} {:<10} {:>12.4e} {:>12.4e} {:>8} {:>11.4e} {:>7.3}",
            name,
            ap.kind().to_string(),
            ap.x_min(),
            ap.x_max(),
            s.n,
            s.rmse,
            s.r2
        );
    }
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// The file name of a path, for messages and the calibration's source.
pub fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}
