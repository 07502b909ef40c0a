//! What the chamber simulator hands out: progress, the run as a log, the CSV read back at its
//! written precision, the `driftlab simulate` command and the bundled sample logs.

use driftlab::log::ingest::{self, ReadOptions};
use driftlab::sim::{profile, profile_names, simulate, simulate_with_progress};

mod common;
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
}

#[test]
fn sample_logs_are_what_their_first_line_says() {
    // Every bundled log is remade, byte for byte, by the command on its first line.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs");
    let mut seen = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("csv") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let first = text.lines().next().unwrap();
        let words: Vec<&str> = first.split_whitespace().collect();
        assert_eq!(
            &words[..4],
            ["#", "driftlab", "simulate", "--profile"],
            "{first}"
        );
        let name = words[4];
        assert_eq!(words[5], "--seed");
        let seed: u64 = words[6].parse().unwrap();
        let mut run = simulate(&profile(name).unwrap(), seed);
        if words.get(7) == Some(&"--noise-only") {
            run = run.noise_only();
        }
        let out = tempfile::tempdir().unwrap();
        let remade = out.path().join("x.csv");
        run.write_csv(&remade).unwrap();
        assert!(
            std::fs::read_to_string(&remade).unwrap() == text,
            "{} differs from `{first}`",
            path.display()
        );
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
    ] {
        assert!(
            seen.iter().any(|s| s == name),
            "sample_logs/{name}.csv missing"
        );
    }
}
