//! The record of a campaign's runs as a calibration file holds it, checked on every load and
//! save: each run's numbers within what a chamber run can be ([`validate_runs`]), and the axes
//! of a unit telling of the same runs ([`check_same_runs`]). Apart from the fit because it is
//! the file's rules, not the campaign's arithmetic.

use super::RunRecord;
use crate::error::Invalid;

/// The largest bias or turn-on offset a run's record may hold, °/h: a gyro's rate range, far
/// beyond any bias.
const MAX_RECORDED_DPH: f64 = 1e7;

/// Refuses a recorded bias or offset that is no number a gyro gives.
fn plausible_rate(field: String, v: f64) -> std::result::Result<(), Invalid> {
    if v.is_finite() && v.abs() <= MAX_RECORDED_DPH {
        Ok(())
    } else {
        Err(Invalid::new(
            field,
            format!(
                "is {} °/h: a recorded bias is a finite number within ±{MAX_RECORDED_DPH:e} °/h",
                crate::number::readable(v)
            ),
        ))
    }
}

/// The most plateaus a run's record may hold (a chamber program holds tens; a hand-edited
/// file of millions would be held whole on every read).
pub const MAX_RUN_PLATEAUS: usize = 10_000;

/// The longest name a run's record may hold, characters: a run is named by its file, and no
/// file system names a file longer than 255 bytes (`NAME_MAX`); a name of a million characters
/// would be printed whole on every line that names the run.
pub const MAX_RUN_NAME_CHARS: usize = 255;

/// The furthest a run's first time stamp may lie from its clock's zero, s: 2⁵³ s (285 million
/// years), past which a time in f64 no longer counts whole seconds, so no clock a gyro is
/// logged on reaches it (a count of ms since 1970 read as s is 1.7e12).
pub const MAX_RUN_START_S: f64 = 9_007_199_254_740_992.0;

/// The longest run a record may hold, s: a year, the span past which the log reader says a
/// log's time is "longer than any chamber run"
/// ([`STATED_UNIT_LONGEST_S`](crate::log::ingest::STATED_UNIT_LONGEST_S)).
pub const MAX_RUN_DURATION_S: f64 = crate::log::ingest::STATED_UNIT_LONGEST_S;

/// Checks the runs a calibration file records: at most [`crate::log::campaign::MAX_RUNS`],
/// names (at most [`MAX_RUN_NAME_CHARS`] long) and hashes printable, no run's hash another's
/// in any case, every number finite, a run's start within [`MAX_RUN_START_S`] of its clock's
/// zero, its span at most [`MAX_RUN_DURATION_S`] and its samples no more than a gigahertz
/// gives over it, each plateau's end after its start and within its run, and a turn-on offset
/// on every run or on none.
///
/// # Errors
/// An [`Invalid`] naming the field (`source.runs[1].plateaus[0].bias_dph`).
pub fn validate_runs(runs: &[RunRecord]) -> std::result::Result<(), Invalid> {
    use crate::log::campaign::MAX_RUNS;
    use crate::number::readable;
    if runs.len() > MAX_RUNS {
        return Err(Invalid::new(
            "source.runs",
            format!(
                "holds {} runs: a campaign joins at most {MAX_RUNS}",
                runs.len()
            ),
        ));
    }
    let finite = |field: String, v: f64| {
        if v.is_finite() {
            Ok(())
        } else {
            Err(Invalid::new(field, "must be a finite number"))
        }
    };
    for (k, r) in runs.iter().enumerate() {
        let at = |f: &str| format!("source.runs[{k}].{f}");
        for (f, text) in [("name", &r.name), ("sha256", &r.sha256)] {
            // A run is named by its file, whose name may hold a blank other than the space (an
            // ideographic space): written escaped now, but as read by earlier versions, whose
            // files must still load. It is shown escaped ([`crate::text::escaped`]).
            let blank_allowed = |c: char| f == "name" && crate::text::prints_as_blank(c);
            if let Some(c) = text
                .chars()
                .find(|&c| crate::text::is_unprintable(c) && !blank_allowed(c))
            {
                return Err(Invalid::new(
                    at(f),
                    format!("holds {}", crate::text::unprintable_named(c)),
                ));
            }
        }
        let chars = r.name.chars().count();
        if chars > MAX_RUN_NAME_CHARS {
            return Err(Invalid::new(
                at("name"),
                format!(
                    "is {chars} characters long: a run is named by its file, and a file's name \
                     has at most {MAX_RUN_NAME_CHARS}"
                ),
            ));
        }
        finite(at("start_s"), r.start_s)?;
        if r.start_s.abs() > MAX_RUN_START_S {
            return Err(Invalid::new(
                at("start_s"),
                format!(
                    "is {} s: a run starts within ±2^53 s ({} s, 285 million years) of its \
                     clock's zero, where a time still counts whole seconds",
                    readable(r.start_s),
                    readable(MAX_RUN_START_S)
                ),
            ));
        }
        if !(r.duration_s.is_finite() && r.duration_s >= 0.0) {
            return Err(Invalid::new(
                at("duration_s"),
                "must be a duration in seconds",
            ));
        }
        if r.duration_s > MAX_RUN_DURATION_S {
            return Err(Invalid::new(
                at("duration_s"),
                format!(
                    "is {} s: longer than any chamber run (a year, {} s, at most, as the log \
                     reader takes a log's time to span)",
                    readable(r.duration_s),
                    readable(MAX_RUN_DURATION_S)
                ),
            ));
        }
        // A run sampled at a gigahertz, the fastest any reader takes a log's step to be,
        // holds one sample a nanosecond of its span and one more.
        let most = (r.duration_s / crate::judge::allan::MIN_TAU0_S).floor() + 1.0;
        if r.samples as f64 > most {
            return Err(Invalid::new(
                at("samples"),
                format!(
                    "is {}: a run of {} s, sampled at a gigahertz at most, holds at most {most:.0} \
                     samples",
                    r.samples,
                    readable(r.duration_s),
                ),
            ));
        }
        if let Some(c) = r.turn_on_offset_dph {
            plausible_rate(at("turn_on_offset_dph"), c)?;
        }
        if let Some((j, q)) = runs[..k]
            .iter()
            .enumerate()
            .find(|(_, q)| !r.sha256.is_empty() && q.sha256.eq_ignore_ascii_case(&r.sha256))
        {
            return Err(Invalid::new(
                at("sha256"),
                format!(
                    "is the SHA-256 of source.runs[{j}] ({}) too{}: a campaign holds each run \
                     once",
                    crate::text::escaped(&q.name, false),
                    if q.sha256 == r.sha256 {
                        ""
                    } else {
                        ", in another case of its hexadecimal digits"
                    }
                ),
            ));
        }
        if r.plateaus.len() > MAX_RUN_PLATEAUS {
            return Err(Invalid::new(
                at("plateaus"),
                format!(
                    "holds {} plateaus: a run's record holds at most {MAX_RUN_PLATEAUS}",
                    r.plateaus.len()
                ),
            ));
        }
        // Both within their bounds: the run's end and the slack are finite.
        let end_s = r.start_s + r.duration_s;
        let slack = 1e-6 * (r.start_s.abs() + r.duration_s).max(1.0);
        for (j, p) in r.plateaus.iter().enumerate() {
            let at = |f: &str| format!("source.runs[{k}].plateaus[{j}].{f}");
            finite(at("start_s"), p.start_s)?;
            finite(at("end_s"), p.end_s)?;
            finite(at("temp_c"), p.temp_c)?;
            if !(-273.15..=1000.0).contains(&p.temp_c) {
                return Err(Invalid::new(
                    at("temp_c"),
                    format!(
                        "is {} °C: no chamber holds a gyro there (-273.15 to 1000 °C)",
                        readable(p.temp_c)
                    ),
                ));
            }
            plausible_rate(at("bias_dph"), p.bias_dph)?;
            if p.end_s < p.start_s {
                return Err(Invalid::new(at("end_s"), "ends before the plateau starts"));
            }
            // Within the run's own span (to the rounding of times written in decimals).
            if p.start_s < r.start_s - slack || p.end_s > end_s + slack {
                return Err(Invalid::new(
                    at("start_s"),
                    format!(
                        "places the plateau at {} .. {} s, outside its run ({} .. {} s)",
                        readable(p.start_s),
                        readable(p.end_s),
                        readable(r.start_s),
                        readable(end_s)
                    ),
                ));
            }
        }
    }
    let with = runs.iter().position(|r| r.turn_on_offset_dph.is_some());
    let without = runs.iter().position(|r| r.turn_on_offset_dph.is_none());
    if let (Some(with), Some(without)) = (with, without) {
        return Err(Invalid::new(
            format!("source.runs[{without}].turn_on_offset_dph"),
            format!(
                "is missing, and source.runs[{with}] has one: turn-on offsets are estimated \
                 for every run of a campaign or for none (--per-run-offset)"
            ),
        ));
    }
    Ok(())
}

/// Checks that `runs`, one axis's record of a unit's campaign, tells of the same runs as
/// `first`, the first axis's: the same runs in the same order, with the same file, samples,
/// span and plateaus (their times, temperature and approach), and turn-on offsets on both or
/// on neither. Only a plateau's bias and a run's offset are each axis's own. `first_axis`
/// names the first axis in the message.
///
/// # Errors
/// An [`Invalid`] naming the field of `runs` that differs (`source.runs[1].sha256`), as the
/// caller prefixes it with the axis.
pub fn check_same_runs(
    runs: &[RunRecord],
    first: &[RunRecord],
    first_axis: &str,
) -> std::result::Result<(), Invalid> {
    let why = "the axes of a unit share the runs (their files, spans and plateaus); only a \
               plateau's bias and a run's turn-on offset are each axis's own";
    let differs = |field: String, mine: String, theirs: String| {
        Invalid::new(
            field,
            format!("differs from axis {first_axis}'s ({mine} against {theirs}): {why}"),
        )
    };
    if runs.len() != first.len() {
        return Err(Invalid::new(
            "source.runs",
            format!(
                "holds {} runs, axis {first_axis}'s {}: {why}",
                runs.len(),
                first.len()
            ),
        ));
    }
    let text = |t: &str| format!("\"{}\"", crate::text::escaped(&cut(t), false));
    let number = |v: f64| crate::number::significant(v, 17);
    for (k, (r, f)) in runs.iter().zip(first).enumerate() {
        let at = |field: &str| format!("source.runs[{k}].{field}");
        for (field, mine, theirs) in [("name", &r.name, &f.name), ("sha256", &r.sha256, &f.sha256)]
        {
            if mine != theirs {
                return Err(differs(at(field), text(mine), text(theirs)));
            }
        }
        if r.samples != f.samples {
            return Err(differs(
                at("samples"),
                r.samples.to_string(),
                f.samples.to_string(),
            ));
        }
        for (field, mine, theirs) in [
            ("start_s", r.start_s, f.start_s),
            ("duration_s", r.duration_s, f.duration_s),
        ] {
            if mine != theirs {
                return Err(differs(at(field), number(mine), number(theirs)));
            }
        }
        if r.plateaus.len() != f.plateaus.len() {
            return Err(Invalid::new(
                at("plateaus"),
                format!(
                    "holds {} plateaus, axis {first_axis}'s {}: {why}",
                    r.plateaus.len(),
                    f.plateaus.len()
                ),
            ));
        }
        for (j, (p, q)) in r.plateaus.iter().zip(&f.plateaus).enumerate() {
            let at = |field: &str| format!("source.runs[{k}].plateaus[{j}].{field}");
            for (field, mine, theirs) in [
                ("start_s", p.start_s, q.start_s),
                ("end_s", p.end_s, q.end_s),
                ("temp_c", p.temp_c, q.temp_c),
            ] {
                if mine != theirs {
                    return Err(differs(at(field), number(mine), number(theirs)));
                }
            }
            if p.approach != q.approach {
                return Err(differs(
                    at("approach"),
                    format!("{:?}", p.approach).to_lowercase(),
                    format!("{:?}", q.approach).to_lowercase(),
                ));
            }
        }
        if r.turn_on_offset_dph.is_some() != f.turn_on_offset_dph.is_some() {
            return Err(Invalid::new(
                at("turn_on_offset_dph"),
                format!(
                    "is {}, and axis {first_axis}'s runs have {}: turn-on offsets are estimated \
                     for every axis of a unit or for none",
                    if r.turn_on_offset_dph.is_some() {
                        "given"
                    } else {
                        "missing"
                    },
                    if f.turn_on_offset_dph.is_some() {
                        "theirs"
                    } else {
                        "none"
                    }
                ),
            ));
        }
    }
    Ok(())
}

/// `text` as a message quotes it: its first 80 characters, and how long it is when longer.
fn cut(text: &str) -> String {
    match text.char_indices().nth(80) {
        None => text.to_string(),
        Some((end, _)) => format!("{}… ({} characters)", &text[..end], text.chars().count()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::campaign::RunRecord;

    fn run(name: &str) -> RunRecord {
        RunRecord {
            name: name.to_string(),
            sha256: format!("{:064x}", name.len()),
            samples: 10,
            start_s: 0.0,
            duration_s: 9.0,
            plateaus: Vec::new(),
            turn_on_offset_dph: None,
        }
    }

    #[test]
    fn a_run_named_by_a_file_with_an_ideographic_space_loads_and_a_control_does_not() {
        // Earlier versions recorded a file's name as read; one holding U+3000 must still load.
        let r = validate_runs(&[run("run\u{3000}1.csv"), run("run2.csv")]);
        assert!(r.is_ok(), "{r:?}");
        let e = validate_runs(&[run("run\u{1b}[2J.csv"), run("run2.csv")]).unwrap_err();
        assert_eq!(e.field, "source.runs[0].name");
        // A Hangul filler prints as a blank too: a name may hold it as it may the space.
        let r = validate_runs(&[run("run\u{3164}.csv"), run("run2.csv")]);
        assert!(r.is_ok(), "{r:?}");
    }
}
