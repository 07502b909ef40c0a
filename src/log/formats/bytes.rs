//! A bounds-checked little-endian reader over a byte slice that knows where its bytes sit in
//! the file, so every short read becomes an error at an offset instead of a panic.

use super::error::Broken;

/// Reads fields in order from `data`; `base` is the file offset of `data[0]`.
#[derive(Debug, Clone)]
pub(crate) struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
    base: u64,
}

/// Runs `each` over the records of a decompressed chunk (ROS bag, MCAP) until its bytes are
/// used up; `each` reads one record from the cursor it is handed, at the offset it is given.
/// An error inside is placed at the chunk's offset in the file, with its offset among the
/// decompressed bytes in the message ([`Broken::inside_chunk`]).
pub(crate) fn each_record_of_chunk<'a>(
    inner: &'a [u8],
    chunk_at: u64,
    mut each: impl FnMut(&mut Bytes<'a>, u64) -> Result<(), Broken>,
) -> Result<(), Broken> {
    let mut b = Bytes::new(inner, 0);
    while !b.is_empty() {
        let at = b.offset();
        each(&mut b, at).map_err(|e| e.inside_chunk(chunk_at))?;
    }
    Ok(())
}

impl<'a> Bytes<'a> {
    pub(crate) fn new(data: &'a [u8], base: u64) -> Bytes<'a> {
        Bytes { data, pos: 0, base }
    }

    /// File offset of the next byte.
    pub(crate) fn offset(&self) -> u64 {
        self.base + self.pos as u64
    }

    /// Bytes not read yet.
    pub(crate) fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.remaining() == 0
    }

    /// The next `n` bytes; an error naming `what` when fewer are left.
    pub(crate) fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], Broken> {
        if n > self.remaining() {
            return Err(Broken::at(
                self.offset(),
                format!(
                    "{what} needs {n} bytes but only {} are left",
                    self.remaining()
                ),
            ));
        }
        let s = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    pub(crate) fn skip(&mut self, n: usize, what: &str) -> Result<(), Broken> {
        self.take(n, what).map(|_| ())
    }

    pub(crate) fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], Broken> {
        let s = self.take(N, what)?;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }

    pub(crate) fn u8(&mut self, what: &str) -> Result<u8, Broken> {
        Ok(self.array::<1>(what)?[0])
    }

    pub(crate) fn u16(&mut self, what: &str) -> Result<u16, Broken> {
        Ok(u16::from_le_bytes(self.array(what)?))
    }

    pub(crate) fn u32(&mut self, what: &str) -> Result<u32, Broken> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    pub(crate) fn u64(&mut self, what: &str) -> Result<u64, Broken> {
        Ok(u64::from_le_bytes(self.array(what)?))
    }

    /// A length read from the file, as usize, checked against what is left so that no
    /// allocation is ever sized by a corrupted field.
    pub(crate) fn len_u32(&mut self, what: &str) -> Result<usize, Broken> {
        let at = self.offset();
        let n = self.u32(what)? as usize;
        if n > self.remaining() {
            return Err(Broken::at(
                at,
                format!(
                    "{what} says {n} bytes but only {} are left",
                    self.remaining()
                ),
            ));
        }
        Ok(n)
    }

    /// As [`Bytes::len_u32`] for a 64-bit length.
    pub(crate) fn len_u64(&mut self, what: &str) -> Result<usize, Broken> {
        let at = self.offset();
        let n = self.u64(what)?;
        if n > self.remaining() as u64 {
            return Err(Broken::at(
                at,
                format!(
                    "{what} says {n} bytes but only {} are left",
                    self.remaining()
                ),
            ));
        }
        Ok(n as usize)
    }
}

/// Little-endian scalars at a fixed place of a slice already known to be long enough.
pub(crate) fn le_u16(b: &[u8], at: usize) -> u16 {
    u16::from_le_bytes([b[at], b[at + 1]])
}

pub(crate) fn le_u32(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

pub(crate) fn le_u64(b: &[u8], at: usize) -> u64 {
    let mut a = [0u8; 8];
    a.copy_from_slice(&b[at..at + 8]);
    u64::from_le_bytes(a)
}

pub(crate) fn le_f32(b: &[u8], at: usize) -> f32 {
    f32::from_bits(le_u32(b, at))
}

pub(crate) fn le_f64(b: &[u8], at: usize) -> f64 {
    f64::from_bits(le_u64(b, at))
}

/// Text from a fixed-size, NUL-padded field (DataFlash names and formats).
pub(crate) fn c_string(b: &[u8]) -> String {
    let end = b.iter().position(|&c| c == 0).unwrap_or(b.len());
    String::from_utf8_lossy(&b[..end]).trim_end().to_string()
}

/// The first bytes of a file in hex, for an error saying what it is not.
pub(crate) fn hex_head(b: &[u8]) -> String {
    if b.is_empty() {
        return "nothing (the file is empty)".into();
    }
    let h: Vec<String> = b.iter().take(8).map(|c| format!("{c:02x}")).collect();
    h.join(" ")
}
