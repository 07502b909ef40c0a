//! The figures of a model itself, drawn once per axis before its logs': a Vakhrameev
//! calibration's coefficients (`k0`, `k1`, `k2`: the fitted curves with the plateau points and,
//! when its own log is among the logs, the pointwise K1± and K2± values they were fitted to;
//! for a calibration of a campaign, `campaign`: every run's plateau biases beside K0), a
//! regression model's searches (`costs`: RMS residual over the values tried, the chosen one
//! marked; only when the model searched).

use super::figures::{self, PlateauPoint, RateAxes, RateSet};
use super::{Figure, figure, file_name};
use crate::error::Result;
use crate::log::Log;
use crate::models::DriftModel;
use crate::models::regression::RegressionCalibration;
use crate::models::vakhrameev::Calibration;
use std::path::{Path, PathBuf};

/// What a model's own figures leave for the rest of its report.
pub(super) struct ModelFigures {
    /// File stems the model's figures and the page take, which a log's figures must not.
    pub(super) taken: Vec<String>,
    /// Every file written.
    pub(super) files: Vec<PathBuf>,
    /// Things the reader should know.
    pub(super) notes: Vec<String>,
    /// The figures, in the page's order.
    pub(super) figures: Vec<Figure>,
}

/// Draws the figures of `model` into `out_dir`; `in_sample` says which of `logs` is its own.
pub(super) fn draw(
    model: &DriftModel,
    logs: &[(PathBuf, Log)],
    in_sample: &[bool],
    out_dir: &Path,
) -> Result<ModelFigures> {
    match model {
        DriftModel::Vakhrameev(cal) => vakhrameev(cal, logs, in_sample, out_dir),
        DriftModel::Regression(reg) => regression(reg, logs, in_sample, out_dir),
    }
}

/// The campaign's figure (`campaign`): every run's plateau biases over temperature with K0.
fn campaign_figure(cal: &Calibration, out_dir: &Path, files: &mut Vec<PathBuf>) -> Result<Figure> {
    let runs: Vec<figures::RunPoints> = cal
        .source
        .runs
        .iter()
        .enumerate()
        .map(|(k, r)| figures::RunPoints {
            label: format!("run {}: {}", k + 1, crate::text::escaped(&r.name, false)),
            points: r.plateaus.iter().map(|p| (p.temp_c, p.bias_dph)).collect(),
        })
        .collect();
    let f = figures::campaign_biases(
        &out_dir.join("campaign"),
        "Plateau biases of the campaign's runs and K0(T)",
        &cal.k0,
        &runs,
    )?;
    files.extend(f.iter().cloned());
    let offsets = cal
        .source
        .runs
        .iter()
        .any(|r| r.turn_on_offset_dph.is_some());
    Ok(figure(
        "Campaign".into(),
        format!(
            "Each plateau's bias (the mean raw rate, the run's turn-on offset included), a              colour per run, over its temperature, and the {} fit of K0(T){}.",
            cal.k0.kind(),
            if offsets {
                ", which the runs' estimated turn-on offsets were kept out of: a run's points \
                 sit about its offset (campaign section) from the others'"
            } else {
                ""
            }
        ),
        f,
    ))
}

/// K0(T) with its plateau points, K1± and K2± with their pointwise values.
fn vakhrameev(
    cal: &Calibration,
    logs: &[(PathBuf, Log)],
    in_sample: &[bool],
    out_dir: &Path,
) -> Result<ModelFigures> {
    let mut notes = Vec::new();
    let mut files = Vec::new();
    let mut taken: Vec<String> = ["k0", "k1", "k2", "report"]
        .iter()
        .map(|s| s.to_string())
        .collect();

    // The calibration's figures.
    let mut cal_figures = Vec::new();
    let k0_points: Vec<PlateauPoint> = cal
        .plateaus
        .iter()
        .map(|p| PlateauPoint {
            temp_c: p.temp_c,
            omega_dph: p.omega_dph,
            std_dph: p.omega_std_dph,
        })
        .collect();
    let f = figures::k0(
        &out_dir.join("k0"),
        "Static bias K0(T) from the temperature plateaus",
        &cal.k0,
        &k0_points,
    )?;
    files.extend(f.iter().cloned());
    cal_figures.push(figure(
        "K0(T)".into(),
        format!(
            "Static bias K0 over temperature: the mean rate of each of the {} plateaus (± std of \
             the raw rate) and the {} fit over {:.1} … {:.1} °C, held at its edge value beyond.",
            cal.plateaus.len(),
            cal.k0.kind(),
            cal.k0.x_min(),
            cal.k0.x_max()
        ),
        f,
    ));
    if !cal.source.runs.is_empty() {
        taken.push("campaign".into());
        cal_figures.push(campaign_figure(cal, out_dir, &mut files)?);
    }

    let own = in_sample.iter().position(|&b| b);
    let points = own.map(|i| cal.pointwise(&logs[i].1));
    let source_note = match own {
        Some(i) => format!(
            "Dots: the pointwise values on the calibration log {} (thinned for drawing).",
            crate::text::escaped(&file_name(&logs[i].0), false)
        ),
        None => {
            notes.push(format!(
                "The calibration's own log ({}) is not among the logs: the K1 and K2 figures \
                 show the fitted curves without their points, and every log is held out.",
                crate::text::escaped(&cal.source.name, false)
            ));
            "The calibration log was not given, so only the fitted curves are drawn.".into()
        }
    };
    for (k, (name, var, x_desc, y_desc, db, plus, minus)) in [
        (
            "K1",
            "dT/dt",
            "rate of temperature dT/dt, °C/s",
            "K1, (°/h)/(°C/s)",
            cal.resolved.deadband_tdot,
            &cal.k1_plus,
            &cal.k1_minus,
        ),
        (
            "K2",
            "d²T/dt²",
            "second derivative of temperature d²T/dt², °C/s²",
            "K2, (°/h)/(°C/s²)",
            cal.resolved.deadband_tddot,
            &cal.k2_plus,
            &cal.k2_minus,
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let pts = points.as_ref();
        let f = figures::rate_coefficient(
            &out_dir.join(name.to_lowercase()),
            &format!("{name}± over {var}: + set (thermal acceleration) and − set (deceleration)"),
            RateAxes {
                name,
                x_desc,
                y_desc,
                deadband: db,
            },
            [
                RateSet {
                    sign: "+",
                    curve: plus,
                    points: pts.map(|p| &p[2 * k]),
                },
                RateSet {
                    sign: "−",
                    curve: minus,
                    points: pts.map(|p| &p[2 * k + 1]),
                },
            ],
        )?;
        files.extend(f.iter().cloned());
        cal_figures.push(figure(
            format!("{name}±({var})"),
            format!(
                "{name}+ and {name}− over {var}: fitted curves (dashed where held at the edge \
                 value) and the dead-band |{var}| ≤ {:.3e} left out of the fits. {source_note}",
                db
            ),
            f,
        ));
    }
    drop(points);

    Ok(ModelFigures {
        taken,
        files,
        notes,
        figures: cal_figures,
    })
}

/// The cost curves of the model's searches, when it searched.
fn regression(
    cal: &RegressionCalibration,
    logs: &[(PathBuf, Log)],
    in_sample: &[bool],
    out_dir: &Path,
) -> Result<ModelFigures> {
    let m = &cal.model;
    let mut notes = Vec::new();
    let mut files = Vec::new();
    let taken: Vec<String> = ["costs", "report"].iter().map(|s| s.to_string()).collect();
    if !logs.is_empty() && !in_sample.contains(&true) {
        notes.push(format!(
            "The model's own log ({}) is not among the logs: every log is held out.",
            crate::text::escaped(&cal.source.name, false)
        ));
    }

    // The searches.
    let mut model_figures = Vec::new();
    let lines: Vec<figures::CostLine> = m
        .searches
        .iter()
        .map(|c| figures::CostLine {
            parameter: &c.parameter,
            x: &c.x,
            rmse: &c.rmse,
            best: c.best,
            log_x: c.parameter == "lambda_s",
        })
        .collect();
    if !lines.is_empty() {
        let f = figures::cost_curves(
            &out_dir.join("costs"),
            &format!(
                "Searches of model {}: RMS residual over the values tried",
                m.spec.name
            ),
            &lines,
        )?;
        files.extend(f.iter().cloned());
        let edge: Vec<&str> = m
            .searches
            .iter()
            .filter(|c| c.at_edge)
            .map(|c| c.parameter.as_str())
            .collect();
        model_figures.push(figure(
            "Search cost curves".into(),
            format!(
                "RMS residual of the least-squares fit at each value tried for the parameters \
                 the model is not linear in (λ on a logarithmic axis; a delay per temperature \
                 band for τd(T)); the vertical line marks the value chosen.{}",
                if edge.is_empty() {
                    String::new()
                } else {
                    format!(
                        " At the edge of the searched range (the optimum may lie beyond): {}.",
                        edge.join(", ")
                    )
                }
            ),
            f,
        ));
    }

    Ok(ModelFigures {
        taken,
        files,
        notes,
        figures: model_figures,
    })
}
