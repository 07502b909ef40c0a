//! `driftlab allan`: the Allan deviation of a log's rate, with intervals and the gyro
//! read-outs (ARW, bias instability, RRW).

use super::common::{self, CliError, LogArgs};
use super::log_source;
use driftlab::judge::allan::{self, AllanDeviation, AllanOptions, Readout, TauSpacing, kalibr};
use driftlab::log::formats::Format;
use driftlab::log::ingest::{ExtraColumns, Input, Needs};
use std::path::PathBuf;

/// Arguments of `allan`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The log: a chamber log (its rate column is used), or one column of rate samples.
    pub log: PathBuf,
    /// Sampling interval, s. Needed for a one-column log (its sample index times this is the
    /// time); for a log with time it overrides the median step.
    #[arg(long, value_name = "S")]
    pub tau0: Option<f64>,
    /// Every averaging factor up to N/4 instead of octaves (slow on long logs: O(N²)).
    #[arg(long)]
    pub all_tau: bool,
    /// Print one JSON object instead of the table (with Kalibr's four values under
    /// "kalibr", in rad/s/sqrt(Hz), rad/s^2/sqrt(Hz), m/s^2/sqrt(Hz), m/s^3/sqrt(Hz)).
    #[arg(long)]
    pub json: bool,
    /// Also write Kalibr's IMU noise file (imu.yaml): gyroscope_noise_density from the angle
    /// random walk, gyroscope_random_walk from the rate random walk, each the largest over
    /// the gyro axes analysed (--axes, --rate-col), and the accelerometer's pair where the log
    /// has accelerometer axes (the largest over them), with the tau ranges they were read from
    /// (atomically).
    #[arg(long, value_name = "OUT.yaml")]
    pub kalibr: Option<PathBuf>,
    /// --kalibr: write the random walks even though the log's temperature moves by more than
    /// a stable lab holds (2 °C), which makes its long-τ slopes the thermal drift's as much as
    /// the sensor's; the file then says so. Without it such a file is refused.
    #[arg(long)]
    pub allow_moving_temperature: bool,
    /// The gyro axes to analyse, comma-separated (`gx,gz`, or by rate column or ending letter):
    /// by default every axis of a log of several (a single `--rate-col` analyses that one).
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub axes: Vec<String>,
    /// The IMU's ROS topic in the Kalibr file (default: the topic of a ROS bag or MCAP gyro,
    /// else /imu0).
    #[arg(long, value_name = "TOPIC")]
    pub rostopic: Option<String>,
    #[command(flatten)]
    pub log_args: LogArgs,
}

pub fn run(a: Args) -> Result<(), CliError> {
    a.log_args.refuse_accel("allan")?;
    if let Some(k) = &a.kalibr {
        let mut reads = common::Reads::default();
        reads.add("the log", &a.log);
        common::refuse_outputs(&[("--kalibr", k)], &reads)?;
    }
    if let Some(t) = a.tau0 {
        allan::check_tau0(t).map_err(|e| format!("--tau0: {e}"))?;
    }
    let read_opts = a.log_args.options()?;
    if a.allow_moving_temperature && a.kalibr.is_none() {
        return Err(
            "--allow-moving-temperature lets --kalibr write the random walks of a log whose \
             temperature moves: give --kalibr OUT.yaml"
                .into(),
        );
    }
    if a.rostopic.is_some() && a.kalibr.is_none() && !a.json {
        return Err("--rostopic names the topic of the Kalibr file: give --kalibr OUT.yaml".into());
    }
    if let Some(t) = &a.rostopic {
        driftlab::judge::allan::kalibr::check_rostopic(t)
            .map_err(|e| format!("--rostopic {t:?}: {e}"))?;
    }
    let input = a.log_args.open(&a.log)?;
    // A drone or robot log is read from its file; a CSV, a one-column file or a stream once.
    let drone = match &input {
        Input::Path(path) => log_source::read_drone_log(&a.log_args, path, &read_opts, false)?,
        Input::Bytes { .. } => None,
    };
    // A ROS gyro's topic is its instance's label.
    let ros_topic = drone.as_ref().and_then(|(_, d)| {
        matches!(d.format, Format::RosBag | Format::Mcap)
            .then(|| d.instances.iter().find(|s| s.index == d.chosen))
            .flatten()
            .map(|s| s.label.clone())
    });
    let series = match drone {
        Some(_) => None,
        None => input.rate_series(&read_opts).map_err(|e| e.to_string())?,
    };
    // Every gyro axis (°/h; the one in `omega_dph` first) and the accelerometer axes (m/s²)
    // for Kalibr, which takes the noisiest of those analysed; the axes analysed, by position
    // among the gyro's.
    let mut accel: Vec<(String, Vec<f64>)> = Vec::new();
    // Accelerometer axes whose unit their names do not say: Kalibr's file says so.
    let mut accel_unknown: Vec<String> = Vec::new();
    let mut recorded_step_s = None;
    // What the temperature of the analysed samples did (a log of one column has none).
    let mut temperature = None;
    // The time of each sample, s, for the messages of the readings check.
    let times: Vec<f64>;
    // A column of rate samples alone, whose one axis has no name.
    let one_column = series.is_some();
    let (source, gyro, tau0_s, chosen) = match series {
        Some(series) => {
            let tau0 = a
                .tau0
                .or(a.log_args.sample_rate.map(|hz| 1.0 / hz))
                .ok_or_else(|| {
                    format!(
                        "{}: a log of one column has no time; give its sampling interval with \
                         --tau0 S (or --sample-rate HZ)",
                        series.source
                    )
                })?;
            if !a.axes.is_empty() {
                return Err(format!(
                    "--axes: {} is one column of rate samples, with no axes to choose",
                    series.source
                )
                .into());
            }
            times = (0..series.omega_dph.len())
                .map(|k| k as f64 * tau0)
                .collect();
            let gyro = vec![("rate".to_string(), series.omega_dph)];
            (series.source, gyro, tau0, None)
        }
        None => {
            let recorded = match drone {
                Some((log, _)) => log,
                None => {
                    // The rate alone, whatever the temperature column holds, and the
                    // accelerometers where Kalibr's values are asked for: no other column.
                    let needs = Needs {
                        temperature: false,
                        extras: Some(ExtraColumns {
                            accelerometers: a.json || a.kalibr.is_some(),
                            ..ExtraColumns::default()
                        }),
                    };
                    let log = a.log_args.read_unresampled(&input, &needs)?;
                    if let Some(told) = temperature_unused(&log) {
                        note!("note: {}: {told}", log.source);
                    }
                    log
                }
            };
            // Kalibr discretises the noise densities at the rate of the IMU's messages, the
            // log's as recorded, not the rate of its bins.
            recorded_step_s = Some(recorded.nominal_dt_s());
            let log = a.log_args.resampled(recorded)?;
            // The Allan deviation needs evenly spaced samples: a log with gaps gives its
            // longest stretch, and says so.
            let (log, note) = driftlab::log::resample::longest_segment(log);
            if let Some(note) = note {
                note!("note: {}: {note}", log.source);
            }
            temperature = allan::TemperatureMotion::of(&log.temp_c);
            if let Some(m) = temperature.filter(|m| m.moves) {
                note!("warning: {}: {}", log.source, m.describe());
            }
            let step = log.nominal_dt_s();
            let tau0 = a.tau0.unwrap_or(step);
            if let Some(told) = allan::tau0_against_step(tau0, step, &log.source) {
                note!("warning: {}", told.replacen("tau0", "--tau0", 1));
            }
            let chosen = axes_to_analyse(&a, &log)?;
            for c in log.extra.into_iter().filter(|c| c.is_accelerometer()) {
                match c.accelerometer_to_m_s2() {
                    Some(f) => {
                        let mut values: Vec<f64> = c.values.into_iter().map(|v| v * f).collect();
                        // Refused as `evaluate` refuses the axis: its noise read through 10³⁸
                        // would be written to Kalibr's file. (One that never changes is told
                        // below, in the words of an Allan curve that cannot be drawn.)
                        match driftlab::models::check_readings(&driftlab::models::AxisReadings {
                            source: &log.source,
                            axis: &c.name,
                            kind: driftlab::log::AxisKind::Accel,
                            values: &values,
                            time_s: &log.time_s,
                            time_shift_s: 0.0,
                        }) {
                            Err(driftlab::Error::Fit(driftlab::models::FitError::FrozenRate {
                                ..
                            }))
                            | Ok(()) => {}
                            Err(e) => return Err(e.to_string().into()),
                        }
                        if let Some((run, holes)) = kalibr::longest_finite_run(&values) {
                            note!(
                                "note: {}: accelerometer axis {}: {holes} of its {} samples \
                                 read no number; its Allan deviation is taken over its longest \
                                 run of readings, samples {} to {}",
                                log.source,
                                driftlab::text::escaped(&c.name, false),
                                values.len(),
                                run.start + 1,
                                run.end
                            );
                            values = values[run].to_vec();
                        }
                        accel.push((c.name, values));
                    }
                    None => accel_unknown.push(c.name),
                }
            }
            times = log.time_s;
            let mut gyro = vec![(log.axis, log.omega_dph)];
            gyro.extend(log.other_axes.into_iter().map(|x| (x.name, x.omega_dph)));
            (log.source, gyro, tau0, chosen)
        }
    };
    // `None`: one axis, printed as driftlab always has; else every axis asked, in turn.
    let several = chosen.is_some();
    let chosen: Vec<usize> = match chosen {
        Some(names) => names
            .iter()
            .filter_map(|n| gyro.iter().position(|(g, _)| g == n))
            .collect(),
        None => vec![0],
    };
    let samples = gyro.first().map_or(0, |(_, r)| r.len());
    let opts = AllanOptions {
        tau0_s,
        spacing: if a.all_tau {
            TauSpacing::All
        } else {
            TauSpacing::Octave
        },
        ..AllanOptions::default()
    };
    if a.all_tau && samples > 200_000 {
        note!(
            "warning: --all-tau on {} samples computes {} deviations of O(N) each{}; octave τ \
             (the default) takes a fraction of a second",
            samples,
            samples / 4,
            if chosen.len() > 1 {
                format!(", for each of {} axes", chosen.len())
            } else {
                String::new()
            }
        );
    }
    let mut devs: Vec<(usize, AllanDeviation)> = Vec::with_capacity(chosen.len());
    for &k in &chosen {
        let (name, rate) = &gyro[k];
        // An axis no figure can take is refused as `evaluate` refuses it: its read-outs would
        // be those of the readings beyond any gyro's, or of a wire.
        driftlab::models::check_readings(&driftlab::models::AxisReadings {
            source: &source,
            axis: if one_column { "" } else { name },
            kind: driftlab::log::AxisKind::Gyro,
            values: rate,
            time_s: &times,
            time_shift_s: 0.0,
        })
        .map_err(|e| e.to_string())?;
        let dev = if several {
            common::status(&format!(
                "computing the Allan deviation of {source}, axis {name}"
            ));
            allan::allan(rate, &opts).map_err(|e| format!("{source}: axis {name}: {e}"))?
        } else {
            common::status(&format!("computing the Allan deviation of {source}"));
            allan::allan(rate, &opts).map_err(|e| format!("{source}: {e}"))?
        };
        devs.push((k, dev));
    }
    let noise = if a.json || a.kalibr.is_some() {
        let rostopic = match (&a.rostopic, &ros_topic) {
            (Some(t), _) | (None, Some(t)) => t.clone(),
            (None, None) => {
                if a.kalibr.is_some() {
                    note!(
                        "note: {source}: rostopic /imu0 in the Kalibr file (give the IMU's with \
                         --rostopic TOPIC)"
                    );
                }
                "/imu0".to_string()
            }
        };
        let mut noise = kalibr_noise(&source, &gyro, &devs, &accel, tau0_s, &rostopic)?;
        if !accel_unknown.is_empty() {
            note!(
                "warning: {source}: the accelerometer columns {} do not say their unit (m/s^2, g \
                 or mg in the name, as acc_x_g): Kalibr's accelerometer pair is left out",
                accel_unknown.join(", ")
            );
        }
        noise.accelerometers_without_unit = accel_unknown;
        noise.temperature_moves = temperature.filter(|m| m.moves);
        if a.log_args.bin.is_some()
            && let Some(step) = recorded_step_s
        {
            noise.update_rate_hz = kalibr::update_rate_hz(step);
        }
        Some(noise)
    } else {
        None
    };
    if let (Some(path), Some(noise)) = (&a.kalibr, &noise) {
        let moving = if a.allow_moving_temperature {
            kalibr::MovingTemperature::Write
        } else {
            kalibr::MovingTemperature::Refuse
        };
        let text = kalibr::imu_yaml(noise, &source, moving).map_err(|e| {
            let hint = match (&e, a.log_args.bin) {
                (kalibr::KalibrError::TemperatureMoves { .. }, _) => {
                    " (--allow-moving-temperature writes the file all the same, saying so in it)"
                        .to_string()
                }
                (_, Some(bin)) => format!(
                    " (--bin {} averaged the log's white noise away below {0} s: analyse the \
                     log as recorded)",
                    driftlab::number::readable(bin)
                ),
                (_, None) => String::new(),
            };
            format!("{source}: {e}{hint}; {} not written", path.display())
        })?;
        driftlab::files::atomic::write_bytes(path, text.as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))?;
        note!("Kalibr noise model written to {}", path.display());
    }
    let Some((_, first)) = devs.first() else {
        return Err("no gyro axis to analyse".into());
    };
    if a.json {
        // The first axis analysed at the top, as for a log of one axis; every axis under "axes".
        let mut j = json(&source, first);
        // Where the log has a temperature: what it did, and the warning when it moves.
        if let Some(m) = &temperature {
            j["temperature"] = serde_json::to_value(m).map_err(|e| e.to_string())?;
            if m.moves {
                j["temperature"]["warning"] = m.describe().into();
            }
        }
        if several {
            j["axes"] = devs
                .iter()
                .map(|(k, d)| {
                    let mut v = json(&source, d);
                    v["name"] = gyro[*k].0.clone().into();
                    v
                })
                .collect::<Vec<_>>()
                .into();
        }
        j["kalibr"] = serde_json::to_value(&noise).map_err(|e| e.to_string())?;
        return common::print_json(&j);
    }
    if !several {
        return print_table(&source, first);
    }
    for (k, d) in &devs {
        out!("=== Axis {} ===", gyro[*k].0)?;
        print_table(&source, d)?;
        out!()?;
    }
    print_summary(&source, &gyro, &devs)
}

/// What a log read without a temperature did with it, for a note: no column, a column of no
/// number, or rows whose temperature is blank, NaN or unreadable (analysed all the same);
/// `None` when every row has one.
fn temperature_unused(log: &driftlab::Log) -> Option<String> {
    let column = log
        .info
        .columns
        .iter()
        .find(|c| c.role == driftlab::log::ColumnRole::Temperature);
    let Some(column) = column else {
        return Some(
            "no temperature column: the Allan deviation reads the rate alone, and needs none"
                .into(),
        );
    };
    let blank = log.temp_c.iter().filter(|t| t.is_nan()).count();
    if blank == 0 {
        return None;
    }
    if blank == log.temp_c.len() {
        return Some(format!(
            "the temperature column {} holds no number: the Allan deviation reads the rate \
             alone, and needs none",
            column.name
        ));
    }
    let first = log.temp_c.iter().position(|t| t.is_nan()).unwrap_or(0);
    Some(format!(
        "the temperature column {} is blank, NaN or no number on {blank} rows (the first at {} \
         s): the Allan deviation needs no temperature, so their rate is analysed with the others",
        column.name,
        common::num(log.time_s.get(first).copied().unwrap_or(f64::NAN))
    ))
}

/// The axes to analyse ([`common::chosen_axes`]).
fn axes_to_analyse(a: &Args, log: &driftlab::Log) -> Result<Option<Vec<String>>, CliError> {
    common::chosen_axes(&a.axes, &a.log_args, log)
}

/// One line per axis analysed: its three read-outs.
fn print_summary(
    source: &str,
    gyro: &[(String, Vec<f64>)],
    devs: &[(usize, AllanDeviation)],
) -> Result<(), CliError> {
    out!("{source}: read-outs of every axis analysed")?;
    out!(
        "  {:<8} {:>32} {:>32} {:>32}",
        "axis",
        "angle random walk",
        "bias instability",
        "rate random walk"
    )?;
    let cell = |r: &Option<Readout>| match r {
        Some(r) => format!(
            "{:.4e} {}{}",
            r.value,
            r.unit,
            if r.extrapolated { " (extr.)" } else { "" }
        ),
        None => "none".to_string(),
    };
    for (k, d) in devs {
        let r = &d.readouts;
        out!(
            "  {:<8} {:>32} {:>32} {:>32}",
            gyro[*k].0,
            cell(&r.arw),
            cell(&r.bias_instability),
            cell(&r.rrw)
        )?;
    }
    Ok(())
}

/// Each named series as borrowed slices.
fn as_refs(v: &[(String, Vec<f64>)]) -> Vec<(&str, &[f64])> {
    v.iter().map(|(n, x)| (n.as_str(), x.as_slice())).collect()
}

/// Kalibr's values: the read-outs of the gyro axes analysed (those `--axes` or a single
/// `--rate-col` chose, as printed), with the log's accelerometer axes. An axis left out by
/// the choice is left out of the file too: the noisiest of every axis would give the file
/// another axis's noise than the one asked for, and the file names the axis it read.
fn kalibr_noise(
    source: &str,
    gyro: &[(String, Vec<f64>)],
    devs: &[(usize, AllanDeviation)],
    accel: &[(String, Vec<f64>)],
    tau0_s: f64,
    rostopic: &str,
) -> Result<kalibr::KalibrNoise, String> {
    let readouts: Vec<kalibr::AxisReadouts> = devs
        .iter()
        .map(|(k, d)| kalibr::AxisReadouts {
            axis: gyro[*k].0.clone(),
            readouts: d.readouts.clone(),
        })
        .collect();
    let accel = kalibr::axis_readouts(&as_refs(accel), tau0_s)
        .map_err(|(name, e)| format!("{source}: {}", accelerometer_error(&name, &e)))?;
    Ok(kalibr::kalibr_noise(&readouts, &accel, tau0_s, rostopic))
}

/// Why accelerometer axis `name` has no Allan curve, in its own words: the deviation's error
/// speaks of a gyro's rate samples, which an accelerometer's are not.
fn accelerometer_error(name: &str, e: &allan::AllanError) -> String {
    match e {
        allan::AllanError::Constant(v) => format!(
            "accelerometer axis {name}: every sample reads {} m/s^2: an accelerometer that \
             never changes has no noise to analyse (a sensor disconnected or stuck, or a log \
             that fills the axis for an IMU without one: leave the column out)",
            driftlab::number::readable(*v)
        ),
        allan::AllanError::NotFinite { index, value } => {
            format!("accelerometer axis {name}: sample {index} is not a finite number ({value})")
        }
        allan::AllanError::TooShort(n) => format!(
            "accelerometer axis {name}: an Allan deviation needs at least 2 samples, the \
             series has {n}"
        ),
        other => format!("accelerometer axis {name}: {other}"),
    }
}

/// The one JSON object: columns of the curve, then the read-outs.
fn json(source: &str, d: &AllanDeviation) -> serde_json::Value {
    let col = |f: &dyn Fn(&allan::AllanPoint) -> serde_json::Value| {
        d.points.iter().map(f).collect::<Vec<_>>()
    };
    serde_json::json!({
        "source": source,
        "samples": d.samples,
        "tau0_s": d.options.tau0_s,
        "overlapping": d.options.overlapping,
        "confidence": d.options.confidence,
        "unit": "deg/h",
        "tau": col(&|p| p.tau_s.into()),
        "adev": col(&|p| p.adev.into()),
        "n": col(&|p| p.n_terms.into()),
        "adev_min": col(&|p| p.adev_min.into()),
        "adev_max": col(&|p| p.adev_max.into()),
        "alpha": col(&|p| p.alpha.into()),
        "edf": col(&|p| p.edf.into()),
        "readouts": d.readouts,
    })
}

fn print_table(source: &str, d: &AllanDeviation) -> Result<(), CliError> {
    out!(
        "{source}: overlapping Allan deviation of {} samples, tau0 = {} s, {:.1}% intervals",
        d.samples,
        common::num(d.options.tau0_s),
        d.options.confidence * 100.0
    )?;
    out!(
        "  {:>12} {:>13} {:>10} {:>13} {:>13} {:>5}",
        "tau (s)",
        "sigma (deg/h)",
        "n",
        "min",
        "max",
        "alpha"
    )?;
    let opt = |v: Option<f64>| v.map_or_else(|| "-".to_string(), |v| format!("{v:.6e}"));
    for p in &d.points {
        out!(
            "  {:>12} {:>13.6e} {:>10} {:>13} {:>13} {:>5}",
            // m·τ0 in binary can print as 0.30000000000000004; nine digits are plenty.
            driftlab::number::significant(p.tau_s, 9),
            p.adev,
            p.n_terms,
            opt(p.adev_min),
            opt(p.adev_max),
            p.alpha
        )?;
    }
    out!("  read-outs:")?;
    let r = &d.readouts;
    readout("angle random walk", &r.arw, "no -1/2 region in the curve")?;
    readout(
        "bias instability",
        &r.bias_instability,
        "the curve shows no minimum it rises from",
    )?;
    readout("rate random walk", &r.rrw, "no +1/2 region in the curve")
}

fn readout(name: &str, r: &Option<Readout>, none: &str) -> Result<(), CliError> {
    match r {
        Some(r) => out!(
            "    {name:<18} {:.6e} {:<14} {}{}",
            r.value,
            r.unit,
            r.method,
            if r.extrapolated {
                " (extrapolated)"
            } else {
                ""
            }
        ),
        None => out!("    {name:<18} none: {none}"),
    }
}
