//! What the chamber simulator hands out: progress, the run as a log, the CSV read back at its
//! written precision, the `driftlab simulate` command and the bundled sample logs.

use driftlab::log::ingest::{self, ReadOptions};
use driftlab::sim::{profile, profile_names, simulate, simulate_with_progress};

use crate::common;
use common::sim::*;

#[test]
fn progress_is_reported_up_to_one() {
    let p = profile("fast-ramps").unwrap();
    let seen = std::cell::RefCell::new(Vec::new());
    let r = simulate_with_progress(&p, 1, &|f| seen.borrow_mut().push(f));
    let seen = seen.into_inner();
    assert!(seen.len() > 10);
    assert!(seen.windows(2).all(|w| w[0] <= w[1]));
    assert_eq!(*seen.last().unwrap(), 1.0);
    assert_eq!(r.len(), p.sample_count());
}

#[test]
fn to_log_carries_the_chamber_as_a_channel() {
    let p = profile("fast-ramps").unwrap();
    let r = simulate(&p, 1);
    let log = r.to_log("sim:fast-ramps");
    assert_eq!(log.source, "sim:fast-ramps");
    assert_eq!(log.time_s, r.time_s);
    assert_eq!(log.omega_dph, r.omega_dph);
    assert_eq!(log.temp_c, r.temp_c);
    assert_eq!(log.channel("temp_chamber_c").unwrap().values, r.chamber_c);
    assert_eq!(log.nominal_dt_s(), 1.0);
}

fn read_back(path: &std::path::Path) -> (Vec<String>, Vec<[f64; 4]>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head = vec![
        lines.next().unwrap().to_string(),
        lines.next().unwrap().to_string(),
    ];
    let rows = lines
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [f[0], f[1], f[2], f[3]]
        })
        .collect();
    (head, rows)
}

#[test]
fn csv_reads_back_at_the_written_precision() {
    let dir = tempfile::tempdir().unwrap();
    let p = profile("fast-ramps").unwrap();
    let r = simulate(&p, 11);
    let path = dir.path().join("fast.csv");
    r.write_csv(&path).unwrap();
    let (head, rows) = read_back(&path);
    assert_eq!(
        head[0],
        "# driftlab simulate --profile fast-ramps --seed 11"
    );
    assert_eq!(head[1], "time_s,omega_dph,temp_c,temp_chamber_c");
    assert_eq!(rows.len(), r.len());
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row[0], r.time_s[i]);
        assert!((row[1] - r.omega_dph[i]).abs() <= 0.5e-4 + 1e-12);
        assert_eq!(row[2], r.temp_c[i]);
        assert!((row[3] - r.chamber_c[i]).abs() <= 0.5e-3 + 1e-12);
    }

    // A faster sampling: times such as 0.1 s come back exactly too.
    let mut p = step_profile(20.0, 21.0);
    p.name = "ten-hz".into();
    p.sample_rate_hz = 10.0;
    p.program.truncate(2);
    let r = simulate(&p, 12);
    let path = dir.path().join("ten.csv");
    r.write_csv(&path).unwrap();
    let (_, rows) = read_back(&path);
    assert_eq!(rows.len(), r.len());
    assert_eq!(rows[3][0], 0.3);
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row[0], r.time_s[i]);
        assert!((row[0] - i as f64 / 10.0).abs() < 1e-9);
    }
}

fn driftlab_cli(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .output()
        .expect("driftlab runs")
}

#[test]
fn cli_lists_the_profiles_and_writes_noise_only() {
    let help = driftlab_cli(&["simulate", "--help"]);
    let help = String::from_utf8(help.stdout).unwrap();
    for name in profile_names() {
        assert!(help.contains(name), "--help lists {name}");
    }
    assert!(help.contains("--noise-only"));
    for flag in [
        "--axes",
        "--accel",
        "--rate-hz",
        "--gap",
        "--bursts",
        "--jitter",
        "--raw-temp-col",
        "--dialect",
        "--rate-names",
        "--rate-unit",
        "--time-unit",
        "--separator",
        "--decimal-mark",
    ] {
        assert!(help.contains(flag), "--help shows {flag}");
    }

    let dir = tempfile::tempdir().unwrap();
    let full = dir.path().join("full.csv");
    let quiet = dir.path().join("quiet.csv");
    for (path, extra) in [(&full, None), (&quiet, Some("--noise-only"))] {
        let mut args = vec![
            "simulate",
            "--profile",
            "yan-steps-high",
            "--seed",
            "4",
            "--out",
            path.to_str().unwrap(),
        ];
        args.extend(extra);
        let out = driftlab_cli(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let run = simulate(&profile("yan-steps-high").unwrap(), 4);
    let a = ingest::read_path(&full, &ReadOptions::default()).unwrap();
    let b = ingest::read_path(&quiet, &ReadOptions::default()).unwrap();
    assert!(a.time_s == run.time_s);
    assert!(b.time_s == run.time_s);
    for i in 0..run.len() {
        assert!((b.omega_dph[i] - run.noise_dph[i]).abs() <= 0.5e-4 + 1e-12);
        let d = a.omega_dph[i] - b.omega_dph[i];
        assert!((d - run.thermal_dph[i]).abs() <= 1e-4 + 1e-9);
    }
    let bad = driftlab_cli(&["simulate", "--profile", "moon", "--out", "x.csv"]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("laser-gyro"));

    // Options that cannot be honoured are refused, naming the option, and nothing is written.
    let x = dir.path().join("x.csv");
    let x = x.to_str().unwrap();
    for (args, word) in [
        (vec!["--gap", "5"], "--gap"),
        (vec!["--bursts", "10:5"], "--bursts"),
        (vec!["--rate-hz", "0"], "--rate-hz"),
        (vec!["--axes", "4"], "--axes"),
        (vec!["--profile", "laser-gyro", "--axes", "3"], "--axes"),
        (vec!["--profile", "laser-gyro", "--accel"], "--accel"),
        (vec!["--rate-hz", "600", "--jitter"], "--jitter"),
        (vec!["--decimal-mark", "comma"], "--decimal-mark"),
        (vec!["--dialect", "moon"], "stand"),
        (vec!["--rate-names", "q"], "gx_dps"),
    ] {
        let mut all = vec!["simulate", "--out", x];
        all.extend(&args);
        let out = driftlab_cli(&all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert!(err.contains(word), "{args:?}: {err}");
        assert!(!std::path::Path::new(x).exists(), "{args:?} wrote a file");
    }
}

#[test]
fn sample_logs_are_what_their_first_line_says() {
    // Every bundled log is remade, byte for byte, by the `driftlab simulate` command on its
    // first `#` line (after the stand's line, for a stand's dialect), run as a user runs it.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs");
    let out = tempfile::tempdir().unwrap();
    let mut seen = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("csv") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let command = text
            .lines()
            .take_while(|l| l.starts_with('#'))
            .find_map(|l| l.strip_prefix("# driftlab simulate "))
            .unwrap_or_else(|| panic!("{}: no `# driftlab simulate` line", path.display()));
        let words: Vec<&str> = command.split_whitespace().collect();
        assert_eq!(words[0], "--profile", "{command}");
        let remade = out.path().join("x.csv");
        let mut args = vec!["simulate"];
        args.extend(&words);
        args.extend(["--out", remade.to_str().unwrap()]);
        let run = driftlab_cli(&args);
        assert!(
            run.status.success(),
            "{command}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        assert!(
            std::fs::read_to_string(&remade).unwrap() == text,
            "{} differs from `driftlab simulate {command}`",
            path.display()
        );
        // The single-axis logs are also the library's run of their profile and seed.
        if words.len() <= 5 {
            let seed: u64 = words[3].parse().unwrap();
            let mut lib = simulate(&profile(words[1]).unwrap(), seed);
            if words.get(4) == Some(&"--noise-only") {
                lib = lib.noise_only();
            }
            lib.write_csv(&remade).unwrap();
            assert!(std::fs::read_to_string(&remade).unwrap() == text);
        }
        seen.push(path.file_stem().unwrap().to_string_lossy().to_string());
    }
    for name in [
        "calibration",
        "validation",
        "yan-steps-low",
        "yan-steps-mid",
        "yan-steps-high",
        "yan-full-range",
        "laser-gyro",
        "imu3-calibration",
        "imu3-validation",
    ] {
        assert!(
            seen.iter().any(|s| s == name),
            "sample_logs/{name}.csv missing"
        );
    }
}

#[test]
fn the_three_axis_sample_logs_are_a_stands_three_axis_runs() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs");
    for (name, profile_name) in [
        ("imu3-calibration", "calibration"),
        ("imu3-validation", "validation"),
    ] {
        let path = dir.join(format!("{name}.csv"));
        let csv = Csv::read(&path, ';', true);
        assert!(csv.comments[0].starts_with("stand: "), "{name}");
        assert_eq!(
            csv.names.join(";"),
            "time_ms;gx_dps;gy_dps;gz_dps;ax_g;ay_g;az_g;temp_c;temp_chamber_c"
        );
        // 5 Hz over the whole program, time in ms.
        let p = profile(profile_name).unwrap();
        let ms = csv.column("time_ms");
        assert_eq!(ms.len(), (p.sample_count() - 1) * 5 + 1);
        assert!(ms.windows(2).all(|w| (w[1] - w[0] - 200.0).abs() < 1e-6));
        // Under 25 MB each, so they can be bundled.
        let size = std::fs::metadata(&path).unwrap().len();
        assert!(size < 25_000_000, "{name}: {size} bytes");
    }
}
