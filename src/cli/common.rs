//! Pieces every subcommand shares: how to read a log, progress bars, number formatting.

use driftlab::Log;
use driftlab::log::ingest::{self, ColumnRef, RateUnit, ReadOptions, TimeUnit};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::Path;

/// Column mapping and format options, on every command that reads a log.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct LogArgs {
    /// Time column: a header name or a 1-based index (default: found by name).
    #[arg(long, value_name = "NAME|N")]
    pub time_col: Option<String>,
    /// Gyro rate column: a header name or a 1-based index (default: found by name).
    #[arg(long, value_name = "NAME|N")]
    pub rate_col: Option<String>,
    /// Calibration temperature column: a header name or a 1-based index (default: the first
    /// temperature column).
    #[arg(long, value_name = "NAME|N")]
    pub temp_col: Option<String>,
    /// Unit of the rate column: deg/h, deg/s or rad/s (default: from the header, else deg/h).
    #[arg(long, value_name = "UNIT")]
    pub rate_unit: Option<String>,
    /// Unit of the time column: s, ms, min, h or samples (default: from the header, else s).
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
            rate_col: col(&self.rate_col).map_err(|e| format!("--rate-col: {e}"))?,
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

    /// Reads only the time, rate and temperature columns of a log (for the commands that use
    /// nothing else: the other columns are neither parsed nor held).
    pub fn read_columns(&self, path: &Path) -> Result<Log, String> {
        let opts = ReadOptions {
            skip_extras: true,
            ..self.options()?
        };
        self.read_with(path, &opts)
    }

    /// Reads the columns `model` needs: the calibration columns, and the second temperature
    /// and extra channels when the model reads them.
    pub fn read_for(
        &self,
        path: &Path,
        model: &driftlab::models::fitted::DriftModel,
    ) -> Result<Log, String> {
        match model.inputs() {
            (None, channels) if channels.is_empty() => self.read_columns(path),
            _ => self.read(path),
        }
    }

    /// Reads a log, with a progress bar on an interactive terminal.
    pub fn read(&self, path: &Path) -> Result<Log, String> {
        self.read_with(path, &self.options()?)
    }

    /// Reads a log as it was recorded, neither binned nor reduced to its bursts (`inspect`,
    /// which describes the file), unless `--bin` asks for bins.
    pub fn read_recorded(&self, path: &Path) -> Result<Log, String> {
        let log = self.read_plain(path, &self.options()?)?;
        match self.bin {
            Some(_) => self.resampled(log),
            None => Ok(log),
        }
    }

    fn read_with(&self, path: &Path, opts: &ReadOptions) -> Result<Log, String> {
        let log = self.read_plain(path, opts)?;
        self.resampled(log)
    }

    /// The log averaged into bins (--bin) or one sample per burst, before anything else.
    fn resampled(&self, log: Log) -> Result<Log, String> {
        let (log, note) = driftlab::log::resample::prepare(log, self.bin)?;
        if let Some(note) = note {
            eprintln!("note: {}: {note}", log.source);
        }
        Ok(log)
    }

    fn read_plain(&self, path: &Path, opts: &ReadOptions) -> Result<Log, String> {
        let bar = progress_bar(&format!("reading {}", path.display()));
        let log = ingest::read_path_with_progress(path, opts, &|f| {
            if let Some(b) = &bar {
                b.set_position((f * 1000.0) as u64);
            }
            true
        })
        .map_err(|e| e.to_string());
        if let Some(b) = bar {
            b.finish_and_clear();
        }
        let log = log?;
        for p in &log.info.problems {
            // A problem of a whole column has no line.
            let place = match (p.line, p.column) {
                (0, Some(c)) => format!(" column {c}"),
                (0, None) => String::new(),
                (l, Some(c)) => format!("{l}:{c}"),
                (l, None) => l.to_string(),
            };
            let times = if p.count > 1 {
                format!(" ({} times)", p.count)
            } else {
                String::new()
            };
            eprintln!("warning: {}:{place}: {}{times}", log.source, p.message);
        }
        Ok(log)
    }
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
    bar.set_message(message.to_string());
    Some(bar)
}

/// A short spinner-free status line on stderr when interactive.
pub fn status(message: &str) {
    if std::io::stderr().is_terminal() {
        eprintln!("{message}");
    }
}

/// Prints a value as pretty JSON on stdout.
pub fn print_json<T: serde::Serialize>(value: &T) -> Result<(), String> {
    let text = serde_json::to_string_pretty(value).map_err(|e| e.to_string())?;
    println!("{text}");
    Ok(())
}

/// Formats a ratio raw ÷ corrected for tables: `n/a` when it cannot be computed, and marked
/// `worse` below 1, where the correction made the figure worse than raw.
pub fn ratio(r: f64) -> String {
    if !r.is_finite() {
        "n/a".into()
    } else if r < 1.0 {
        format!("{r:.2}x worse")
    } else {
        format!("{r:.2}x")
    }
}

/// Formats a figure in °/h for tables: `n/a` when it could not be computed.
pub fn figure(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.4}")
    } else {
        "n/a".into()
    }
}

/// Prints an evaluation as a small table of raw, corrected and ratio.
pub fn print_evaluation(e: &driftlab::judge::metrics::Evaluation) {
    let c = &e.comparison;
    println!(
        "  {:<34} {:>11} {:>11} {:>12}",
        "figure (deg/h)", "raw", "corrected", "raw/cor"
    );
    let rows = [
        (
            "peak-to-peak of filtered drift",
            c.raw.p2p_dph,
            c.corrected.p2p_dph,
            c.p2p_ratio,
        ),
        (
            "std of filtered drift",
            c.raw.std_dph,
            c.corrected.std_dph,
            c.std_ratio,
        ),
        (
            "max |10-min mean|",
            c.raw.win_mean_max_abs_dph,
            c.corrected.win_mean_max_abs_dph,
            c.win_mean_ratio,
        ),
        (
            "mean 10-min RMS",
            c.raw.win_rms_mean_dph,
            c.corrected.win_rms_mean_dph,
            c.win_rms_ratio,
        ),
    ];
    for (name, raw, cor, r) in rows {
        println!(
            "  {name:<34} {:>11} {:>11} {:>12}",
            figure(raw),
            figure(cor),
            ratio(r)
        );
    }
    for (what, why) in [
        ("peak-to-peak and std", c.raw.filtered_unavailable),
        ("window figures", c.raw.windows_unavailable),
    ] {
        if let Some(why) = why {
            println!("  {what} n/a: {why}");
        }
    }
    if c.worse_than_raw.any() {
        println!(
            "  worse than raw: {} (ratio below 1)",
            c.worse_than_raw.names().join(", ")
        );
    }
    println!(
        "  {} samples ({} warm-up samples left out), {} windows; {:.1}% outside the calibrated ranges",
        c.raw.samples,
        e.warmup_samples,
        c.raw.windows,
        e.outside_fraction * 100.0
    );
}
