//! A rate unit with a number beside it: a scale (`omega [deg/s/1000]`, `omega [deg/s x 1e-3]`,
//! `omega [deg/s]/1000`, `omega (deg/s)*1000`, `omega_dps_div1000`, `omega_dps_x1000`) or a
//! count of the unit (`omega_1000dps`, `omega_1000_dps`). Read as the unit beside it, the
//! column would be a thousand times off (or, with the count glued to the unit, read in the
//! default deg/h, 3.6 times off), and no check of the values could tell: a rate has no range
//! a value must keep to. The number may also be a sensor's (`gyro 2 [deg/s]`); either way
//! the unit is not the one written, and the reader asks for it. Words after a unit still
//! qualify the column (`omega_dps_raw`, `Rate [deg/h] (gyro 2)`): only a number, or a sign
//! of a product or a quotient with one, right beside the unit is a scale.

use super::super::NameParts;
use super::{StatedRate, Words, counted, rate_in_slot, rate_in_words, slot_words};

/// Words that multiply or divide what is before them by the number after them (`x 1000`,
/// `div 1000`, `1e-3` split into `1e` and `3` being numbers already).
const SCALE_SIGNS: &[&str] = &["x", "times", "mul", "by", "div", "over", "e"];

/// Whether `word` (a lower-case word of a name or of a unit slot) is a scale: a number
/// (`1000`, the `1e` and `3` of `1e-3`), or a multiplier or divisor glued to one (`x1000`,
/// `div1000`, `e3`). A one (`1`, `x1`) scales nothing, as one of a unit is that unit.
fn is_scale(word: &str) -> bool {
    let starts_with_digit = |w: &str| w.starts_with(|c: char| c.is_ascii_digit());
    let number = SCALE_SIGNS
        .iter()
        .find_map(|s| word.strip_prefix(s).filter(|r| starts_with_digit(r)))
        .unwrap_or(word);
    starts_with_digit(number) && number != "1"
}

/// The words of a scale right beside the unit at `words[at..end]`, with the unit's: from the
/// word before it when that is a number (`1000_dps`), to the word after it when that is one
/// (`dps_div1000`), or to the number after a sign that follows it (`dps_x_1000`).
fn scale_around(words: &[String], at: usize, end: usize) -> Option<(usize, usize)> {
    if at > 0 && is_scale(&words[at - 1]) {
        return Some((at - 1, end));
    }
    match &words[end..] {
        [a, ..] if is_scale(a) => Some((at, end + 1)),
        [sign, n, ..] if SCALE_SIGNS.contains(&sign.as_str()) && is_scale(n) => Some((at, end + 2)),
        _ => None,
    }
}

/// The one rate unit `words` state with a scale beside it, as those words joined by `_`.
fn scaled_in(words: &[String]) -> Option<String> {
    let Words::Unit { at, end, .. } = rate_in_words(words, 0) else {
        return None;
    };
    let (from, to) = scale_around(words, at, end)?;
    Some(words[from..to].join("_"))
}

/// A word that is a rate unit glued after a count of it (`1000dps`, `10mrads`), as
/// `time_100us` is a count of microseconds: not the unit it ends with.
fn counted_unit(word: &str) -> bool {
    let digits = word.chars().take_while(char::is_ascii_digit).count();
    digits > 0
        && digits < word.len()
        && &word[..digits] != "1"
        && StatedRate::from_words(&[word[digits..].to_string()]).is_some()
}

/// The rate unit with a number beside it that the name `p` states, as written (`deg/s/1000`,
/// `[deg/s] 1000`, `dps_x1000`, `1000dps`), if it states one: where a unit is written alone
/// (a number inside that text, or right before or after the brackets), or among the name's
/// words. Such a name states no unit the reader reads: the one rule by which a rate column's
/// unit is not taken from its name (`classify`, `stated_rate`) and its read is refused
/// (`unread_unit`).
pub(crate) fn rate_scale(p: &NameParts) -> Option<String> {
    if let Some(text) = p.unit.as_deref().filter(|t| !counted(t)) {
        let text = text.trim();
        if scaled_in(&slot_words(text)).is_some() {
            return Some(text.to_string());
        }
        if rate_in_slot(text).is_some() {
            // The brackets as one word among the name's, where they stood.
            let mut words = p.words.clone();
            words.insert(p.unit_at, format!("[{text}]"));
            if let Some((from, to)) = scale_around(&words, p.unit_at, p.unit_at + 1) {
                return Some(words[from..to].join(" "));
            }
        }
    }
    scaled_in(&p.words).or_else(|| p.words.iter().find(|w| counted_unit(w)).cloned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scale(name: &str) -> Option<String> {
        rate_scale(&super::super::super::name_parts(name))
    }

    #[test]
    fn numbers_beside_a_rate_unit_are_scales() {
        for (name, shown) in [
            ("omega [deg/s/1000]", "deg/s/1000"),
            ("omega [deg/s x 1e-3]", "deg/s x 1e-3"),
            ("omega [deg/s]/1000", "[deg/s] 1000"),
            ("omega (deg/s)*1000", "[deg/s] 1000"),
            ("omega 1000*[deg/s]", "1000 [deg/s]"),
            ("omega [deg/s] x 1000", "[deg/s] x 1000"),
            ("omega_dps_div1000", "dps_div1000"),
            ("omega_dps_x1000", "dps_x1000"),
            ("omega_dps_x_1000", "dps_x_1000"),
            ("omega_1000dps", "1000dps"),
            ("omega_1000_dps", "1000_dps"),
            ("gyro_x_rad_s_1e3", "rad_s_1e3"),
        ] {
            assert_eq!(scale(name).as_deref(), Some(shown), "{name}");
        }
    }

    #[test]
    fn words_after_a_unit_and_ones_are_no_scales() {
        for name in [
            "omega_dps",
            "omega_dps_raw",
            "gyro_x_dps_avg",
            "w_rad_s_x",
            "Rate [deg/h] (gyro 2)",
            "Rate (deg/s, filtered)",
            "gyro2_dps",
            "omega (imu1)",
            "omega_1_dps",
            "omega [deg/s] x1",
            "omega_dps_x",
            "time_1000",
            "omega",
        ] {
            assert_eq!(scale(name), None, "{name}");
        }
    }
}
