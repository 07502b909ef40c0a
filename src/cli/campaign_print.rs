//! What `calibrate` prints of a campaign an axis was fitted on: each run with its plateaus
//! (and turn-on offset), the bias repeatability at each shared temperature, and the thermal
//! hysteresis, as text and as JSON. Nothing for a calibration of one run.

use super::common::{CliError, fixed};
use driftlab::judge::campaign::{hysteresis, repeatability};
use driftlab::models::DriftModel;
use driftlab::models::campaign::Approach;

/// The campaign block of `--json`: `runs`, `repeatability` and `hysteresis` (each a list),
/// and the tolerance they were grouped with; `None` for a calibration of one run.
pub fn json(model: &DriftModel, tolerance_c: f64) -> Option<serde_json::Value> {
    let runs = &model.source().runs;
    if runs.is_empty() {
        return None;
    }
    Some(serde_json::json!({
        "tolerance_c": tolerance_c,
        "runs": runs,
        "repeatability": repeatability(runs, tolerance_c),
        "hysteresis": hysteresis(runs, tolerance_c),
    }))
}

/// The campaign as text, after the model's summary; nothing for a calibration of one run.
pub fn text(model: &DriftModel, tolerance_c: f64) -> Result<(), CliError> {
    let runs = &model.source().runs;
    if runs.is_empty() {
        return Ok(());
    }
    out!()?;
    out!("Campaign of {} runs:", runs.len())?;
    for (k, r) in runs.iter().enumerate() {
        out!(
            "  run {} {}: {} samples, {} h{}",
            k + 1,
            r.name,
            r.samples,
            fixed(r.duration_s / 3600.0, 2),
            match r.turn_on_offset_dph {
                Some(c) => format!(", turn-on offset {} deg/h (kept out of K0)", fixed(c, 4)),
                None => String::new(),
            }
        )?;
        for p in &r.plateaus {
            out!(
                "    {:>10} .. {:>10} s  T {:>8} degC  bias {:>9} deg/h  {}",
                driftlab::number::fixed_stamp(p.start_s),
                driftlab::number::fixed_stamp(p.end_s),
                fixed(p.temp_c, 3),
                fixed(p.bias_dph, 4),
                match p.approach {
                    Approach::Heating => "reached heating",
                    Approach::Cooling => "reached cooling",
                    Approach::Start => "where the run started",
                }
            )?;
        }
    }
    let rep = repeatability(runs, tolerance_c);
    out!(
        "Bias repeatability (plateaus within {} degC of each other's group):",
        fixed(tolerance_c, 2)
    )?;
    if rep.is_empty() {
        out!("  no temperature is held by two plateaus")?;
    }
    for g in &rep {
        out!(
            "  {:>8} degC  spread {:>8} deg/h over {} plateaus ({})",
            fixed(g.temp_c, 2),
            fixed(g.spread_dph, 4),
            g.values.len(),
            g.runs
                .iter()
                .zip(&g.values)
                .map(|(r, v)| format!("{r} {}", fixed(*v, 4)))
                .collect::<Vec<_>>()
                .join(", ")
        )?;
    }
    let hys = hysteresis(runs, tolerance_c);
    out!(
        "Thermal hysteresis (bias reached heating less reached cooling{}):",
        if runs.iter().any(|r| r.turn_on_offset_dph.is_some()) {
            ", net of the turn-on offsets"
        } else {
            ", turn-on differences between runs included (--per-run-offset takes them out)"
        }
    )?;
    if hys.is_empty() {
        out!("  no temperature is reached both heating and cooling")?;
    }
    for h in &hys {
        out!(
            "  {:>8} degC  {:>9} deg/h  (heating {} over {}, cooling {} over {})",
            fixed(h.temp_c, 2),
            fixed(h.difference_dph, 4),
            fixed(h.heating_dph, 4),
            h.heating_plateaus,
            fixed(h.cooling_dph, 4),
            h.cooling_plateaus
        )?;
    }
    Ok(())
}
