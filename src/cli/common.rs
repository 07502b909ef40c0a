//! Pieces every subcommand shares: how to read a log, progress bars, number formatting, and
//! the writes to standard output and error.
//!
//! Nothing here prints with `println!`: it panics when standard output is full or closed
//! (`driftlab inspect run.csv > /dev/full`, `| head -1`). [`out!`] returns the error instead,
//! and `main` ends the command with one line and a non-zero status, or quietly when the reader
//! of a pipe has closed it, as Unix tools do. [`note!`] writes a warning or status line to
//! standard error, where a failure has nowhere left to be told and is let go.
//!
//! Every [`out!`], [`note!`] and error is one line, and is printed as [`shown`] shows a name:
//! a line break or a tab inside it (a file name, a column name, a calibration's source name,
//! an engine message quoting one) is written as its escape, so no name can start a line of
//! its own that reads as driftlab's (`error: calibration REJECTED`). Several lines are several
//! calls; only [`print_json`] and a file written to standard output keep their line breaks.

pub use super::figures::{
    check_merit, check_merit_to_judge, comparison_cells_in, figure, figure_in, fixed, num,
    print_evaluation, print_evaluation_in, ratio, raw_to_corrected_in,
};
use driftlab::Log;
use driftlab::log::ingest::{ColumnRef, Input, Needs, RateUnit, ReadOptions, TimeUnit};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

/// Why a command stopped: a message for standard error, or standard output closed by the
/// program reading it.
#[derive(Debug)]
pub enum CliError {
    /// Printed by `main` after `error: `, with exit status 1.
    Message(String),
    /// The reader of standard output closed it (`| head -1`): the command stops without a
    /// word, with the status a shell gives a program a closed pipe stopped (141).
    ClosedOutput,
    /// The command did its work and printed it, and ends with this status to say what it
    /// found (`lot`: a unit failed, or could not be calibrated), with nothing more to print.
    Status(u8),
}

impl From<String> for CliError {
    fn from(m: String) -> CliError {
        CliError::Message(m)
    }
}

impl From<&str> for CliError {
    fn from(m: &str) -> CliError {
        CliError::Message(m.to_string())
    }
}

/// The engine's refusal in the command line's words: the read settings it names are named by
/// their flags ([`super::log_source::in_flags`]).
impl From<driftlab::Error> for CliError {
    fn from(e: driftlab::Error) -> CliError {
        CliError::Message(super::log_source::in_flags(&e.to_string()))
    }
}

impl From<driftlab::error::Invalid> for CliError {
    fn from(e: driftlab::error::Invalid) -> CliError {
        CliError::Message(super::log_source::in_flags(&e.to_string()))
    }
}

/// The error of a write to standard output, as the command ends with it.
pub fn stdout_error(e: std::io::Error) -> CliError {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        CliError::ClosedOutput
    } else {
        CliError::Message(format!("standard output: {e}"))
    }
}

/// Writes formatted text as one line to standard output, as [`shown`] shows it (a line break
/// or tab inside it escaped), and a line end.
///
/// # Errors
/// A full disk or a closed pipe, as [`stdout_error`] names them.
pub fn write_out(args: std::fmt::Arguments<'_>) -> Result<(), CliError> {
    write_stdout(&shown(&std::fmt::format(args)))
}

/// Writes a text of several lines of its own (pretty JSON, whose strings hold no raw line
/// break) to standard output, as [`terminal_text`] shows it, and a line end.
///
/// # Errors
/// As [`write_out`].
fn write_out_lines(text: &str) -> Result<(), CliError> {
    write_stdout(&terminal_text(text))
}

fn write_stdout(text: &str) -> Result<(), CliError> {
    let mut o = std::io::stdout().lock();
    o.write_all(text.as_bytes())
        .and_then(|()| o.write_all(b"\n"))
        .map_err(stdout_error)
}

/// Flushes standard output, whose last bytes may still be buffered when a command ends.
///
/// # Errors
/// As [`write_out`].
pub fn flush_out() -> Result<(), CliError> {
    std::io::stdout().lock().flush().map_err(stdout_error)
}

/// Writes one line to standard error, as [`shown`] shows it (a line break or tab inside it
/// escaped), letting a failure go: there is nowhere left to report it.
pub fn write_err(args: std::fmt::Arguments<'_>) {
    let text = std::fmt::format(args);
    let text = cut_to_read(&text);
    let mut e = std::io::stderr().lock();
    let _ = e
        .write_all(shown(&text).as_bytes())
        .and_then(|()| e.write_all(b"\n"));
}

/// The most characters of a message or warning shown: one quoting a 5,000-character column
/// name, or listing thousands, is cut, and says how long it was.
const MAX_MESSAGE_CHARS: usize = 2000;

/// `text` cut to [`MAX_MESSAGE_CHARS`], with its full length said, when longer.
fn cut_to_read(text: &str) -> std::borrow::Cow<'_, str> {
    match text.char_indices().nth(MAX_MESSAGE_CHARS) {
        None => std::borrow::Cow::Borrowed(text),
        Some((end, _)) => std::borrow::Cow::Owned(format!(
            "{} … (cut here: {} characters in all)",
            &text[..end],
            text.chars().count()
        )),
    }
}

/// A text that came from a file (a column name, a ROS topic, a gyro id, a file name) as a
/// terminal is to show it: every character a terminal would obey rather than print (C0 and
/// C1 controls, ESC and DEL among them, line breaks and tabs too) and every bidirectional
/// override that would reorder what follows, written as its visible escape (`\u001b`). Every
/// line a command prints goes through this whole ([`write_out`], [`write_err`]), so that a
/// name's line breaks cannot start a line of their own.
pub fn shown(s: &str) -> std::borrow::Cow<'_, str> {
    escaped(s, false)
}

/// A whole text of several lines a command prints, as [`shown`] but with its own line breaks
/// and tabs kept: pretty JSON (whose strings escape their own), a file written to standard
/// output.
pub fn terminal_text(s: &str) -> std::borrow::Cow<'_, str> {
    escaped(s, true)
}

fn escaped(s: &str, keep_lines: bool) -> std::borrow::Cow<'_, str> {
    driftlab::text::escaped(s, keep_lines)
}

/// `println!` that returns the error of a full or closed standard output instead of
/// panicking: `out!("{x}")?`.
macro_rules! out {
    () => {
        $crate::cli::common::write_out(format_args!(""))
    };
    ($($arg:tt)*) => {
        $crate::cli::common::write_out(format_args!($($arg)*))
    };
}

/// `eprintln!` that never panics (standard error full or closed is let go).
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::cli::common::write_err(format_args!($($arg)*))
    };
}

/// Column mapping and format options, on every command that reads a log.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct LogArgs {
    /// Time column: a header name or a 1-based index (default: found by name).
    #[arg(long, value_name = "NAME|N")]
    pub time_col: Option<String>,
    /// Gyro rate column: a header name or a 1-based index (default: found by name). Repeat it
    /// for the axes of a multi-axis unit whose names do not say they are rates (`calibrate`
    /// then fits those axes).
    #[arg(long, value_name = "NAME|N")]
    pub rate_col: Vec<String>,
    /// Calibration temperature column: a header name or a 1-based index (default: the first
    /// temperature column).
    #[arg(long, value_name = "NAME|N")]
    pub temp_col: Option<String>,
    /// Unit of the rate column: deg/h (dph), deg/s (dps), mdeg/s (mdps) or rad/s (default: from the header, else deg/h).
    #[arg(long, value_name = "UNIT")]
    pub rate_unit: Option<String>,
    /// Unit of the time column: s, ms, us, ns, min, h or samples (default: from the header, else s).
    #[arg(long, value_name = "UNIT")]
    pub time_unit: Option<String>,
    /// Sampling rate in Hz, for a time column in samples or a log without time.
    #[arg(long, value_name = "HZ")]
    pub sample_rate: Option<f64>,
    /// Field separator: ',', ';', 'tab' or 'space' (default: sniffed).
    #[arg(long, value_name = "SEP")]
    pub delimiter: Option<String>,
    /// Numbers use a decimal comma (default: sniffed).
    #[arg(long)]
    pub decimal_comma: bool,
    /// Average the log into bins of S seconds before anything else (for 100 Hz–2 kHz IMU
    /// logs). Without it, a log written in bursts is reduced to one sample per burst.
    #[arg(long, value_name = "S")]
    pub bin: Option<f64>,
    /// Which gyro of a drone or robot log (`log_source.rs`).
    #[command(flatten)]
    pub format: super::log_source::FormatArgs,
    /// Accelerometer column, a header name or a 1-based index (repeatable): read as an
    /// accelerometer axis, beside the gyro axes (default: the columns whose names say so,
    /// acc_x, ax_g, accel_x_m_s2). calibrate, apply, evaluate, report and allan take it.
    #[arg(long, value_name = "NAME|N")]
    pub accel_col: Vec<String>,
    /// Unit of the accelerometer columns whose names state none: g, mg or m/s2 (default:
    /// told by the magnitude of gravity on them).
    #[arg(long, value_name = "UNIT")]
    pub accel_unit: Option<String>,
}

impl LogArgs {
    /// The engine's read options for these arguments.
    pub fn options(&self) -> Result<ReadOptions, String> {
        let col = |s: &Option<String>| s.as_deref().map(|v| v.parse::<ColumnRef>()).transpose();
        let delimiter = match self.delimiter.as_deref() {
            None => None,
            Some("tab" | "\\t" | "\t") => Some(b'\t'),
            Some("space" | "whitespace" | " ") => Some(b' '),
            Some(s) if s.len() == 1 => Some(s.as_bytes()[0]),
            Some(s) => return Err(format!("--delimiter \"{s}\": use ',', ';', tab or space")),
        };
        Ok(ReadOptions {
            time_col: col(&self.time_col).map_err(|e| format!("--time-col: {e}"))?,
            rate_col: col(&self.rate_col.first().cloned())
                .map_err(|e| format!("--rate-col: {e}"))?,
            axis_cols: self.rate_col[self.rate_col.len().min(1)..]
                .iter()
                .map(|v| v.parse::<ColumnRef>())
                .collect::<Result<_, _>>()
                .map_err(|e| format!("--rate-col: {e}"))?,
            temp_col: col(&self.temp_col).map_err(|e| format!("--temp-col: {e}"))?,
            rate_unit: self
                .rate_unit
                .as_deref()
                .map(|s| s.parse::<RateUnit>())
                .transpose()
                .map_err(|e| format!("--rate-unit: {e}"))?,
            time_unit: self
                .time_unit
                .as_deref()
                .map(|s| s.parse::<TimeUnit>())
                .transpose()
                .map_err(|e| format!("--time-unit: {e}"))?,
            sample_rate_hz: self.sample_rate,
            delimiter,
            decimal_comma: self.decimal_comma.then_some(true),
            has_header: None,
            skip_extras: false,
        })
    }

    /// Opens a log given on the command line: `-` is standard input, and a FIFO or a device
    /// is read once, whole ([`Input`]); a file is read later from its path.
    pub fn open(&self, path: &Path) -> Result<Input, String> {
        Input::open(path).map_err(|e| e.to_string())
    }

    /// Reads only the time, rate and temperature columns of a log (for the commands that use
    /// nothing else: the other columns are neither parsed nor held).
    pub fn read_columns(&self, input: &Input) -> Result<Log, String> {
        let opts = ReadOptions {
            skip_extras: true,
            ..self.options()?
        };
        self.read_with(input, &opts)
    }

    /// Reads the columns every axis of `unit` needs: only the rate and temperature columns
    /// when no axis's model reads anything else (the others are neither parsed nor held).
    pub fn read_for(
        &self,
        input: &Input,
        unit: &driftlab::models::UnitCalibration,
    ) -> Result<Log, String> {
        let plain = unit
            .axes
            .iter()
            .all(|ax| matches!(ax.model.inputs(), (None, c) if c.is_empty()));
        let log = if unit.has_accelerometers() {
            self.read_with_accelerometers(input, unit, plain)?
        } else {
            self.refuse_accel_without(unit)?;
            if plain {
                self.read_columns(input)?
            } else {
                self.read(input)?
            }
        };
        if unit.is_unit() {
            self.refuse_rate_cols_beside(unit, &log)?;
        }
        Ok(log)
    }

    /// Refuses a `--rate-col` that names no axis of `unit` in `log`: a unit's axes are found
    /// by their names, so such a column would be read as a rate that nothing corrects, and
    /// the column it was (a temperature) taken from the roles the unit reads.
    fn refuse_rate_cols_beside(
        &self,
        unit: &driftlab::models::UnitCalibration,
        log: &Log,
    ) -> Result<(), String> {
        let unit_axes: Vec<String> = unit
            .axes
            .iter()
            .filter_map(|ax| log.matching_axis(&ax.name, &ax.rate_column))
            .collect();
        let missing: Vec<&str> = unit
            .axes
            .iter()
            .filter(|ax| log.matching_axis(&ax.name, &ax.rate_column).is_none())
            .map(|ax| ax.name.as_str())
            .collect();
        if !self.rate_col.is_empty() && !missing.is_empty() {
            return Err(format!(
                "--rate-col: the calibration is a unit of axes {}, and with the columns given \
                 the log has none for axis {}: give the columns of every axis of the unit, or \
                 leave --rate-col out",
                unit.axis_names().join(", "),
                missing.join(", ")
            ));
        }
        for given in &self.rate_col {
            let column = match given.parse::<usize>() {
                Ok(k) => log
                    .info
                    .columns
                    .iter()
                    .find(|c| c.index == k)
                    .map(|c| c.name.clone())
                    .unwrap_or_else(|| given.clone()),
                Err(_) => given.clone(),
            };
            let axis = log.find_axis(&column);
            if !axis.as_ref().is_some_and(|a| unit_axes.contains(a)) {
                return Err(format!(
                    "--rate-col {given}: the calibration is a unit of axes {}, found in the log \
                     by their names or their rate columns' names; column \"{}\" is none of them \
                     (leave --rate-col out, or give the columns of the unit's axes)",
                    unit.axis_names().join(", "),
                    column.escape_debug()
                ));
            }
        }
        // A unit corrects every axis it has: fewer columns than its axes would pick some
        // of them, and the others would still be corrected from the log's own columns.
        if !self.rate_col.is_empty() && self.rate_col.len() < unit.axes.len() {
            return Err(format!(
                "--rate-col {}: the calibration is a unit of {} axes ({}), and corrects every \
                 one: give one --rate-col for each of its axes, or leave --rate-col out",
                self.rate_col.join(", --rate-col "),
                unit.axes.len(),
                unit.axis_names().join(", ")
            ));
        }
        Ok(())
    }

    /// Reads a log, with a progress bar on an interactive terminal.
    pub fn read(&self, input: &Input) -> Result<Log, String> {
        self.read_with(input, &self.options()?)
    }

    /// Reads what a command `needs` of a log: the extra columns it uses (the others are
    /// neither parsed nor held), and whether it must have a temperature.
    pub fn read_needing(&self, input: &Input, needs: &Needs) -> Result<Log, String> {
        let log = self.read_plain(input, &self.options()?, needs)?;
        self.resampled(log)
    }

    /// Reads a log as it was recorded, neither binned nor reduced to its bursts (`inspect`,
    /// which describes the file), unless `--bin` asks for bins.
    pub fn read_recorded(&self, input: &Input) -> Result<Log, String> {
        let log = self.read_plain(input, &self.options()?, &Needs::default())?;
        match self.bin {
            Some(_) => self.resampled(log),
            None => Ok(log),
        }
    }

    /// Reads what a command `needs` of a log as it was recorded, before
    /// [`LogArgs::resampled`] bins it (for a command that needs the recorded rate as well as
    /// the binned log).
    pub fn read_unresampled(&self, input: &Input, needs: &Needs) -> Result<Log, String> {
        self.read_plain(input, &self.options()?, needs)
    }

    fn read_with(&self, input: &Input, opts: &ReadOptions) -> Result<Log, String> {
        let log = self.read_plain(input, opts, &Needs::default())?;
        self.resampled(log)
    }

    /// The log averaged into bins (--bin) or one sample per burst, before anything else.
    pub fn resampled(&self, log: Log) -> Result<Log, String> {
        let (log, note) = driftlab::log::resample::prepare(log, self.bin)
            .map_err(|e| super::log_source::in_flags(&e.to_string()))?;
        if let Some(note) = note {
            note!("note: {}: {note}", log.source);
        }
        Ok(log)
    }

    fn read_plain(&self, input: &Input, opts: &ReadOptions, needs: &Needs) -> Result<Log, String> {
        // A drone or robot log, told by its first bytes (read from its file).
        if let Input::Path(path) = input
            && let Some((log, _)) =
                super::log_source::read_drone_log(self, path, opts, needs.temperature)?
        {
            return Ok(log);
        }
        let read = |needs: &Needs| {
            let bar = progress_bar(&format!("reading {}", input.name()));
            let log = input
                .read_needing(opts, needs, &|f| {
                    if let Some(b) = &bar {
                        b.set_position((f * 1000.0) as u64);
                    }
                    true
                })
                .map_err(|e| super::log_source::in_flags(&e.to_string()));
            if let Some(b) = bar {
                b.finish_and_clear();
            }
            log
        };
        let mut log = read(needs)?;
        // A channel asked for by name that the log does not hold: read again with every
        // column, so that the message that says so lists every channel the log has.
        if let Some(kept) = &needs.extras
            && kept.names.iter().any(|n| log.channel(n).is_none())
        {
            log = read(&Needs {
                extras: None,
                ..needs.clone()
            })?;
        }
        super::log_source::problems_in_flags(&mut log);
        print_problems(&log.source, &log.info.problems);
        Ok(log)
    }
}

/// Prints the problems of the log read from `source`, each a warning with its line and column
/// when it has them, on standard error.
pub fn print_problems(source: &str, problems: &[driftlab::log::Problem]) {
    for p in problems {
        // A problem of a whole column has no line.
        let place = match (p.line, p.column) {
            (0, Some(c)) => format!(" column {c}"),
            (0, None) => String::new(),
            (l, Some(c)) => format!("{l}:{c}"),
            (l, None) => l.to_string(),
        };
        let times = p.times();
        note!("warning: {source}:{place}: {}{times}", p.message);
    }
}

/// An engine error about the log `source`, named once: `FILE: why` (the fit's own messages
/// already start with the file; the others do not).
pub fn about(source: &str, e: impl std::fmt::Display) -> String {
    let m = e.to_string();
    if m.starts_with(&format!("{source}: ")) {
        m
    } else {
        format!("{source}: {m}")
    }
}

/// A fit's error about the log `source`, in the command line's words: the plateaus the engine
/// asks to be marked are given with `--plateau`; a setting refused is named as `setting`
/// words it (by its option, [`in_option_words`], or by the recipe file that gave it).
pub fn fit_failed(
    source: &str,
    e: &driftlab::Error,
    setting: &dyn Fn(&driftlab::error::Invalid) -> String,
) -> String {
    let m = match e {
        driftlab::Error::Invalid(i) => about(source, setting(i)),
        _ => about(source, e),
    };
    use driftlab::models::FitError;
    // The options that get around a fit's refusal, named after the engine's words.
    let options = match e {
        driftlab::Error::Fit(f) => match f.innermost() {
            FitError::NoK0Plateaus => Some("--plateau START:END"),
            FitError::NoRateHistory { .. } => Some("--smooth, --step-h"),
            FitError::DelayBeyondLog { .. } => Some("--delay"),
            FitError::NotStatic { .. } => Some("--axis-model AXIS=poly-t3, or --model of one"),
            FitError::FrozenRate { axis, .. } if !axis.is_empty() => {
                Some("calibrate the other axes: --axes")
            }
            _ => None,
        },
        _ => None,
    };
    match options {
        Some(o) => format!("{m} ({o})"),
        None => m,
    }
}

/// Every file a command reads, each with what it is in words ("the log", "the recipe of axis
/// gx (--axis-recipe)"): what none of its outputs may be. Each command gives the whole list
/// (its logs, calibrations, recipes, the files of other options) to [`refuse_outputs`] or
/// [`refuse_folder_over`] before it reads or writes anything.
#[derive(Debug, Default)]
pub struct Reads<'a> {
    files: Vec<(String, &'a Path)>,
}

impl<'a> Reads<'a> {
    /// A list that starts with the file at `path`, read as `what` (a command's calibration).
    pub fn of(what: impl Into<String>, path: &'a Path) -> Reads<'a> {
        let mut reads = Reads::default();
        reads.add(what, path);
        reads
    }

    /// The file at `path`, read as `what`. Standard input (`-`) is no file and is left out.
    pub fn add(&mut self, what: impl Into<String>, path: &'a Path) -> &mut Self {
        if path != Path::new("-") {
            self.files.push((what.into(), path));
        }
        self
    }

    /// The files read at `paths`, each as `what`.
    pub fn add_all(&mut self, what: &str, paths: &'a [PathBuf]) -> &mut Self {
        for p in paths {
            self.add(what, p);
        }
        self
    }
}

/// Refuses, before anything is read, a stream given for two of a command's `logs`: standard
/// input (`-`) twice, or one FIFO or device by two paths. A stream gives its bytes once: the
/// second read of standard input found nothing ("the file is empty"), and the second open of a
/// FIFO waited for a writer for ever.
///
/// # Errors
/// The stream named, and how to give it twice: as a file.
pub fn refuse_stream_twice(logs: &[&Path]) -> Result<(), CliError> {
    let dash = Path::new("-");
    if logs.iter().filter(|p| **p == dash).count() > 1 {
        return Err(CliError::Message(
            "standard input (`-`) can be given for one log only: it is read once, whole; save \
             it to a file to give it twice"
                .into(),
        ));
    }
    let stream = |p: &Path| std::fs::metadata(p).is_ok_and(|m| !m.is_file() && !m.is_dir());
    for (k, log) in logs.iter().enumerate() {
        if *log == dash || !stream(log) {
            continue;
        }
        if let Some(first) = logs[..k]
            .iter()
            .find(|p| driftlab::files::atomic::is_same_file(log, p))
        {
            return Err(CliError::Message(format!(
                "{} is given for two logs (as {}): a FIFO or a device can be read once; save \
                 what it gives to a file to give it twice",
                log.display(),
                first.display()
            )));
        }
    }
    Ok(())
}

/// The calibration file at `path`, of one axis or a unit, in the words its loader gives.
///
/// # Errors
/// What the loader refuses (an unreadable, malformed or hand-edited file), naming the file.
pub fn load_calibration(path: &Path) -> Result<driftlab::UnitCalibration, CliError> {
    Ok(driftlab::files::calibration::load_unit(path).map_err(|e| e.to_string())?)
}

/// Refuses, before anything is read or written, an output (each with the option that gives
/// it) that is `-`, that is one of the files the command `reads` (the same file by any path:
/// a link, a hard link, `./`), or that is another of the outputs.
///
/// `-` is standard input where a log is read; as an output it would make a file named `-`,
/// so it is refused by every command whose output is a file (`export`, which writes to
/// standard output, takes `-` as it before this is asked).
///
/// # Errors
/// The first output refused, named with its option, and what it would destroy.
pub fn refuse_outputs(outputs: &[(&str, &Path)], reads: &Reads<'_>) -> Result<(), CliError> {
    for (k, (option, output)) in outputs.iter().enumerate() {
        if *output == Path::new("-") {
            return Err(dash_refused(option, "a file"));
        }
        if let Some((what, input)) = reads
            .files
            .iter()
            .find(|(_, input)| driftlab::files::atomic::is_same_file(output, input))
        {
            return Err(CliError::Message(format!(
                "{option} {}: this is {what} the command reads ({}); writing it would destroy \
                 it, so nothing was written: give another file",
                output.display(),
                input.display()
            )));
        }
        if let Some((first, _)) = outputs[..k]
            .iter()
            .find(|(_, earlier)| same_output(earlier, output))
        {
            return Err(CliError::Message(format!(
                "{option} {} is also {first}: one would replace the other, so nothing was \
                 written: give it another file",
                output.display()
            )));
        }
    }
    Ok(())
}

/// Refuses, before anything is read or written, a folder the command replaces whole (the
/// report's `--out`) that is `-`, or that holds one of the files the command `reads`
/// (replacing the folder would delete it).
///
/// # Errors
/// The first file read inside the folder, named with what it is.
pub fn refuse_folder_over(option: &str, folder: &Path, reads: &Reads<'_>) -> Result<(), CliError> {
    if folder == Path::new("-") {
        return Err(dash_refused(option, "a folder"));
    }
    // A folder not yet there holds nothing.
    let Ok(root) = std::fs::canonicalize(folder) else {
        return Ok(());
    };
    match reads.files.iter().find(|(_, input)| lies_in(input, &root)) {
        Some((what, input)) => Err(CliError::Message(format!(
            "{option} {}: holds {what} the command reads ({}); the folder is replaced whole, \
             which would delete it, so nothing was written: move it out of the folder or give \
             another folder",
            folder.display(),
            input.display()
        ))),
        None => Ok(()),
    }
}

/// Whether `path` lies in the folder `root` (resolved): the file itself (a link followed), or
/// its name in its folder (a link inside `root` to a file elsewhere is removed with `root`).
fn lies_in(path: &Path, root: &Path) -> bool {
    let whole = std::fs::canonicalize(path).ok();
    let named = path.file_name().and_then(|name| {
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        std::fs::canonicalize(dir).ok().map(|d| d.join(name))
    });
    [whole, named].iter().flatten().any(|p| p.starts_with(root))
}

/// `-` given as an output (`kind`: "a file", "a folder") of a command that cannot write to
/// standard output.
fn dash_refused(option: &str, kind: &str) -> CliError {
    CliError::Message(format!(
        "{option} -: `-` stands for standard input or output, and this command writes {kind}, \
         not to standard output: give its name (./- for one named -)"
    ))
}

/// Whether two outputs are one file: the same existing file, or (not yet there) the same
/// path once links and `.`/`..` are resolved in their folders.
fn same_output(a: &Path, b: &Path) -> bool {
    if driftlab::files::atomic::is_same_file(a, b) {
        return true;
    }
    let resolved = |p: &Path| {
        let dir = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        std::fs::canonicalize(dir)
            .ok()
            .map(|d| d.join(p.file_name().unwrap_or_default()))
    };
    a == b || matches!((resolved(a), resolved(b)), (Some(x), Some(y)) if x == y)
}

/// A progress bar counting to 1000, or `None` when stderr is not a terminal (scripts, CI).
pub fn progress_bar(message: &str) -> Option<ProgressBar> {
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {percent}%")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message(shown(message).into_owned());
    Some(bar)
}

/// A short spinner-free status line on stderr when interactive.
pub fn status(message: &str) {
    if std::io::stderr().is_terminal() {
        note!("{message}");
    }
}

/// Prints a value as pretty JSON on stdout.
pub fn print_json<T: serde::Serialize>(value: &T) -> Result<(), CliError> {
    let text = serde_json::to_string_pretty(value).map_err(|e| e.to_string())?;
    write_out_lines(&text)
}

/// A setting the engine refused, named also by the option that sets it on the command line
/// (`filter_s (--filter): ...`): the value may have come from the option or from a recipe.
pub fn with_option(e: driftlab::error::Invalid) -> CliError {
    CliError::Message(in_option_words(&e))
}

/// [`with_option`]'s words, for a warning about a setting that was taken.
pub fn in_option_words(e: &driftlab::error::Invalid) -> String {
    let option = match e.field.as_str() {
        "filter_s" => "--filter",
        "window_s" => "--window",
        "models" => "--models",
        "temp_smoothing_s" => "--smooth",
        "step_h_s" => "--step-h",
        "deadband_tdot" => "--deadband-tdot",
        "deadband_tddot" => "--deadband-tddot",
        "gyro_id" => "--gyro-id",
        "plateaus" => "--plateau",
        "per_run_offset" => "--per-run-offset",
        "tolerance_c" => "--temp-tolerance",
        f if f.ends_with(".knots") => "--knots",
        _ => return super::log_source::in_flags(&e.to_string()),
    };
    format!("{} ({option}): {}", e.field, e.reason)
}

/// The gyro axes a command works on: those `--axes` names (axis names, rate columns or the
/// letter an axis name ends with), else every axis of a log of several unless a single
/// `--rate-col` names the one, or `None` for one axis (the command works as it always has).
///
/// # Errors
/// An `--axes` entry that names no axis of `log`, or names one twice.
pub fn chosen_axes(
    axes: &[String],
    log_args: &LogArgs,
    log: &Log,
) -> Result<Option<Vec<String>>, CliError> {
    let names = log.axis_names();
    // A single --rate-col chooses the one axis as --axes does: given both, one would be
    // dropped.
    if let ([asked, ..], [column]) = (axes, &log_args.rate_col[..]) {
        return Err(format!(
            "--axes {asked} and --rate-col {column} both choose the axis to work on: give one \
             of them (--rate-col names the column of one axis, --axes picks axes of a log of \
             several)"
        )
        .into());
    }
    if !axes.is_empty() {
        let mut out: Vec<String> = Vec::with_capacity(axes.len());
        for asked in axes {
            let asked = asked.trim();
            if asked.is_empty() {
                return Err(format!(
                    "--axes: an empty name in the list (the axes of {}: {})",
                    log.source,
                    names.join(", ")
                )
                .into());
            }
            let Some(name) = log.find_axis(asked) else {
                return Err(format!(
                    "--axes {asked}: {} has no such gyro axis (its axes: {})",
                    log.source,
                    names.join(", ")
                )
                .into());
            };
            if out.contains(&name) {
                return Err(format!("--axes: axis {name} is named twice").into());
            }
            out.push(name);
        }
        return Ok(Some(out));
    }
    Ok((names.len() > 1 && log_args.rate_col.len() != 1).then_some(names))
}

/// Refuses a calibration of one unnamed axis on a log of several gyro axes, unless a single
/// `--rate-col` names the axis it is for. Such a file does not record the column it was
/// fitted on (`calibrate LOG --rate-col gy_dps` writes one as `calibrate` of a one-axis log
/// does), so taking the log's first axis would correct gx with gy's coefficients, with
/// nothing said; the command cannot know, so it asks. A drone or robot log (read from
/// `path`), whose columns `--rate-col` does not choose, has its gyro's X axis corrected, as
/// `export` writes a single calibration for X, and a note says so and how to choose another.
///
/// # Errors
/// The calibration, the log and its axes named, with the option that chooses.
pub fn refuse_guessed_axis(
    unit: &driftlab::models::UnitCalibration,
    log_args: &LogArgs,
    (path, log): (&Path, &Log),
    calibration: &Path,
) -> Result<(), CliError> {
    let axes = log.axis_names();
    if unit.is_unit() || axes.len() < 2 || log_args.rate_col.len() == 1 {
        return Ok(());
    }
    let column = log.rate_column().unwrap_or_else(|| log.axis.clone());
    let drone = path != Path::new("-")
        && super::log_source::check(log_args, path, &log_args.options()?)?.is_some();
    if drone {
        note!(
            "note: {}: a calibration of one axis, on {} of {} gyro axes ({}): it corrects {} \
             (column {column}), the gyro's X axis, as export writes a single calibration; to \
             correct another, `driftlab convert` the log and name the axis's column with \
             --rate-col",
            calibration.display(),
            log.source,
            axes.len(),
            axes.join(", "),
            log.axis
        );
        return Ok(());
    }
    Err(format!(
        "{}: a calibration of one axis, which does not record the column it was fitted on, and \
         {} has {} gyro axes ({}): name the column of the axis it corrects with --rate-col \
         (e.g. --rate-col {column})",
        calibration.display(),
        log.source,
        axes.len(),
        axes.join(", ")
    )
    .into())
}
