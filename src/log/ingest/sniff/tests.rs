//! Unit tests of record splitting and of a header split at wide gaps.

use super::*;

fn split(s: &str, d: Delim) -> Vec<String> {
    let mut out = Vec::new();
    let _ = split_fields(s.as_bytes(), d, &mut out);
    out.iter()
        .map(|f| String::from_utf8_lossy(f).into_owned())
        .collect()
}

#[test]
fn splits_quotes_padding_and_trailing_separators() {
    assert_eq!(split("a, b ,c", Delim::Byte(b',')), ["a", "b", "c"]);
    assert_eq!(
        split("\"1,5\",\"x\"\"y\"", Delim::Byte(b',')),
        ["1,5", "x\"y"]
    );
    assert_eq!(split("1,2,", Delim::Byte(b',')), ["1", "2", ""]);
    assert_eq!(split("  1  2\t3 ", Delim::Whitespace), ["1", "2", "3"]);
    assert_eq!(split("", Delim::Whitespace), Vec::<String>::new());
    let mut out = Vec::new();
    assert!(split_fields(b"1,\"open", Delim::Byte(b','), &mut out).is_err());
    assert_eq!(
        split_wide("Time [s]   Rate [deg/h]\tT"),
        ["Time [s]", "Rate [deg/h]", "T"]
    );
}
