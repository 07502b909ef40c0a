//! The chunk codecs of ROS bags (bz2, lz4) and MCAP (zstd, lz4), each bounded by the size the
//! chunk declares: a corrupt size can neither allocate without limit nor pass unnoticed.

use std::io::Read;

/// A chunk's compression.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Codec {
    None,
    Bz2,
    Lz4,
    Zstd,
}

/// The most a chunk is trusted to declare before a byte of it is decompressed; past it the
/// output grows as it is produced.
const PREALLOCATE_AT_MOST: usize = 64 << 20;

/// A chunk that does not decompress to the size it declares (the caller places it at the
/// chunk's offset).
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
}

/// `+` after a size read up to one past the declared one: there was more.
fn more_than(got: &usize, declared: &u64) -> &'static str {
    if *got as u64 > *declared { "+" } else { "" }
}

/// Decompresses `data` into exactly `size` bytes.
pub(crate) fn decompress(codec: Codec, data: &[u8], size: u64) -> Result<Vec<u8>, DecompressError> {
    let cap = usize::try_from(size)
        .unwrap_or(usize::MAX)
        .min(PREALLOCATE_AT_MOST);
    let mut out = Vec::with_capacity(cap);
    let limit = size.saturating_add(1);
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
    let name = match codec {
        Codec::Bz2 => "bz2",
        Codec::Lz4 => "lz4",
        Codec::Zstd => "zstd",
        Codec::None => "uncompressed",
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
