//! A log cut down to some of its rows, as another log: a block of a run held out, or the run
//! without it.

use super::Log;
use std::ops::Range;

impl Log {
    /// The rows of `self` that `keep` (by index) says, every column alike (rate, temperature,
    /// other axes, extra channels), named `source`. The time keeps its values, so rows left
    /// out between kept ones read as a gap, as a recorder's dropout would.
    pub fn rows_kept(&self, source: &str, keep: impl Fn(usize) -> bool) -> Log {
        let kept = |v: &[f64]| -> Vec<f64> {
            v.iter()
                .enumerate()
                .filter(|(i, _)| keep(*i))
                .map(|(_, x)| *x)
                .collect()
        };
        let mut out = Log {
            source: source.to_string(),
            time_s: kept(&self.time_s),
            omega_dph: kept(&self.omega_dph),
            temp_c: kept(&self.temp_c),
            extra: self.extra.clone(),
            axis: self.axis.clone(),
            axis_kind: self.axis_kind,
            other_axes: self.other_axes.clone(),
            info: self.info.clone(),
        };
        for c in &mut out.extra {
            c.values = kept(&c.values);
        }
        for a in &mut out.other_axes {
            a.omega_dph = kept(&a.omega_dph);
        }
        out.info.rows_read = out.time_s.len();
        out
    }

    /// The rows `block` alone, named `source`.
    pub fn rows_in(&self, source: &str, block: Range<usize>) -> Log {
        self.rows_kept(source, |i| block.contains(&i))
    }

    /// Every row but those of `block`, named `source`.
    pub fn rows_without(&self, source: &str, block: Range<usize>) -> Log {
        self.rows_kept(source, |i| !block.contains(&i))
    }
}
