//! The chunk codecs of ROS bags (bz2, lz4) and MCAP (zstd, lz4), streamed and bounded: a
//! chunk is decompressed as its bytes come out of the codec, never past the size it declares
//! (plus one byte, to see that there is more), never past [`CHUNK_AT_MOST`], and the chunks of
//! one file never past [`Budget`] in all. A decompression bomb (92 KB of zstd or 3 KB of bz2
//! that expand to 4 GB) is refused by its declared size before a byte is decompressed, or
//! stops at the cap; nothing is allocated for a declared size before its bytes exist.

use std::io::Read;

/// A chunk's compression.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Codec {
    None,
    Bz2,
    Lz4,
    Zstd,
}

impl Codec {
    fn name(self) -> &'static str {
        match self {
            Codec::Bz2 => "bz2",
            Codec::Lz4 => "lz4",
            Codec::Zstd => "zstd",
            Codec::None => "uncompressed",
        }
    }
}

/// The most one chunk may decompress to: the one chunk held at a time while its records are
/// read, the fixed allowance above what the reader keeps. Recorders write chunks of about
/// 768 KiB (rosbag, ros2 bag, the mcap tools); a chunk holding one huge message (an image, a
/// point cloud) is larger, but not by this much.
pub(crate) const CHUNK_AT_MOST: u64 = 256 << 20;

/// What the chunks of one file may decompress to in all: [`BUDGET_FLOOR`] or
/// [`BUDGET_RATIO`] times the file's size, whichever is more. Real logs compress their
/// messages 2 to 20 times; a file of many small bombs (each under [`CHUNK_AT_MOST`]) would
/// otherwise keep a reader busy for hours on a file of a few kilobytes.
pub(crate) struct Budget {
    left: u64,
    total: u64,
}

/// See [`Budget`].
pub(crate) const BUDGET_FLOOR: u64 = 1 << 30;
/// See [`Budget`].
pub(crate) const BUDGET_RATIO: u64 = 1024;

impl Budget {
    /// The budget of a file of `file_len` bytes.
    pub(crate) fn for_file(file_len: usize) -> Budget {
        let total = BUDGET_FLOOR.max((file_len as u64).saturating_mul(BUDGET_RATIO));
        Budget { left: total, total }
    }
}

/// A chunk that cannot be decompressed, or not within bounds (the caller places it at the
/// chunk's offset in the file).
#[derive(Debug, thiserror::Error)]
pub(crate) enum DecompressError {
    /// The codec refused the bytes.
    #[error("the {codec} chunk does not decompress: {source}")]
    Corrupt {
        /// The codec's name.
        codec: &'static str,
        /// What the codec said.
        source: std::io::Error,
    },
    /// The bytes decompress to another size than the chunk declares.
    #[error(
        "the {codec} chunk decompresses to {got}{} bytes but declares {declared}",
        more_than(.got, .declared)
    )]
    WrongSize {
        /// The codec's name.
        codec: &'static str,
        /// Bytes it gave (read up to one past the declared size).
        got: usize,
        /// Bytes the chunk declares.
        declared: u64,
    },
    /// The chunk declares more than one chunk may hold.
    #[error(
        "the {codec} chunk declares {declared} bytes once decompressed ({compressed} bytes \
         compressed), more than the {} MiB driftlab holds for one chunk: a corrupt size or a \
         decompression bomb",
        CHUNK_AT_MOST >> 20
    )]
    TooLarge {
        /// The codec's name.
        codec: &'static str,
        /// Bytes the chunk declares.
        declared: u64,
        /// Its compressed bytes.
        compressed: usize,
    },
    /// The chunks so far and this one declare more than the file's budget.
    #[error(
        "the chunks up to this one declare more than {total} bytes once decompressed in all, \
         over {BUDGET_RATIO} times the file's size: a decompression bomb"
    )]
    OverBudget {
        /// The file's budget, bytes.
        total: u64,
    },
}

/// `+` after a size read up to one past the declared one: there was more.
fn more_than(got: &usize, declared: &u64) -> &'static str {
    if *got as u64 > *declared { "+" } else { "" }
}

/// Decompresses `data` into exactly `size` bytes, within [`CHUNK_AT_MOST`] and what is left
/// of `budget`.
pub(crate) fn decompress(
    codec: Codec,
    data: &[u8],
    size: u64,
    budget: &mut Budget,
) -> Result<Vec<u8>, DecompressError> {
    let name = codec.name();
    if size > CHUNK_AT_MOST {
        return Err(DecompressError::TooLarge {
            codec: name,
            declared: size,
            compressed: data.len(),
        });
    }
    if size > budget.left {
        return Err(DecompressError::OverBudget {
            total: budget.total,
        });
    }
    budget.left -= size;
    // Room for what the compressed bytes can plausibly give; the vector grows past it only
    // as decompressed bytes arrive.
    let start = usize::try_from(size.min(data.len().saturating_mul(4) as u64)).unwrap_or(0);
    let mut out = Vec::with_capacity(start);
    let limit = size + 1;
    let res = match codec {
        Codec::Bz2 => bzip2::read::BzDecoder::new(data)
            .take(limit)
            .read_to_end(&mut out),
        Codec::Lz4 => lz4_flex::frame::FrameDecoder::new(data)
            .take(limit)
            .read_to_end(&mut out),
        Codec::Zstd => match zstd::stream::read::Decoder::with_buffer(data) {
            Ok(d) => d.take(limit).read_to_end(&mut out),
            Err(e) => Err(e),
        },
        Codec::None => data.take(limit).read_to_end(&mut out),
    };
    res.map_err(|source| DecompressError::Corrupt {
        codec: name,
        source,
    })?;
    if out.len() as u64 != size {
        return Err(DecompressError::WrongSize {
            codec: name,
            got: out.len(),
            declared: size,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chunk_is_refused_by_its_declared_size_before_it_is_decompressed() {
        let mut budget = Budget::for_file(100);
        // Not even valid zstd: the size alone refuses it.
        let e = decompress(Codec::Zstd, b"junk", 3 << 30, &mut budget).unwrap_err();
        assert!(e.to_string().contains("256 MiB"), "{e}");
        let data = vec![7u8; 1000];
        assert_eq!(
            decompress(Codec::None, &data, 1000, &mut budget).unwrap(),
            data
        );
    }

    #[test]
    fn a_chunk_giving_more_than_it_declares_stops_one_byte_past_it() {
        let big = zstd::bulk::compress(&vec![0u8; 1 << 20], 3).unwrap();
        let mut budget = Budget::for_file(big.len());
        let e = decompress(Codec::Zstd, &big, 1000, &mut budget).unwrap_err();
        assert_eq!(
            e.to_string(),
            "the zstd chunk decompresses to 1001+ bytes but declares 1000"
        );
    }

    #[test]
    fn the_chunks_of_a_file_share_one_budget() {
        let mut budget = Budget {
            left: 2000,
            total: 2000,
        };
        let data = vec![1u8; 1500];
        assert!(decompress(Codec::None, &data, 1500, &mut budget).is_ok());
        let e = decompress(Codec::None, &data, 1500, &mut budget).unwrap_err();
        assert!(
            matches!(e, DecompressError::OverBudget { total: 2000 }),
            "{e}"
        );
    }
}
