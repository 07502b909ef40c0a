//! One subscription of a wanted topic and the raw rows of its samples, decoded into columns
//! once the file is read: the store between the message walk and the assembly of instances.

use super::format::{Base, Located};
use crate::log::formats::bytes::{le_f32, le_f64, le_u16, le_u32, le_u64};
use crate::log::formats::recording::Values;
use std::collections::HashMap;

/// One subscription of a wanted topic, and the columns read from its samples.
pub(super) struct Sub {
    pub(super) topic: &'static str,
    pub(super) multi_id: u8,
    pub(super) size: usize,
    /// The bytes a sample must have: PX4 leaves out a format's trailing `_padding` fields.
    pub(super) need: usize,
    pub(super) fields: HashMap<String, Located>,
    /// Raw payloads (after the msg_id) of every sample, cut to `size`: decoded once the
    /// file is read, which keeps the pass over the file a copy.
    pub(super) rows: Vec<u8>,
}

impl Sub {
    pub(super) fn count(&self) -> usize {
        self.rows.len().checked_div(self.size).unwrap_or(0)
    }

    pub(super) fn row(&self, i: usize) -> &[u8] {
        &self.rows[i * self.size..(i + 1) * self.size]
    }

    /// A scalar field (element `k` of an array) of every row, as float64 or integer.
    pub(super) fn column(&self, name: &str, k: usize) -> Option<Column> {
        let f = *self.fields.get(name)?;
        let base = f.base?;
        if k >= f.count {
            return None;
        }
        let at = f.offset + k * base.size();
        let n = self.count();
        Some(match base {
            Base::F32 => Column::F32((0..n).map(|i| le_f32(self.row(i), at)).collect()),
            Base::F64 => Column::F64((0..n).map(|i| le_f64(self.row(i), at)).collect()),
            Base::U64 => Column::U64((0..n).map(|i| le_u64(self.row(i), at)).collect()),
            Base::I64 => Column::U64((0..n).map(|i| le_u64(self.row(i), at)).collect()),
            Base::U32 | Base::I32 => {
                Column::U64((0..n).map(|i| u64::from(le_u32(self.row(i), at))).collect())
            }
            Base::U16 | Base::I16 => {
                Column::U64((0..n).map(|i| u64::from(le_u16(self.row(i), at))).collect())
            }
            Base::U8 | Base::I8 | Base::Bool | Base::Char => {
                Column::U64((0..n).map(|i| u64::from(self.row(i)[at])).collect())
            }
        })
    }

    pub(super) fn values(&self, name: &str, k: usize) -> Option<Values> {
        match self.column(name, k)? {
            Column::F32(v) => Some(Values::F32(v)),
            Column::F64(v) => Some(Values::F64(v)),
            Column::U64(_) => None,
        }
    }

    pub(super) fn integers(&self, name: &str) -> Option<Vec<u64>> {
        match self.column(name, 0)? {
            Column::U64(v) => Some(v),
            _ => None,
        }
    }

    pub(super) fn label(&self) -> String {
        format!("{} multi_id {}", self.topic, self.multi_id)
    }
}

pub(super) enum Column {
    F32(Vec<f32>),
    F64(Vec<f64>),
    U64(Vec<u64>),
}
