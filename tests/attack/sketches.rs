//! A calibration's sample sketch edited by hand to megabytes (the sixteenth attack's): every
//! field of `2;` and 15 MiB of `;` was once collected before the count was checked (286 MB
//! for a 15 MiB text). The text is refused by its length, naming the field, within an address
//! space that the text and the file it sits in need, not more.

use super::limits::{crafted, driftlab_within};

/// The address space the runs get: the binary, its threads, the 15 MiB calibration file read
/// and its text parsed once (about 40 MB resident), and room to spare; the collected fields
/// needed 256 MiB more.
const LIMIT_MIB: u64 = 160;

#[test]
fn a_sketch_of_megabytes_is_refused_by_its_length_within_a_small_memory() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sample = |name: &str| format!("{}/sample_logs/{name}", env!("CARGO_MANIFEST_DIR"));
    let cal = d.join("cal.json").display().to_string();
    driftlab_within(
        d,
        1024,
        &["calibrate", &sample("calibration.csv"), "-o", &cal],
    )
    .succeeds();
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    for (name, text) in [
        ("semis.json", format!("2;{}", ";".repeat(15 << 20))),
        ("colons.json", format!("2;-;-;{};", ":".repeat(15 << 20))),
    ] {
        *json
            .pointer_mut("/calibration/source/samples_sketch")
            .expect("a sketch") = text.into();
        let edited = crafted(d, name, json.to_string().as_bytes());
        let ran = driftlab_within(
            d,
            LIMIT_MIB,
            &["evaluate", &edited, &sample("validation.csv")],
        );
        ran.fails_with(
            "source.samples_sketch: is not a sketch of a run's samples: it is",
            900,
        );
        assert!(
            ran.stderr.contains("bytes long, and a sketch is at most"),
            "{}",
            ran.stderr
        );
    }
}
