//! The time units a column's name may state (`time_ms`, `time [d]`, `time_ms_since_boot`), the
//! words that may be a unit or mean something else (`time_d`, `time_ds`), and the counts of a
//! unit that are ticks (`time_100us`, `time [10 ms]`).

use super::{Words, count_of, counted, one_of, shaped, slot_words};
use crate::log::ingest::units::{TimeUnit, unit_key};

/// A word as a time unit among a name's words: `d` and `ds` may mean something else, a
/// one-letter unit counts only as the last word, a sample count only there too.
fn time_word(words: &[String], i: usize) -> Words<TimeUnit> {
    let w = unit_key(&words[i]);
    let last = i + 1 == words.len();
    let show = || words[i].clone();
    match w.as_str() {
        "d" => {
            return Words::Either {
                words: show(),
                may_be: "days (d), or a delta".into(),
            };
        }
        "ds" => {
            return Words::Either {
                words: show(),
                may_be: "deciseconds (ds), or downsampled".into(),
            };
        }
        // `time_of_day_s`: a day is what the time is of, not its unit.
        "day" => return Words::None,
        _ => {}
    }
    // A count of a unit glued to it: `100us`.
    let digits = w.chars().take_while(char::is_ascii_digit).count();
    if digits > 0 && digits < w.len() {
        return match (w[..digits].parse::<f64>(), TimeUnit::from_key(&w[digits..])) {
            // One of a unit is that unit (`1s`).
            (Ok(1.0), Some(u)) => Words::Unit {
                unit: u,
                at: i,
                end: i + 1,
            },
            (Ok(n), Some(u)) if n > 0.0 => match u.to_s_factor() {
                Some(f) => Words::Ticks {
                    words: show(),
                    seconds: n * f,
                },
                None => Words::None,
            },
            _ => Words::None,
        };
    }
    match TimeUnit::from_key(&w) {
        Some(TimeUnit::Samples) if !last => Words::None,
        Some(_) if w.chars().count() < 2 && !last => Words::None,
        Some(u) => {
            // A count before it: `time_10_ms`.
            if let Some(prev) = i.checked_sub(1).map(|p| &words[p])
                && !prev.is_empty()
                && prev.chars().all(|c| c.is_ascii_digit())
                && let (Ok(n), Some(f)) = (prev.parse::<f64>(), u.to_s_factor())
                && n != 1.0
                && n > 0.0
            {
                return Words::Ticks {
                    words: format!("{prev}_{}", words[i]),
                    seconds: n * f,
                };
            }
            Words::Unit {
                unit: u,
                at: i,
                end: i + 1,
            }
        }
        None => Words::None,
    }
}

/// The time unit the words of a name from `from` on state (see the module's rules).
pub(crate) fn time_in_words(words: &[String], from: usize) -> Words<TimeUnit> {
    let mut found = Vec::new();
    for i in from..words.len() {
        match time_word(words, i) {
            Words::Unit { unit, at, end } => found.push((at, end, unit)),
            Words::None => {}
            other => return other,
        }
    }
    one_of(words, found, |u| u.to_string())
}

/// The time unit written where a unit is written alone (`d`, `ms`), or among that text's
/// words (`ms since boot`, after ` in `), unless a number counts it (`10 ms`).
pub(crate) fn time_in_slot(text: &str) -> Option<TimeUnit> {
    if counted(text) {
        // One of a unit is that unit (`1 s`).
        return count_of(text)
            .filter(|&(n, _)| n == 1.0)
            .and_then(|(_, u)| TimeUnit::from_key(&unit_key(u)));
    }
    if let Some(u) = TimeUnit::from_key(&unit_key(text)) {
        return Some(u);
    }
    // Not the `s` of `deg/s`.
    if shaped(text) {
        return None;
    }
    match time_in_words(&slot_words(text), 0) {
        Words::Unit { unit, .. } => Some(unit),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(s: &str) -> Vec<String> {
        super::super::super::name_parts(s).words
    }

    #[test]
    fn times_among_words() {
        let t = |s: &str| time_in_words(&words(s), 1);
        assert!(matches!(
            t("time_ms_since_boot"),
            Words::Unit {
                unit: TimeUnit::Millis,
                ..
            }
        ));
        assert!(matches!(
            t("time_of_day_s"),
            Words::Unit {
                unit: TimeUnit::Seconds,
                ..
            }
        ));
        assert!(matches!(t("time_s_rel"), Words::None));
        assert!(matches!(t("time_ds"), Words::Either { .. }));
        assert!(
            matches!(t("time_100us"), Words::Ticks { seconds, .. } if (seconds - 1e-4).abs() < 1e-18)
        );
        assert!(matches!(t("time_10_ms"), Words::Ticks { .. }));
        assert!(matches!(
            t("time_1_s"),
            Words::Unit {
                unit: TimeUnit::Seconds,
                ..
            }
        ));
        assert_eq!(time_in_slot("1 ms"), Some(TimeUnit::Millis));
        assert_eq!(time_in_slot("10 ms"), None);
    }
}
