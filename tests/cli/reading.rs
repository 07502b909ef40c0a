//! What the commands read of a log, and how much of it they hold: `allan`, `compare` and
//! `report` keep only the columns they use (a stand's export of a thousand unused channels
//! costs them nothing), a log from standard input or a pipe is held only up to a bound, and
//! standard input (or one FIFO) is never given for two logs of one command.
//!
//! Memory is judged as `tests/attack/` judges it: the command runs under an address-space limit
//! (`ulimit -v`, RLIMIT_AS) and must end as it does without one, with the same figures as on
//! the log without the unused columns.

use std::io::Write as _;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common;
use common::run::{ok, p, sample};

/// What a bounded run did: its status (`None` when a signal ended it, as an abort on a failed
/// allocation does), what it printed.
struct Ran {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Longer than any of these runs takes, far shorter than a hang.
const HANG_AFTER: Duration = Duration::from_secs(120);

/// Runs `driftlab ARGS` with its address space limited to `mib` MiB (the shell's `ulimit -v`,
/// when given) and `stdin` as its standard input, writing `feed` into it when given (until
/// driftlab stops reading); a run past [`HANG_AFTER`] is killed and fails the test.
fn run(
    dir: &Path,
    mib: Option<u64>,
    args: &[&str],
    stdin: Stdio,
    feed: Option<Box<dyn FnOnce(std::process::ChildStdin) + Send>>,
) -> Ran {
    let (out, err) = (dir.join("stdout.txt"), dir.join("stderr.txt"));
    let limit = mib.map_or_else(|| "unlimited".to_string(), |m| (m * 1024).to_string());
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {limit} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .stdin(stdin)
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .expect("sh runs");
    let feeder = feed.map(|f| {
        let input = child.stdin.take().expect("stdin piped");
        std::thread::spawn(move || f(input))
    });
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > HANG_AFTER {
            child.kill().ok();
            child.wait().ok();
            panic!("driftlab {args:?} hangs (over {HANG_AFTER:?})");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    if let Some(f) = feeder {
        f.join().unwrap();
    }
    let read = |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap()).into_owned();
    Ran {
        code: status.code(),
        stdout: read(&out),
        stderr: read(&err),
    }
}

impl Ran {
    fn succeeded(&self, what: &str) -> &Ran {
        assert_eq!(
            self.code,
            Some(0),
            "{what}: status {:?}\n{}",
            self.code,
            self.stderr
        );
        self
    }

    /// Status 1 and one `error:` line holding every one of `needles`.
    fn refused_with(&self, what: &str, needles: &[&str]) {
        assert_eq!(
            self.code,
            Some(1),
            "{what}: status {:?}\n{}",
            self.code,
            self.stderr
        );
        let errors: Vec<&str> = self
            .stderr
            .lines()
            .filter(|l| l.starts_with("error: "))
            .collect();
        assert_eq!(errors.len(), 1, "{what}: {}", self.stderr);
        for n in needles {
            assert!(errors[0].contains(n), "{what}: {n:?} not in {}", errors[0]);
        }
    }
}

/// The bundled calibration run (40,201 rows of time, rate, temperature and the chamber's
/// temperature) with a channel a custom model can read, `laser_mw` ([`laser_mw`]), then
/// `unused` empty columns: a stand's export of every channel it could log, most of them not
/// logged.
fn log_with_columns(path: &Path, unused: usize) {
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let mut out = String::with_capacity(text.len() + 40_300 * (unused + 24));
    let empty = ",".repeat(unused);
    let mut row = 0;
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        out.push_str(line);
        if line.starts_with("time") {
            out.push_str(",laser_mw");
            for k in 0..unused {
                out.push_str(&format!(",x{k}"));
            }
        } else {
            out.push_str(&format!(",{}", laser_mw(row)));
            out.push_str(&empty);
            row += 1;
        }
        out.push('\n');
    }
    std::fs::write(path, out).unwrap();
}

/// A channel a custom model can read: a laser's power, wandering with no tie to T.
fn laser_mw(row: usize) -> f64 {
    let t = row as f64;
    5.0 + 0.2 * (t / 1500.0).sin() + 0.05 * (t / 233.0).cos()
}

/// The address space each command gets: the binary, an allocator arena of 64 MiB reserved for
/// each thread that allocates (the reader's and rayon's), and the columns it uses of a
/// 40,201-row log. The commands that read the log of 1,000 unused columns whole held 321 MB for
/// those columns alone (8 bytes a cell), peaked at 561 MB and needed 768 MiB of address space;
/// reading only what they use, they end within 256 MiB every time (and within 96 MiB most
/// times, when the allocator shares its arenas between threads rather than reserve new ones).
const LIMIT_MIB: u64 = 384;

/// `args` followed by `more`.
fn with<'a>(args: &[&'a str], more: &[&'a str]) -> Vec<&'a str> {
    [args, more].concat()
}

/// The models of `compare --json`, each log's name left out.
fn compare_figures(json: &str) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_str(json).unwrap();
    let mut models = v["models"].take();
    for m in models.as_array_mut().unwrap() {
        for l in m["logs"].as_array_mut().unwrap() {
            l.as_object_mut().unwrap().remove("log");
        }
    }
    models
}

#[test]
fn allan_compare_and_report_hold_only_the_columns_they_use() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let narrow = p(d, "narrow.csv");
    let wide = p(d, "wide.csv");
    log_with_columns(Path::new(&narrow), 0);
    log_with_columns(Path::new(&wide), 1000);
    assert!(std::fs::metadata(&wide).unwrap().len() > 40_000_000);
    let cal = p(d, "cal.json");
    ok(&["calibrate", &narrow, "--out", &cal]);
    let limited = |args: &[&str]| {
        let ran = run(d, Some(LIMIT_MIB), args, Stdio::null(), None);
        ran.succeeded(&format!("{args:?} within {LIMIT_MIB} MiB"));
        ran
    };

    // allan: the rate alone (and the accelerometers, none here, for Kalibr's file).
    for json in [false, true] {
        let flag: &[&str] = if json { &["--json"] } else { &[] };
        let on = |log| with(&["allan", log], flag);
        let truth = ok(&on(&narrow)).replace("narrow.csv", "LOG");
        let got = limited(&on(&wide)).stdout.replace("wide.csv", "LOG");
        assert_eq!(got, truth, "allan --json {json}");
    }

    // compare: a preset reads no extra column; a custom model reads the channel it names.
    for models in [
        vec!["--models", "poly-t"],
        vec!["--models", "ieee952", "--custom", "1,T,T^2,ch:laser_mw"],
    ] {
        let on = |log| {
            with(
                &["compare", "--json", "--train", log, "--test", log],
                &models,
            )
        };
        let truth = compare_figures(&ok(&on(&narrow)));
        let got = compare_figures(&limited(&on(&wide)).stdout);
        assert_eq!(got, truth, "compare {models:?}");
        // Every model was fitted: the custom one found the channel it reads.
        for m in truth.as_array().unwrap() {
            assert!(m["error"].is_null(), "{m}");
        }
    }

    // report: the calibration's model reads T alone; the temperature figure draws the log's
    // other temperatures, which are kept.
    let truth = ok(&["report", &cal, &narrow, "--out", &p(d, "rep-narrow")]);
    let got = limited(&["report", &cal, &wide, "--out", &p(d, "rep-wide")]).stdout;
    let first = |s: &str| s.lines().next().unwrap_or("").to_string();
    assert_eq!(
        first(&got).replace("wide.csv", "LOG"),
        first(&truth).replace("narrow.csv", "LOG")
    );
    let figure = std::fs::read_to_string(d.join("rep-wide/temperature-wide.svg")).unwrap();
    assert!(
        figure.contains("temp_chamber_c"),
        "the chamber's temperature is drawn"
    );
}

#[test]
fn a_custom_model_reading_a_channel_is_reported_on_with_it_held() {
    // A calibration whose model reads a channel: the report reads that channel, not the rest.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let narrow = p(d, "narrow.csv");
    let wide = p(d, "wide.csv");
    log_with_columns(Path::new(&narrow), 0);
    log_with_columns(Path::new(&wide), 1000);
    let cal = p(d, "cal.json");
    ok(&[
        "calibrate",
        &narrow,
        "--model",
        "custom",
        "--terms",
        "1,T,T^2,ch:laser_mw",
        "--out",
        &cal,
    ]);
    let truth = ok(&["report", &cal, &narrow, "--out", &p(d, "rep-narrow")]);
    let ran = run(
        d,
        Some(LIMIT_MIB),
        &["report", &cal, &wide, "--out", &p(d, "rep-wide")],
        Stdio::null(),
        None,
    );
    ran.succeeded("report of a model reading laser_mw");
    let first = |s: &str| s.lines().next().unwrap_or("").to_string();
    assert_eq!(
        first(&ran.stdout).replace("wide.csv", "LOG"),
        first(&truth).replace("narrow.csv", "LOG")
    );
}

#[test]
fn a_channel_the_log_lacks_is_told_with_every_channel_it_has() {
    // The model asks for `laser`, which the log lacks: read for that channel alone, the log
    // would seem to have none, and the message would say so.
    let dir = tempfile::tempdir().unwrap();
    let log = p(dir.path(), "run.csv");
    log_with_columns(Path::new(&log), 3);
    let out = ok(&[
        "compare",
        "--train",
        &log,
        "--models",
        "poly-t",
        "--custom",
        "1,T,ch:laser",
    ]);
    assert!(
        out.contains("no channel \"laser\" (extra channels: temp_chamber_c, laser_mw, x0, x1, x2)"),
        "{out}"
    );
}

#[test]
fn an_endless_stream_is_refused_at_its_bound_not_read_until_memory_runs_out() {
    // `yes 1,0.1,20 | driftlab inspect -` grew to 2.1 GB and ended when an allocation failed.
    // Under 1.5 GiB of address space, standard input is read up to its bound of 1 GiB and
    // refused there, with the bound and the way to read a larger log.
    let dir = tempfile::tempdir().unwrap();
    let feed = |mut input: std::process::ChildStdin| {
        let block = "1,0.1,20\n".repeat(1 << 16);
        let mut row = 0u64;
        let _ = input.write_all(b"time_s,omega_dph,temp_c\n");
        loop {
            // Time rising, so that every row is a row a log could hold.
            let mut text = String::with_capacity(block.len() + 64);
            text.push_str(&format!("{row}.5,0.1,20\n"));
            text.push_str(&block);
            row += 1;
            if input.write_all(text.as_bytes()).is_err() {
                break;
            }
            // 3 GB is past any bound: a reader that takes it all has none.
            if row > 5_000 {
                break;
            }
        }
    };
    for command in ["inspect", "allan"] {
        let ran = run(
            dir.path(),
            Some(1536),
            &[command, "-"],
            Stdio::piped(),
            Some(Box::new(feed)),
        );
        ran.refused_with(
            command,
            &["standard input", "1 GiB", "as a file", "is held in memory"],
        );
    }
}

#[test]
fn standard_input_given_for_two_logs_is_refused_before_anything_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let log = || Stdio::from(std::fs::File::open(sample("calibration.csv")).unwrap());
    let out = p(d, "rep");
    for args in [
        vec![
            "compare", "--train", "-", "--test", "-", "--models", "poly-t",
        ],
        vec!["compare", "--train", "x.csv", "--test", "-", "-"],
        vec!["report", &cal, "-", "-", "--out", &out],
    ] {
        let ran = run(d, None, &args, log(), None);
        ran.refused_with(
            &format!("{args:?}"),
            &["standard input (`-`) can be given for one log only"],
        );
    }
    assert!(!Path::new(&out).exists(), "no report was written");
    // A FIFO named twice would be opened twice: the second open waits for a writer for ever.
    let fifo = p(d, "run.fifo");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        common::cannot_run("mkfifo is missing");
        return;
    }
    for args in [
        vec!["compare", "--train", &fifo, "--test", &fifo],
        vec!["report", &cal, &fifo, &fifo, "--out", &out],
    ] {
        let ran = run(d, None, &args, Stdio::null(), None);
        ran.refused_with(&format!("{args:?}"), &["run.fifo", "can be read once"]);
    }
}
