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

/// Why a format message or a type it names cannot be used; the reader puts the byte offset of
/// the message in front.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(super) enum FormatError {
    /// A type defined through itself, or nested past 16 levels.
    #[error("type {0} nests deeper than 16 levels")]
    TooDeep(String),
    /// A type that is neither a scalar nor a format defined before.
    #[error("type {0} is neither a base type nor a defined format")]
    UnknownType(String),
    /// A type larger than the 65 535 bytes of a message.
    #[error("type {0} is larger than a message can be")]
    TooLarge(String),
    /// A format message without the `:` after its name.
    #[error("format \"{0}\" has no ':'")]
    NoName(String),
    /// A field that is not `type name`.
    #[error("field \"{field}\" of format {format} is not \"type name\"")]
    Field {
        /// The field as written.
        field: String,
        /// The format it is in.
        format: String,
    },
    /// An array type whose length does not read.
    #[error("array type \"{ty}\" of format {format} is malformed")]
    Array {
        /// The type as written.
        ty: String,
        /// The format it is in.
        format: String,
    },
}

/// The size of a type of the format language, nested formats included.
pub(super) fn type_size(
    ty: &str,
    formats: &HashMap<String, Vec<FieldDef>>,
    depth: usize,
) -> Result<usize, FormatError> {
    if let Some(b) = Base::parse(ty) {
        return Ok(b.size());
    }
    if depth > 16 {
        return Err(FormatError::TooDeep(ty.to_string()));
    }
    let fields = formats
        .get(ty)
        .ok_or_else(|| FormatError::UnknownType(ty.to_string()))?;
    let mut sum = 0usize;
    for f in fields {
        let s = type_size(&f.ty, formats, depth + 1)?;
        sum = s
            .checked_mul(f.count)
            .and_then(|x| x.checked_add(sum))
            .filter(|&x| x <= usize::from(u16::MAX))
            .ok_or_else(|| FormatError::TooLarge(ty.to_string()))?;
    }
    Ok(sum)
}

/// Parses `name:type a;type[3] b;`.
pub(super) fn parse_format(text: &str) -> Result<(String, Vec<FieldDef>), FormatError> {
    let (name, rest) = text
        .split_once(':')
        .ok_or_else(|| FormatError::NoName(text.to_string()))?;
    let mut fields = Vec::new();
    for part in rest.split(';').filter(|p| !p.is_empty()) {
        let (ty, fname) = part.split_once(' ').ok_or_else(|| FormatError::Field {
            field: part.to_string(),
            format: name.to_string(),
        })?;
        let (ty, count) = match ty.split_once('[') {
            Some((t, n)) => {
                let n = n
                    .strip_suffix(']')
                    .and_then(|n| n.parse::<usize>().ok())
                    .ok_or_else(|| FormatError::Array {
                        ty: ty.to_string(),
                        format: name.to_string(),
                    })?;
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
