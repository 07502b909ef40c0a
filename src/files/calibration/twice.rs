//! A key given twice in one object of a calibration or recipe file is refused: a JSON reader
//! keeps the last of them, and a merge or a hand edit that left two lines of one field (two
//! `px4_device_id`s in the record of the gyro, which chooses the chip another log's
//! calibration is applied to) would act on one of them without a word. The file's structs
//! refuse a field given twice themselves; the parts read through a JSON value first (the
//! record of the gyro, a unit's axes) cannot see it, so the whole text is walked once for it.

use serde::Deserializer as _;
use serde::de::{self, Deserialize, MapAccess, SeqAccess, Visitor};
use std::collections::HashSet;

/// The first key given twice in one object of `text`, as an error naming it with its line and
/// column; `Ok` for a text without one, and for malformed JSON, which the file's reader then
/// refuses in its own words.
pub(super) fn no_key_twice(text: &str) -> Result<(), serde_json::Error> {
    let mut de = serde_json::Deserializer::from_str(text);
    match (&mut de).deserialize_any(Walk) {
        Err(e) if e.classify() == serde_json::error::Category::Data => Err(e),
        _ => Ok(()),
    }
}

/// Walks a JSON value, refusing an object's key given twice.
struct Walk;

/// A value walked by [`Walk`].
struct Walked;

impl<'de> Deserialize<'de> for Walked {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Walked, D::Error> {
        d.deserialize_any(Walk).map(|()| Walked)
    }
}

impl<'de> Visitor<'de> for Walk {
    type Value = ();

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let mut seen = HashSet::new();
        while let Some(key) = map.next_key::<String>()? {
            if !seen.insert(key.clone()) {
                return Err(de::Error::custom(format!(
                    "the field `{}` is given twice in one object (a JSON reader would keep the \
                     last, without a word)",
                    crate::text::escaped(&key, false)
                )));
            }
            map.next_value::<Walked>()?;
        }
        Ok(())
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        while seq.next_element::<Walked>()?.is_some() {}
        Ok(())
    }

    fn visit_bool<E: de::Error>(self, _: bool) -> Result<(), E> {
        Ok(())
    }
    fn visit_i64<E: de::Error>(self, _: i64) -> Result<(), E> {
        Ok(())
    }
    fn visit_u64<E: de::Error>(self, _: u64) -> Result<(), E> {
        Ok(())
    }
    fn visit_f64<E: de::Error>(self, _: f64) -> Result<(), E> {
        Ok(())
    }
    fn visit_str<E: de::Error>(self, _: &str) -> Result<(), E> {
        Ok(())
    }
    fn visit_unit<E: de::Error>(self) -> Result<(), E> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::no_key_twice;

    #[test]
    fn a_key_twice_in_any_object_is_named_with_its_place() {
        let e = no_key_twice("{\"a\": {\"i\": 1,\n \"d\": 2, \"d\": 3}}").unwrap_err();
        let text = e.to_string();
        assert!(text.contains("the field `d` is given twice"), "{text}");
        assert!(text.contains("line 2"), "{text}");
        assert!(no_key_twice("[{\"d\": 1}, {\"d\": 2}]").is_ok());
        assert!(no_key_twice("{\"a\": [1, 2, {\"b\": null}], \"c\": true}").is_ok());
        // Malformed JSON is left to the file's reader.
        assert!(no_key_twice("{\"a\": ").is_ok());
    }
}
