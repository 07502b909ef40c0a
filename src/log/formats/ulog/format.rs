//! The format language of ULog's `F` messages: the scalar types, a topic's fields and where
//! each lies in its payload. Apart from the message walk because it is a small grammar of its
//! own, read once per format and tested alone.

use crate::log::formats::error::quoted;
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
#[derive(Debug, Clone, PartialEq)]
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

/// The deepest nesting of formats the reader follows.
pub(super) const MAX_DEPTH: usize = 16;

/// The most a type can take: the 65 535 bytes of a message.
pub(super) const MAX_SIZE: usize = u16::MAX as usize;

/// Why a format message or a type it names cannot be used; the reader puts the byte offset of
/// the message in front. Names are quoted to a readable length.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(super) enum FormatError {
    /// A type defined through itself, or nested past 16 levels.
    #[error("type {0} nests deeper than 16 levels")]
    TooDeep(String),
    /// A type that is neither a scalar nor a format defined before.
    #[error("type {0} is neither a base type nor a defined format")]
    UnknownType(String),
    /// A type larger than the 65 535 bytes of a message.
    #[error("type {0} is larger than a message can be (65535 bytes)")]
    TooLarge(String),
    /// Formats redefined over and over between subscriptions: working out their sizes again
    /// and again would take longer than the file is worth.
    #[error(
        "working out the sizes of the formats takes more than {0} steps (formats redefined \
         over and over?)"
    )]
    TooMuchWork(usize),
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

/// A name as an error quotes it.
fn q(s: &str) -> String {
    quoted(s).into_owned()
}

/// The sizes of the types of the format language, each worked out once (16 levels of formats
/// of 4 fields each are 4^16 walks without it, 17 with it), with the depth and size limits,
/// and a bound on the work of a file whose formats are redefined between subscriptions
/// (each redefinition forgets what was worked out).
pub(super) struct Sizes {
    /// Type → its size and height (levels of formats from it down to scalars, 1 for a format
    /// of scalars).
    known: HashMap<String, (usize, usize)>,
    steps: usize,
    budget: usize,
}

impl Sizes {
    /// Sizes for a file of `file_len` bytes: its walks may visit 2^20 fields, plus 8 per
    /// byte of the file (a file that defines each format once visits each field once).
    pub(super) fn for_file(file_len: usize) -> Sizes {
        Sizes {
            known: HashMap::new(),
            steps: 0,
            budget: (1 << 20) + file_len.saturating_mul(8),
        }
    }

    /// Forgets every size worked out: a format was redefined.
    pub(super) fn forget(&mut self) {
        self.known.clear();
    }

    /// The size of type `ty`, nested formats included.
    pub(super) fn size(
        &mut self,
        ty: &str,
        formats: &HashMap<String, Vec<FieldDef>>,
    ) -> Result<usize, FormatError> {
        self.walk(ty, formats, 0).map(|(size, _)| size)
    }

    /// Size and height of `ty`, reached at `depth`: a format deeper than [`MAX_DEPTH`] is an
    /// error whether it was worked out before or not.
    fn walk(
        &mut self,
        ty: &str,
        formats: &HashMap<String, Vec<FieldDef>>,
        depth: usize,
    ) -> Result<(usize, usize), FormatError> {
        if let Some(b) = Base::parse(ty) {
            return Ok((b.size(), 0));
        }
        if let Some(&(size, height)) = self.known.get(ty) {
            if depth + height - 1 > MAX_DEPTH {
                return Err(FormatError::TooDeep(q(ty)));
            }
            return Ok((size, height));
        }
        if depth > MAX_DEPTH {
            return Err(FormatError::TooDeep(q(ty)));
        }
        let fields = formats
            .get(ty)
            .ok_or_else(|| FormatError::UnknownType(q(ty)))?;
        let mut sum = 0usize;
        let mut height = 0usize;
        for f in fields {
            self.steps += 1;
            if self.steps > self.budget {
                return Err(FormatError::TooMuchWork(self.budget));
            }
            let (s, h) = self.walk(&f.ty, formats, depth + 1)?;
            height = height.max(h);
            sum = s
                .checked_mul(f.count)
                .and_then(|x| x.checked_add(sum))
                .filter(|&x| x <= MAX_SIZE)
                .ok_or_else(|| FormatError::TooLarge(q(ty)))?;
        }
        self.known.insert(ty.to_string(), (sum, height + 1));
        Ok((sum, height + 1))
    }
}

/// Parses `name:type a;type[3] b;`.
pub(super) fn parse_format(text: &str) -> Result<(String, Vec<FieldDef>), FormatError> {
    let (name, rest) = text
        .split_once(':')
        .ok_or_else(|| FormatError::NoName(q(text)))?;
    let mut fields = Vec::new();
    for part in rest.split(';').filter(|p| !p.is_empty()) {
        let (ty, fname) = part.split_once(' ').ok_or_else(|| FormatError::Field {
            field: q(part),
            format: q(name),
        })?;
        let (ty, count) = match ty.split_once('[') {
            Some((t, n)) => {
                let n = n
                    .strip_suffix(']')
                    .and_then(|n| n.parse::<usize>().ok())
                    .ok_or_else(|| FormatError::Array {
                        ty: q(ty),
                        format: q(name),
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
