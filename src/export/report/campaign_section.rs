//! The campaign an axis was calibrated on, as its report page shows it: the runs, the bias
//! repeatability at each temperature two plateaus share, and the thermal hysteresis, the same
//! figures `driftlab calibrate` prints (`judge::campaign`), read from the calibration's record
//! of the runs alone. Apart from the page because the page holds it once per axis (the axes'
//! records differ in bias and offset only), and nothing at all for a calibration of one run,
//! whose page stays as it was.
//!
//! The per-run figures are the logs' own: a log given to the report whose file's SHA-256 is a
//! run's is that run (in-sample, as `SourceInfo::judge_run` tells it), and its section is
//! marked with the run's number ([`run_of`]); a run whose file was not given is said so in the
//! runs table.

use super::ReportSummary;
use super::html::{Depth, fmt_dph, heading};
use crate::judge::campaign::{hysteresis, repeatability};
use crate::models::campaign::RunRecord;
use maud::{Markup, html};

/// The number (from 1) of the run of `runs` whose file's SHA-256 is `sha256`, or `None`
/// (no hash, or no such run).
pub(super) fn run_of(runs: &[RunRecord], sha256: &str) -> Option<usize> {
    if sha256.is_empty() {
        return None;
    }
    runs.iter()
        .position(|r| !r.sha256.is_empty() && r.sha256.eq_ignore_ascii_case(sha256))
        .map(|k| k + 1)
}

/// A run's name as the page shows it: a character that would reorder or forge the text
/// around it written as its escape (the template escapes the markup).
fn shown(name: &str) -> String {
    crate::text::escaped(name, false).into_owned()
}

/// A temperature as the section prints it, °C.
fn fmt_c(t: f64) -> String {
    format!("{t:.2}")
}

/// The campaign section of an axis whose calibration records `runs`, at depth `d`, the
/// plateaus grouped within `tolerance_c`; nothing when it records none (one run).
pub(super) fn body(runs: &[RunRecord], s: &ReportSummary, tolerance_c: f64, d: Depth) -> Markup {
    if runs.is_empty() {
        return html! {};
    }
    let rep = repeatability(runs, tolerance_c);
    let hys = hysteresis(runs, tolerance_c);
    let net = runs.iter().any(|r| r.turn_on_offset_dph.is_some());
    html! {
        (heading(d.section, html! { "Campaign of " (runs.len()) " runs" }))
        p {
            "The calibration was fitted on several chamber runs of one gyro, each smoothed, \
             differentiated and its plateaus found on its own. "
            @if net {
                "Each run's turn-on offset (a constant of the run no temperature explains) was \
                 estimated jointly with K0 and kept out of it; it is never applied to another log."
            } @else {
                "No turn-on offset was estimated: the runs' turn-on differences are in K0's points."
            }
        }
        "\n"
        (runs_table(runs, s))
        (heading(d.part, html! { "Bias repeatability" }))
        p {
            "The spread (largest less smallest plateau bias) at each temperature two plateaus \
             share, plateaus within " (fmt_c(tolerance_c)) " °C of each other's group; the \
             plateaus' mean raw output, turn-on offsets included."
        }
        "\n"
        @if rep.is_empty() {
            p class="campaign-none" { "No temperature is held by two plateaus." } "\n"
        } @else {
            table class="repeatability" {
                "\n"
                tr { th { "T, °C" } th { "spread, °/h" } th { "plateaus (run: bias, °/h)" } }
                "\n"
                @for g in &rep {
                    tr {
                        td class="num" { (fmt_c(g.temp_c)) }
                        td class="num" { (fmt_dph(g.spread_dph)) }
                        td {
                            @for (k, (r, v)) in g.runs.iter().zip(&g.values).enumerate() {
                                @if k > 0 { ", " }
                                (shown(r)) ": " (fmt_dph(*v))
                            }
                        }
                    }
                    "\n"
                }
            }
            "\n"
        }
        (heading(d.part, html! { "Thermal hysteresis" }))
        p {
            "Bias reached heating less reached cooling at each temperature reached both ways \
             (a run's starting plateau is reached neither way), "
            @if net {
                "net of the turn-on offsets."
            } @else {
                "turn-on differences between runs included (calibrate with --per-run-offset to \
                 take them out)."
            }
        }
        "\n"
        @if hys.is_empty() {
            p class="campaign-none" { "No temperature is reached both heating and cooling." } "\n"
        } @else {
            table class="hysteresis" {
                "\n"
                tr {
                    th { "T, °C" } th { "heating − cooling, °/h" } th { "heating mean, °/h (n)" }
                    th { "cooling mean, °/h (n)" }
                }
                "\n"
                @for h in &hys {
                    tr {
                        td class="num" { (fmt_c(h.temp_c)) }
                        td class="num" { (fmt_dph(h.difference_dph)) }
                        td class="num" {
                            (fmt_dph(h.heating_dph)) " (" (h.heating_plateaus) ")"
                        }
                        td class="num" {
                            (fmt_dph(h.cooling_dph)) " (" (h.cooling_plateaus) ")"
                        }
                    }
                    "\n"
                }
            }
            "\n"
        }
    }
}

/// A row per run: its name and file, its span and plateaus, its turn-on offset, and which log
/// given to the report is it.
fn runs_table(runs: &[RunRecord], s: &ReportSummary) -> Markup {
    html! {
        table class="campaign-runs" {
            "\n"
            tr {
                th { "run" } th { "file" } th { "SHA-256" } th { "samples" } th { "duration, h" }
                th { "plateaus" } th { "turn-on offset, °/h" } th { "in this report" }
            }
            "\n"
            @for (k, r) in runs.iter().enumerate() {
                @let given = s.logs.iter().find(|l| run_of(runs, &l.sha256) == Some(k + 1));
                tr {
                    td class="num" { (k + 1) }
                    td { (shown(&r.name)) }
                    td { code title=(r.sha256) { (r.sha256.get(..12).unwrap_or(&r.sha256)) } }
                    td class="num" { (r.samples) }
                    td class="num" { (crate::number::fixed(r.duration_s / 3600.0, 2)) }
                    td class="num" { (r.plateaus.len()) }
                    td class="num" {
                        @match r.turn_on_offset_dph {
                            Some(c) => (fmt_dph(c)),
                            None => "not estimated",
                        }
                    }
                    td {
                        @match given {
                            Some(l) => { "log " (l.name) " (in-sample)" }
                            None => "not given to the report",
                        }
                    }
                }
                "\n"
            }
        }
        "\n"
    }
}
