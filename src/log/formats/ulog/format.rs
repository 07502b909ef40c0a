//! The format language of ULog's `F` messages: the scalar types, a topic's fields and where
//! each lies in its payload. Apart from the message walk because it is a small grammar of its
//! own, read once per format and tested alone.

use std::collections::HashMap;

/// A scalar type of the format language.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Base {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
    Bool,
    Char,
}

impl Base {
    pub(super) fn parse(s: &str) -> Option<Base> {
        Some(match s {
            "int8_t" => Base::I8,
            "uint8_t" => Base::U8,
            "int16_t" => Base::I16,
            "uint16_t" => Base::U16,
            "int32_t" => Base::I32,
            "uint32_t" => Base::U32,
            "int64_t" => Base::I64,
            "uint64_t" => Base::U64,
            "float" => Base::F32,
            "double" => Base::F64,
            "bool" => Base::Bool,
            "char" => Base::Char,
            _ => return None,
        })
    }

    pub(super) fn size(self) -> usize {
        match self {
            Base::I8 | Base::U8 | Base::Bool | Base::Char => 1,
            Base::I16 | Base::U16 => 2,
            Base::I32 | Base::U32 | Base::F32 => 4,
            Base::I64 | Base::U64 | Base::F64 => 8,
        }
    }
}

/// One field of a format message: `type[n] name`.
#[derive(Debug, Clone)]
pub(super) struct FieldDef {
    pub(super) ty: String,
    pub(super) count: usize,
    pub(super) name: String,
}

/// A top-level field located in a topic's payload.
#[derive(Debug, Clone, Copy)]
pub(super) struct Located {
    pub(super) base: Option<Base>,
    pub(super) offset: usize,
    pub(super) count: usize,
}

/// The size of a type of the format language, nested formats included.
pub(super) fn type_size(
    ty: &str,
    formats: &HashMap<String, Vec<FieldDef>>,
    depth: usize,
) -> Result<usize, String> {
    if let Some(b) = Base::parse(ty) {
        return Ok(b.size());
    }
    if depth > 16 {
        return Err(format!("type {ty} nests deeper than 16 levels"));
    }
    let fields = formats
        .get(ty)
        .ok_or_else(|| format!("type {ty} is neither a base type nor a defined format"))?;
    let mut sum = 0usize;
    for f in fields {
        let s = type_size(&f.ty, formats, depth + 1)?;
        sum = s
            .checked_mul(f.count)
            .and_then(|x| x.checked_add(sum))
            .filter(|&x| x <= usize::from(u16::MAX))
            .ok_or_else(|| format!("type {ty} is larger than a message can be"))?;
    }
    Ok(sum)
}

/// Parses `name:type a;type[3] b;`.
pub(super) fn parse_format(text: &str) -> Result<(String, Vec<FieldDef>), String> {
    let (name, rest) = text
        .split_once(':')
        .ok_or_else(|| format!("format \"{text}\" has no ':'"))?;
    let mut fields = Vec::new();
    for part in rest.split(';').filter(|p| !p.is_empty()) {
        let (ty, fname) = part
            .split_once(' ')
            .ok_or_else(|| format!("field \"{part}\" of format {name} is not \"type name\""))?;
        let (ty, count) = match ty.split_once('[') {
            Some((t, n)) => {
                let n = n
                    .strip_suffix(']')
                    .and_then(|n| n.parse::<usize>().ok())
                    .ok_or_else(|| format!("array type \"{ty}\" of format {name} is malformed"))?;
                (t, n)
            }
            None => (ty, 1),
        };
        fields.push(FieldDef {
            ty: ty.to_string(),
            count,
            name: fname.to_string(),
        });
    }
    Ok((name.to_string(), fields))
}
