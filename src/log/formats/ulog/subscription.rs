//! One subscription of a wanted topic and the raw rows of its samples, decoded into columns
//! once the file is read: the store between the message walk and the assembly of instances.

use super::format::{Base, Located};
use crate::log::formats::bytes::{le_f32, le_f64, le_u16, le_u32, le_u64};
use crate::log::formats::recording::Values;
use std::collections::HashMap;
use std::rc::Rc;

/// Where a topic's fields lie in its payload, worked out once per topic (and again only when
/// a format is redefined), shared by every subscription of it.
pub(super) struct Layout {
    pub(super) fields: HashMap<String, Located>,
    /// The bytes a sample must have, and all that is kept of it: up to the end of the last
    /// field that is not `_padding` (PX4 leaves out a format's trailing padding, and padding
    /// is never read, so none is stored: a format declaring 60 kB of padding costs nothing
    /// per sample).
    pub(super) need: usize,
}

/// One subscription of a wanted topic, and the rows read from its samples.
pub(super) struct Sub {
    pub(super) topic: &'static str,
    pub(super) multi_id: u8,
    pub(super) layout: Rc<Layout>,
    /// The first `layout.need` bytes of the payload (after the msg_id) of every sample:
    /// decoded once the file is read, which keeps the pass over the file a copy.
    pub(super) rows: Vec<u8>,
}

impl Sub {
    fn stride(&self) -> usize {
        self.layout.need
    }

    pub(super) fn count(&self) -> usize {
        self.rows.len().checked_div(self.stride()).unwrap_or(0)
    }

    fn row(&self, i: usize) -> &[u8] {
        &self.rows[i * self.stride()..(i + 1) * self.stride()]
    }

    /// The type and place in a row of element `k` of scalar field `name`, when it has one
    /// inside the bytes kept.
    fn place(&self, name: &str, k: usize) -> Option<(Base, usize)> {
        let f = *self.layout.fields.get(name)?;
        let base = f.base?;
        if k >= f.count {
            return None;
        }
        let at = k.checked_mul(base.size())?.checked_add(f.offset)?;
        (at.checked_add(base.size())? <= self.stride()).then_some((base, at))
    }

    /// The integer field at `p` of row `i` (its bits, zero-extended); `None` for a float.
    fn integer(&self, (base, at): (Base, usize), i: usize) -> Option<u64> {
        let r = self.row(i);
        Some(match base {
            Base::F32 | Base::F64 => return None,
            Base::U64 | Base::I64 => le_u64(r, at),
            Base::U32 | Base::I32 => u64::from(le_u32(r, at)),
            Base::U16 | Base::I16 => u64::from(le_u16(r, at)),
            Base::U8 | Base::I8 | Base::Bool | Base::Char => u64::from(r[at]),
        })
    }

    /// True when `name` (element `k`) is a float field.
    pub(super) fn is_float(&self, name: &str, k: usize) -> bool {
        matches!(self.place(name, k), Some((Base::F32 | Base::F64, _)))
    }

    /// The float field at `p` of the rows `rows` names, NaN where it names none; `None`
    /// when the field is not a float.
    fn floats(
        &self,
        (base, at): (Base, usize),
        rows: impl Iterator<Item = Option<usize>>,
    ) -> Option<Values> {
        Some(match base {
            Base::F32 => Values::F32(
                rows.map(|i| i.map_or(f32::NAN, |i| le_f32(self.row(i), at)))
                    .collect(),
            ),
            Base::F64 => Values::F64(
                rows.map(|i| i.map_or(f64::NAN, |i| le_f64(self.row(i), at)))
                    .collect(),
            ),
            _ => return None,
        })
    }

    /// A float field (element `k` of an array) at the rows `pick` names, NaN where it names
    /// none; `None` when the field is not a float.
    pub(super) fn values_at(&self, name: &str, k: usize, pick: &[Option<usize>]) -> Option<Values> {
        self.floats(self.place(name, k)?, pick.iter().copied())
    }

    /// A float field (element `k` of an array) of every row.
    pub(super) fn values(&self, name: &str, k: usize) -> Option<Values> {
        self.floats(self.place(name, k)?, (0..self.count()).map(Some))
    }

    /// An integer field of every row.
    pub(super) fn integers(&self, name: &str) -> Option<Vec<u64>> {
        let p = self.place(name, 0)?;
        if matches!(p.0, Base::F32 | Base::F64) {
            return None;
        }
        (0..self.count()).map(|i| self.integer(p, i)).collect()
    }

    /// An integer field of the first row (a device id), without reading the others.
    pub(super) fn first_integer(&self, name: &str) -> Option<u64> {
        let p = self.place(name, 0)?;
        if self.count() == 0 {
            return None;
        }
        self.integer(p, 0)
    }

    /// The same subscription holding only the samples `rows` names (places among its own, in
    /// range): one device's samples of a subscription whose device changes.
    pub(super) fn with_rows(&self, rows: &[usize]) -> Sub {
        let mut kept = Vec::with_capacity(rows.len() * self.stride());
        for &i in rows {
            kept.extend_from_slice(self.row(i));
        }
        Sub {
            topic: self.topic,
            multi_id: self.multi_id,
            layout: Rc::clone(&self.layout),
            rows: kept,
        }
    }

    pub(super) fn label(&self) -> String {
        format!("{} multi_id {}", self.topic, self.multi_id)
    }
}
