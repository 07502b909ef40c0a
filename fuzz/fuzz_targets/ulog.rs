//! The Ulog reader (`formats::read_bytes`) on inputs mutated as the format frames them
//! (sizes, counts, repeated records; see `common/structure.rs`), seeded from the sample logs
//! by `seed_formats.py`. A read must give an error of readable length or a recording that holds
//! together, selects and writes, never a panic, a hang or an allocation past the limit.
#![no_main]

#[path = "common/structure.rs"]
mod structure;

use libfuzzer_sys::{fuzz_mutator, fuzz_target};
use structure::Kind;

fuzz_target!(|data: &[u8]| structure::check(Kind::Ulog, data));

fuzz_mutator!(|data: &mut [u8], size: usize, max_size: usize, seed: u32| {
    structure::mutate(Kind::Ulog, data, size, max_size, seed)
});
