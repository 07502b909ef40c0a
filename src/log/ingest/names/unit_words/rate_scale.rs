//! A rate unit with a scale beside it: a number (`omega [deg/s/1000]`, `omega [deg/s x 1e-3]`,
//! `omega [deg/s]/1000`, `omega (deg/s)*1000`, `omega_dps_div1000`, `omega_dps_x1000`), a
//! fraction (`omega [deg/s] (1/1000)`), a percentage (`omega [% of deg/s]`, `omega [deg/s] ‰`,
//! `omega [ppm deg/s]`), a word that scales (`omega [deg/s] per 1000`,
//! `omega [thousandths of deg/s]`, `omega [deg/s] (milli)`, `omega_dps_k`), a count of the
//! unit (`omega_1000dps`, `omega_1000_dps`), or a number glued after the unit (`omega_dps3`,
//! `omega_mdps2`, `gyro_x_rad_s2`). Read as the unit beside it, the column would be a thousand
//! times off (or, with the number glued to the unit, read in the default deg/h, 3.6 times
//! off), and no check of the values could tell: a rate has no range a value must keep to.
//! Words after a unit still qualify the column (`omega_dps_raw`, `Rate [deg/h] (gyro 2)`):
//! only a scale right beside the unit (`of` and `in` between are skipped), or glued to it,
//! is one.
//!
//! A sensor's or an axis's number is no scale wherever it stands, when it is glued to the
//! word it numbers (`gyro2_dps`, `gyro1_dps`, `imu2_omega_dps`, `omega_x1_dps`,
//! `omega_dps_imu2`). A number standing alone beside the unit (`gyro_2_dps`, `omega_dps_3`)
//! may be a sensor's or a scale: the two cannot be told apart there, so it is refused, and the
//! message says how a sensor's number is read. `x` glued to a number beside a unit is a
//! multiplier (`omega_dps_x1000`, `omega_x2_dps`), unless the number is a one (`x1`).

use super::super::NameParts;
use super::{StatedRate, Words, counted, is_note, rate_in_slot, rate_in_words, slot_words};

/// Words that multiply or divide what is before them by the number after them (`x 1000`,
/// `div 1000`, `1e-3` split into `1e` and `3` being numbers already).
const SCALE_SIGNS: &[&str] = &["x", "times", "mul", "by", "div", "over", "e"];

/// Words without a digit that scale a unit beside them: `per` (what follows divides the unit:
/// `deg/s per 1000`, or makes it another quantity: `deg/s per LSB`, a scale factor), the
/// prefixes and their names (`k`, `milli`), the number words (`thousandths`), the ratios
/// (`ppm`, `percent`) and the words that say a scale (`scaled`). Lower case, as a name's words
/// are.
const SCALE_WORDS: &[&str] = &[
    "per",
    "k",
    "kilo",
    "mega",
    "m",
    "milli",
    "u",
    "µ",
    "μ",
    "micro",
    "n",
    "nano",
    "centi",
    "deci",
    "ten",
    "tens",
    "tenth",
    "tenths",
    "hundred",
    "hundreds",
    "hundredth",
    "hundredths",
    "thousand",
    "thousands",
    "thousandth",
    "thousandths",
    "million",
    "millions",
    "millionth",
    "millionths",
    "ppm",
    "ppb",
    "pct",
    "percent",
    "permille",
    "permil",
    "scale",
    "scaled",
    "scaling",
];

/// Words that join a scale to a unit without being either (`thousandths of deg/s`): skipped
/// when looking beside the unit.
const JOINING_WORDS: &[&str] = &["of", "in"];

/// The signs of a ratio, which a name's words (runs of letters and digits) do not keep.
const RATIO_SIGNS: &[char] = &['%', '‰', '‱'];

/// Whether `word` holds a digit (any script's: `²` and `½` too).
fn has_digit(word: &str) -> bool {
    word.chars().any(char::is_numeric)
}

/// Whether `word` is a sensor's or an axis's number: the letters of a word that names one (a
/// note or a role word: `gyro`, `imu`, `sensor`, `y`) with digits glued after them (`gyro2`,
/// `imu1`, `y2`). Not `x` (a multiplier: `x1000`), nor a scale word (`k2`).
fn sensor_number(word: &str) -> bool {
    let letters = word.trim_end_matches(char::is_numeric);
    letters.len() < word.len()
        && !letters.is_empty()
        && letters.chars().all(char::is_alphabetic)
        && !SCALE_SIGNS.contains(&letters)
        && !SCALE_WORDS.contains(&letters)
        && is_note(letters)
}

/// Whether `word` (a lower-case word of a name or of a unit slot) scales a unit beside it: a
/// scale word ([`SCALE_WORDS`]), or a word that holds a digit (`1000`, the `1e` and `3` of
/// `1e-3`, `x1000`, `div1000`, `2nd`, `10s`, `²`) unless it is a one (`1`, `x1`: one of a unit
/// is that unit; the `1` of `deg s-1` and the `¹` of `deg·s⁻¹`, the unit's own exponent) or a
/// sensor's number ([`sensor_number`]).
fn is_scale(word: &str) -> bool {
    if SCALE_WORDS.contains(&word) {
        return true;
    }
    let number = SCALE_SIGNS
        .iter()
        .find_map(|s| {
            word.strip_prefix(s)
                .filter(|r| r.starts_with(char::is_numeric))
        })
        .unwrap_or(word);
    has_digit(word) && !matches!(number, "1" | "¹") && !sensor_number(word)
}

/// The index of the word next to `i` in the direction `step` (-1 before, +1 after), past
/// any [`JOINING_WORDS`].
fn beside(words: &[String], i: usize, step: isize) -> Option<usize> {
    let mut j = i.checked_add_signed(step)?;
    while JOINING_WORDS.contains(&words.get(j)?.as_str()) {
        j = j.checked_add_signed(step)?;
    }
    words.get(j).map(|_| j)
}

/// The words of a scale right beside the unit at `words[at..end]`, with the unit's: from the
/// word before it when that scales (`1000_dps`, `thousandths_of_dps`), to the word after it
/// when that scales (`dps_div1000`, `dps_k`), to the word after `per` (`dps_per_1000`,
/// `dps_per_lsb`), to the number after a sign that follows it (`dps_x_1000`), or to the
/// denominator of a fraction that follows it (`dps_1_1000`, as `(1/1000)` is written).
fn scale_around(words: &[String], at: usize, end: usize) -> Option<(usize, usize)> {
    if let Some(b) = beside(words, at, -1)
        && is_scale(&words[b])
    {
        return Some((b, end));
    }
    let a = beside(words, end - 1, 1)?;
    match &words[a..] {
        // `per` and what it is per (`per_1000`, `per_lsb`).
        [per, _, ..] if per == "per" => Some((at, a + 2)),
        [sign, n, ..] if (SCALE_SIGNS.contains(&sign.as_str()) || sign == "1") && is_scale(n) => {
            Some((at, a + 2))
        }
        [w, ..] if is_scale(w) => Some((at, a + 1)),
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

/// A word that is a rate unit with a number glued to it, before (`1000dps`, `10mrads`: a count
/// of the unit, as `time_100us` is a count of microseconds) or after (`dps3`, `mdps2`, the
/// `s2` of `rad_s2`: a scale, a sensor's number or a square, which cannot be told apart), as
/// the words of the unit it ends: not the unit it holds. A one before the unit counts too
/// (`1dps`): glued, the unit is not the word the reader reads.
fn glued_unit(words: &[String]) -> Option<String> {
    words.iter().enumerate().find_map(|(i, word)| {
        let lead = word.chars().take_while(char::is_ascii_digit).count();
        if lead > 0 && lead < word.len() {
            return StatedRate::from_words(&[word[lead..].to_string()]).map(|_| word.clone());
        }
        let letters = word.trim_end_matches(char::is_numeric);
        if letters.len() == word.len() || letters.is_empty() {
            return None;
        }
        // The unit may take words before this one (`rad` of `rad_s2`).
        (i.saturating_sub(3)..=i).find_map(|from| {
            let mut unit = words[from..i].to_vec();
            unit.push(letters.to_string());
            StatedRate::from_words(&unit).map(|_| words[from..=i].join("_"))
        })
    })
}

/// The ratio signs in `text`, as written (`‰`, `%`).
fn ratio_signs(text: &str) -> String {
    text.chars().filter(|c| RATIO_SIGNS.contains(c)).collect()
}

/// The rate unit with a scale beside it that the name `p` states, as written (`deg/s/1000`,
/// `[deg/s] 1000`, `dps_x1000`, `1000dps`, `dps3`, `% of deg/s`, `[deg/s] ‰`), if it states
/// one: where a unit is written alone (a scale inside that text, or right before or after the
/// brackets), or among the name's words. Such a name states no unit the reader reads: the one
/// rule by which a rate column's unit is not taken from its name (`classify`, `stated_rate`)
/// and its read is refused (`unread_unit`).
pub(crate) fn rate_scale(p: &NameParts) -> Option<String> {
    if let Some(text) = p.unit.as_deref().filter(|t| !counted(t)) {
        let text = text.trim();
        let words = slot_words(text);
        let rate = rate_in_slot(text).is_some();
        if scaled_in(&words).is_some()
            || glued_unit(&words).is_some()
            || (rate && !ratio_signs(text).is_empty())
        {
            return Some(text.to_string());
        }
        if rate {
            // The brackets as one word among the name's, where they stood.
            let mut words = p.words.clone();
            words.insert(p.unit_at, format!("[{text}]"));
            if let Some((from, to)) = scale_around(&words, p.unit_at, p.unit_at + 1) {
                return Some(words[from..to].join(" "));
            }
            let signs = ratio_signs(&p.base);
            if !signs.is_empty() {
                return Some(format!("[{text}] {signs}"));
            }
        }
    }
    if let Some(text) = scaled_in(&p.words).or_else(|| glued_unit(&p.words)) {
        return Some(text);
    }
    // A ratio sign anywhere in a name whose words state a rate unit (`omega_dps_%`).
    let signs = ratio_signs(&p.base);
    if signs.is_empty() {
        return None;
    }
    match rate_in_words(&p.words, 0) {
        Words::Unit { at, end, .. } => Some(format!("{} {signs}", p.words[at..end].join("_"))),
        _ => None,
    }
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
            // A fraction, a ratio, a word that scales.
            ("omega [deg/s] (1/1000)", "[deg/s] 1 1000"),
            ("omega [deg/s 1/1000]", "deg/s 1/1000"),
            ("omega [deg/s] per 1000", "[deg/s] per 1000"),
            ("omega_dps_per_lsb", "dps_per_lsb"),
            ("omega [thousandths of deg/s]", "thousandths of deg/s"),
            ("omega_thousandths_of_dps", "thousandths_of_dps"),
            ("omega [deg/s] (milli)", "[deg/s] milli"),
            ("omega [deg/s] (scaled by 1000)", "[deg/s] scaled"),
            ("omega [deg/s] ‰", "[deg/s] ‰"),
            ("omega [% of deg/s]", "% of deg/s"),
            ("omega [ppm deg/s]", "ppm deg/s"),
            ("omega_dps_%", "dps %"),
            ("omega_dps_k", "dps_k"),
            ("omega_k_dps", "k_dps"),
            ("omega_dps_²", "dps_²"),
            // A number glued to the unit, after it or (a one too) before it.
            ("omega_dps3", "dps3"),
            ("omega_mdps2", "mdps2"),
            ("gyro_x_rad_s2", "rad_s2"),
            ("omega [dps3]", "dps3"),
            ("omega_1dps", "1dps"),
            // A number alone beside the unit, whether a sensor's or a scale.
            ("gyro_2_dps", "2_dps"),
            ("omega_dps_3", "dps_3"),
            ("omega [deg/s] #2", "[deg/s] 2"),
            ("omega_x2_dps", "x2_dps"),
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
            // A sensor's or an axis's number glued to its word, wherever it stands.
            "gyro1_dps",
            "imu2_omega_dps",
            "omega_x1_dps",
            "omega_y2_dps",
            "omega_dps_imu2",
            "gyro_x2_raw_dps",
            "Rate (deg/s, gyro 2)",
            "Rate (deg/s) gyro 2",
            "omega [deg/s, filtered]",
            "omega_m_dps",
            "omega_deg_per_min",
            "omega [degrees per minute]",
            "omega [deg s-1]",
            "omega [deg·s⁻¹]",
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
