//! The CSV reader on a large log: the time of one read from a warm page cache and the peak
//! memory it takes, then the median of a few more reads. A whole-program benchmark (no
//! criterion: one read of 10M rows takes seconds), run as
//!
//!     cargo bench --no-default-features --bench read_big_log
//!
//! `DRIFTLAB_BENCH_ROWS` (default 10 000 000) sets the size; `DRIFTLAB_BENCH_STYLE` the
//! dialect: `csv` (default: `time_s,omega_dph,temp_c,aux`), `csv3` (no extra column),
//! `semicolon` (decimal comma) or `spaces` (aligned columns); `DRIFTLAB_BENCH_PATH` reads an
//! existing log instead; `DRIFTLAB_BENCH_REPEAT` the reads after the first (default 3).

use driftlab::log::ingest::{ReadOptions, read_path};
use std::io::Write;

/// A xorshift generator: the same noise on every run, without a dependency.
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

/// The process's peak resident memory so far, kB (Linux; `None` elsewhere).
fn vm_hwm_kb() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Generates (once, in /tmp) and reads a large log, printing the time and peak memory.
fn main() {
    let rows: usize = std::env::var("DRIFTLAB_BENCH_ROWS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10_000_000);
    let style = std::env::var("DRIFTLAB_BENCH_STYLE").unwrap_or_else(|_| "csv".into());
    // `DRIFTLAB_BENCH_PATH` reads an existing log instead (e.g. /tmp/driftlab-bench/big.csv).
    let given = std::env::var_os("DRIFTLAB_BENCH_PATH").map(std::path::PathBuf::from);
    let path = given
        .clone()
        .unwrap_or_else(|| format!("/tmp/driftlab_bench_{style}_{rows}.csv").into());
    if given.is_none() && !path.exists() {
        let t0 = std::time::Instant::now();
        let tmp = path.with_extension("tmp");
        let mut w =
            std::io::BufWriter::with_capacity(1 << 20, std::fs::File::create(&tmp).unwrap());
        let (d, header) = match style.as_str() {
            "csv3" => (",", "time_s,omega_dph,temp_c"),
            "semicolon" => (";", "time_s;omega_dph;temp_c;aux"),
            "spaces" => ("  ", "time_s  omega_dph  temp_c  aux"),
            _ => (",", "time_s,omega_dph,temp_c,aux"),
        };
        writeln!(w, "{header}").unwrap();
        let mut rng = XorShift(42);
        for i in 0..rows {
            let noise = (rng.next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            let temp = 25.0 + 40.0 * (i as f64 * 2e-6).sin();
            let mut line = format!(
                "{}.{:03}{d}{:.7}{d}{:.6}",
                i,
                (rng.next() % 3),
                0.01234 + 0.05 * noise,
                temp
            );
            if style != "csv3" {
                line += &format!("{d}{:.4}", 12.5 + noise);
            }
            if style == "semicolon" {
                line = line.replace('.', ",");
            }
            writeln!(w, "{line}").unwrap();
        }
        w.flush().unwrap();
        drop(w);
        std::fs::rename(&tmp, &path).unwrap();
        println!("generated {} in {:.2?}", path.display(), t0.elapsed());
    }
    let size = std::fs::metadata(&path).unwrap().len();
    // Warm the page cache (streaming, so memory stays low) so the timing is the reader's.
    std::io::copy(
        &mut std::fs::File::open(&path).unwrap(),
        &mut std::io::sink(),
    )
    .unwrap();
    let before = vm_hwm_kb();
    let t0 = std::time::Instant::now();
    let log = read_path(&path, &ReadOptions::default()).unwrap();
    let first = t0.elapsed().as_secs_f64();
    let after = vm_hwm_kb();
    let cols = (3 + log.extra.len()) * log.len() * 8;
    println!(
        "read {} rows ({:.0} MB) in {:.3} s; result columns {:.0} MB; VmHWM before {:?} kB, \
         after {:?} kB; problems {:?}",
        log.len(),
        size as f64 / 1e6,
        first,
        cols as f64 / 1e6,
        before,
        after,
        log.info.problems
    );
    drop(log);
    let mut times = Vec::new();
    let repeat: usize = std::env::var("DRIFTLAB_BENCH_REPEAT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    for _ in 0..repeat {
        let t0 = std::time::Instant::now();
        let log = read_path(&path, &ReadOptions::default()).unwrap();
        times.push(t0.elapsed().as_secs_f64());
        drop(log);
    }
    let mut sorted = times.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN);
    println!("{repeat} more reads: {times:.3?} s; median {median:.3} s");
}
