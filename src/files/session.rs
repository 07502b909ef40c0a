//! The workbench session file: everything an engineer set up, so that a calibration can be
//! reopened exactly as it was left — the log and how it was read, the validation log, every
//! choice of the recipe (plateaus included), knots moved by hand, and what was on screen.
//!
//! ```json
//! { "format": "driftlab-session", "version": 1,
//!   "session": { "log": { "path": "run7.csv", "read": { "delimiter": ";" } },
//!                "validation": null, "recipe": { ... },
//!                "merit": { "filter_s": 100, "window_s": 600 }, "view": { ... } } }
//! ```
//!
//! The session of a log of several gyro axes (a unit) is version 2: `axes` lists each axis's
//! own choices (`{ "name": "gy", "recipe": { ... } }`) and `view.axis` the
//! axis shown; `recipe` is then the first axis's. A session of one axis is written
//! as version 1, as it always was, and version-1 files keep loading.
//!
//! `merit` says how the workbench judged the calibration: its filter is the recipe's (a
//! session whose `merit.filter_s` differs is refused), its window is the session's own
//! (10 minutes when `merit` is absent). Knots set by hand are checked as a calibration's
//! values are: finite, plausible, as many as their approximation has.
//!
//! Like calibration files, sessions name their format and version, reject unknown fields and
//! are written atomically. Paths are stored relative to the session file when the log lies
//! in the same folder or below it, so a folder of logs and sessions can be moved as a whole.

use crate::error::{Error, Invalid, Result};
use crate::judge::metrics::MeritOptions;
use crate::log::accel_axes::AccelAsk;
use crate::log::ingest::ReadOptions;
use crate::log::read::InstanceChoice;
use crate::models::recipe::Recipe;
/// The knots set by hand are the model's (Vakhrameev's coefficients); the session stores them.
pub use crate::models::vakhrameev::knots::{Coefficient, KnotEdits};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The format name written into every session file.
pub const FORMAT: &str = "driftlab-session";
/// The newest session version this build writes and reads (2: a unit's axes).
pub const VERSION: u32 = 2;

/// The version of a session of one gyro axis, written as before units existed.
pub const VERSION_SINGLE: u32 = 1;

/// A log and how to read it.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LogRef {
    /// The file (relative paths are relative to the session file's folder).
    pub path: PathBuf,
    /// The column mapping, units and dialect the engineer chose in the import view.
    #[serde(default)]
    pub read: ReadOptions,
    /// Bins of this many seconds the log is averaged into after the read (`--bin`); absent:
    /// a log written in bursts is reduced to one sample per burst, any other used as read.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bin_s: Option<f64>,
    /// The gyro and temperature chosen of a drone or robot log; absent: the reader's default.
    #[serde(default, skip_serializing_if = "InstanceChoice::is_default")]
    pub instance: InstanceChoice,
    /// A campaign's runs after the first (`path`), read as it is and joined after it, in
    /// order (relative paths as `path`); absent for one log.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub more_runs: Vec<PathBuf>,
    /// The accelerometer columns and their unit chosen in the import view (`--accel-col`,
    /// `--accel-unit`); absent: every column named as an accelerometer, its unit stated or
    /// told by gravity.
    #[serde(default, skip_serializing_if = "AccelAsk::is_default")]
    pub accelerometers: AccelAsk,
}

/// What was on screen, so the session reopens where it was left.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ViewState {
    /// Visible time range of the time plots, s (`None`: the whole log).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_range_s: Option<[f64; 2]>,
    /// Whether the result plot shows the validation log rather than the calibration log.
    pub show_validation: bool,
    /// The gyro axis shown, for a unit of several (version 2).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub axis: Option<String>,
}

/// One gyro axis's own choices in the session of a unit.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AxisChoices {
    /// The axis (`gx`), as the log names it.
    pub name: String,
    /// Its recipe (the T settings and plateaus are those of every axis), with its knots placed
    /// and set by hand.
    pub recipe: Recipe,
    /// Its knot values set by hand, as sessions wrote them before the recipe held them: read
    /// into the recipe on loading ([`from_json`]), never written.
    #[serde(skip_serializing_if = "KnotEdits::is_empty")]
    pub knots: KnotEdits,
}

/// A workbench session.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Session {
    /// The calibration log.
    pub log: Option<LogRef>,
    /// A second log, held out to judge the calibration.
    pub validation: Option<LogRef>,
    /// Every choice of the calibration, the knots placed and set by hand among them.
    pub recipe: Recipe,
    /// Knot values set by hand, as sessions wrote them before the recipe held them: read into
    /// the recipe on loading ([`from_json`]), never written.
    #[serde(skip_serializing_if = "KnotEdits::is_empty")]
    pub knots: KnotEdits,
    /// How the figures of merit are computed.
    pub merit: MeritOptions,
    /// What was on screen.
    pub view: ViewState,
    /// For a unit of several gyro axes, every axis's own choices, in the log's order (empty
    /// for a log of one axis).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub axes: Vec<AxisChoices>,
    /// The log's accelerometer axes left out of the unit (turned off in the axis strip).
    /// They are in it by default, so that a file written before the workbench calibrated
    /// accelerometers opens with them, and the field is written only when they are off.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub accelerometers_off: bool,
}

impl Session {
    /// Whether this is the session of a unit of several axes (written as version 2).
    pub fn is_unit(&self) -> bool {
        !self.axes.is_empty() || self.view.axis.is_some()
    }
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SessionFile {
    format: String,
    version: u32,
    session: Session,
}

#[derive(Deserialize)]
struct Header {
    format: Option<String>,
    version: Option<u64>,
}

impl Session {
    /// Paths made relative to `dir` where the file lies in it or below it (for saving).
    pub fn relative_to(&self, dir: &Path) -> Session {
        let rel = |r: &Option<LogRef>| {
            let rel = |p: &PathBuf| {
                p.strip_prefix(dir)
                    .map(Path::to_path_buf)
                    .unwrap_or_else(|_| p.clone())
            };
            r.as_ref().map(|r| LogRef {
                path: rel(&r.path),
                more_runs: r.more_runs.iter().map(rel).collect(),
                ..r.clone()
            })
        };
        Session {
            log: rel(&self.log),
            validation: rel(&self.validation),
            ..self.clone()
        }
    }

    /// Relative paths resolved against `dir` (after loading).
    pub fn resolved_in(mut self, dir: &Path) -> Session {
        let resolve = |path: &mut PathBuf| {
            if path.is_relative() {
                let p = dir.join(&*path);
                *path = std::fs::canonicalize(&p).unwrap_or(p);
            }
        };
        for r in [&mut self.log, &mut self.validation].into_iter().flatten() {
            resolve(&mut r.path);
            r.more_runs.iter_mut().for_each(resolve);
        }
        self
    }
}

/// The session as the JSON text of a session file.
pub fn to_json(session: &Session) -> String {
    let file = SessionFile {
        format: FORMAT.into(),
        version: if session.is_unit() {
            VERSION
        } else {
            VERSION_SINGLE
        },
        session: session.clone(),
    };
    serde_json::to_string_pretty(&file).unwrap_or_default() + "\n"
}

/// Reads a session from JSON text; `path` names the file in messages. Relative log paths are
/// left as written (see [`Session::resolved_in`]).
pub fn from_json(path: &Path, text: &str) -> Result<Session> {
    let err = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let header: Header =
        serde_json::from_str(text).map_err(|e| err(format!("not a session file: {e}")))?;
    match header.format.as_deref() {
        Some(FORMAT) => {}
        Some(other) => return Err(err(format!("format is \"{other}\", expected \"{FORMAT}\""))),
        None => return Err(err(format!("no \"format\" field: not a {FORMAT} file"))),
    }
    match header.version {
        Some(v) if v == VERSION as u64 || v == VERSION_SINGLE as u64 => {}
        Some(v) => {
            return Err(err(format!(
                "version {v} is not supported by this driftlab (reads versions \
                 {VERSION_SINGLE} and {VERSION})"
            )));
        }
        None => return Err(err("no \"version\" field".into())),
    }
    let mut file: SessionFile = serde_json::from_str(text).map_err(|e| err(e.to_string()))?;
    if file.version == VERSION_SINGLE && file.session.is_unit() {
        return Err(err(
            "a version-1 session holds one axis: \"axes\" and \"view.axis\" need version 2".into(),
        ));
    }
    file.session
        .recipe
        .validate()
        .map_err(|e| err(format!("recipe: {e}")))?;
    for (k, a) in file.session.axes.iter().enumerate() {
        if a.name.trim().is_empty() {
            return Err(err(format!("axes[{k}]: an axis needs a name")));
        }
        if file.session.axes[..k].iter().any(|b| b.name == a.name) {
            return Err(err(format!("axes[{k}]: \"{}\" names two axes", a.name)));
        }
        a.recipe
            .validate()
            .map_err(|e| err(format!("axes[{}].recipe: {e}", a.name)))?;
        a.knots
            .check(&a.recipe)
            .map_err(|e| err(format!("axes[{}].knots.{e}", a.name)))?;
    }
    let session = &mut file.session;
    session
        .knots
        .check(&session.recipe)
        .map_err(|e| err(format!("knots.{e}")))?;
    // Values set by hand that an older session kept beside its recipe belong to the recipe.
    let both = |at: String, key: &str| {
        err(format!(
            "{at}knots.{key}: knot values set both here (where older sessions kept them) and in \
             {at}recipe.{key}.values, and they differ: keep one of the two"
        ))
    };
    let knots = std::mem::take(&mut session.knots);
    knots
        .fold_into(&mut session.recipe)
        .map_err(|key| both(String::new(), key))?;
    for a in &mut session.axes {
        let knots = std::mem::take(&mut a.knots);
        let at = format!("axes[{}].", a.name);
        knots
            .fold_into(&mut a.recipe)
            .map_err(|key| both(at.clone(), key))?;
    }
    if merit_given(text) {
        check_merit(&session.merit, &session.recipe).map_err(|e| err(format!("merit.{e}")))?;
    } else {
        session.merit = MeritOptions {
            filter_s: session.recipe.filter_s,
            ..MeritOptions::default()
        };
    }
    Ok(file.session)
}

/// Whether the session text gives `merit` (else the workbench's own are taken).
fn merit_given(text: &str) -> bool {
    serde_json::from_str::<serde_json::Value>(text)
        .ok()
        .and_then(|v| v.get("session")?.get("merit").cloned())
        .is_some()
}

/// Refuses a session's figures of merit that the workbench would not use as written: a filter
/// other than the recipe's (the workbench filters the figures as the recipe filters Ω), a
/// window that is not a number of seconds between 1 µs and 11.6 days.
fn check_merit(merit: &MeritOptions, recipe: &Recipe) -> std::result::Result<(), Invalid> {
    use crate::models::recipe::{MAX_WINDOW_S, MIN_WINDOW_S};
    use crate::number::readable;
    if merit.filter_s != recipe.filter_s {
        return Err(Invalid::new(
            "filter_s",
            format!(
                "{} s differs from the recipe's filter_s ({} s): the workbench filters the \
                 figures of merit as the recipe filters Ω; remove it or write the recipe's",
                readable(merit.filter_s),
                readable(recipe.filter_s)
            ),
        ));
    }
    let w = merit.window_s;
    if !(w.is_finite() && (MIN_WINDOW_S..=MAX_WINDOW_S).contains(&w)) {
        return Err(Invalid::new(
            "window_s",
            format!(
                "{} s: a window of the figures of merit is between {} s and {} s",
                readable(w),
                readable(MIN_WINDOW_S),
                readable(MAX_WINDOW_S)
            ),
        ));
    }
    Ok(())
}

/// Writes a session file atomically, with log paths relative to its folder where possible.
pub fn save(path: &Path, session: &Session) -> Result<()> {
    let dir = path.parent().unwrap_or(Path::new(""));
    let dir = std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf());
    let text = to_json(&session.relative_to(&dir));
    crate::files::atomic::write_bytes(path, text.as_bytes()).map_err(|e| Error::io(path, e))
}

/// Reads a session file, resolving relative log paths against its folder.
pub fn load(path: &Path) -> Result<Session> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let text = String::from_utf8(bytes).map_err(|e| Error::File {
        path: path.to_path_buf(),
        message: format!("not UTF-8 text: {e}"),
    })?;
    let dir = path.parent().unwrap_or(Path::new(""));
    Ok(from_json(path, &text)?.resolved_in(dir))
}
