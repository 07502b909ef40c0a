//! Writes a big chamber log for the benchmarks (BENCHMARKS.md, `bench/run.sh`).
//!
//! ```text
//! cargo run --release --no-default-features --example make_big_log -- OUT.csv [ROWS] [SEED]
//! ```
//!
//! Runs the simulator's `calibration` profile once (about 40 000 samples at 1 Hz, plateaus at
//! 20, 60, −50 and 20 °C, ending where it started) and tiles it until `ROWS` rows (default
//! 10 000 000, about 300 MB), time continuing from tile to tile. Columns and number formats are
//! those of `SimRun::write_csv`: `time_s,omega_dph,temp_c,temp_chamber_c`, time as the shortest
//! text that reads back exactly, rate to 0.0001 °/h, temperatures to 0.001 °C.
//!
//! Every tile repeats the same rows, so the text after the time column is formatted once per
//! row of the tile and only the time is formatted per row of the file.

use std::fmt::Write as _;
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let usage = "usage: make_big_log OUT.csv [ROWS (default 10000000)] [SEED (default 1)]";
    let out = PathBuf::from(args.next().ok_or(usage)?);
    let rows: usize = match args.next() {
        Some(s) => s.replace('_', "").parse().map_err(|_| usage)?,
        None => 10_000_000,
    };
    let seed: u64 = match args.next() {
        Some(s) => s.parse().map_err(|_| usage)?,
        None => 1,
    };

    let t0 = Instant::now();
    let profile = driftlab::sim::profile("calibration").ok_or("no calibration profile")?;
    let run = driftlab::sim::simulate(&profile, seed);
    let n = run.len();
    if n < 2 {
        return Err("the simulator returned fewer than 2 samples".into());
    }
    let sim_s = t0.elapsed().as_secs_f64();

    // Time continues across tiles: one tile lasts its duration plus one step.
    let dt = run.time_s[1] - run.time_s[0];
    let period = run.time_s[n - 1] - run.time_s[0] + dt;

    // The rest of each row, formatted once: ",omega,temp,chamber\n".
    let mut tail = String::with_capacity(n * 28);
    let mut tail_end = Vec::with_capacity(n + 1);
    tail_end.push(0);
    for i in 0..n {
        let _ = writeln!(
            tail,
            ",{:.4},{:.3},{:.3}",
            run.omega_dph[i], run.temp_c[i], run.chamber_c[i]
        );
        tail_end.push(tail.len());
    }
    let tail = tail.as_bytes();

    let file = std::fs::File::create(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut w = BufWriter::with_capacity(1 << 22, file);
    let io = |e: std::io::Error| format!("{}: {e}", out.display());
    writeln!(
        w,
        "# driftlab make_big_log: profile calibration, seed {seed}, {n} samples tiled to {rows} rows"
    )
    .map_err(io)?;
    writeln!(w, "time_s,omega_dph,temp_c,temp_chamber_c").map_err(io)?;
    let mut line = Vec::with_capacity(64);
    let mut num = String::with_capacity(32);
    for r in 0..rows {
        let (tile, i) = (r / n, r % n);
        let t = run.time_s[i] + tile as f64 * period;
        line.clear();
        if t.fract() == 0.0 && t.abs() < 9.0e15 {
            push_int(&mut line, t as i64);
        } else {
            // Rounded to 1 ns as the simulator does, so that it prints short and exact.
            num.clear();
            let _ = write!(num, "{}", (t * 1e9).round() / 1e9);
            line.extend_from_slice(num.as_bytes());
        }
        line.extend_from_slice(&tail[tail_end[i]..tail_end[i + 1]]);
        w.write_all(&line).map_err(io)?;
    }
    w.flush().map_err(io)?;
    let bytes = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(0);
    eprintln!(
        "{rows} rows ({:.1} MB) written to {} in {:.2} s (simulation {:.2} s)",
        bytes as f64 / 1e6,
        out.display(),
        t0.elapsed().as_secs_f64(),
        sim_s
    );
    Ok(())
}

/// Appends the decimal digits of `v`.
fn push_int(out: &mut Vec<u8>, v: i64) {
    if v < 0 {
        out.push(b'-');
    }
    let mut u = v.unsigned_abs();
    let mut buf = [0u8; 20];
    let mut k = buf.len();
    loop {
        k -= 1;
        buf[k] = b'0' + (u % 10) as u8;
        u /= 10;
        if u == 0 {
            break;
        }
    }
    out.extend_from_slice(&buf[k..]);
}
