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

/// Decompresses `data` into exactly `size` bytes.
pub(crate) fn decompress(codec: Codec, data: &[u8], size: u64) -> Result<Vec<u8>, String> {
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
    res.map_err(|e| format!("the {name} chunk does not decompress: {e}"))?;
    if out.len() as u64 != size {
        return Err(format!(
            "the {name} chunk decompresses to {}{} bytes but declares {size}",
            out.len(),
            if out.len() as u64 > size { "+" } else { "" }
        ));
    }
    Ok(out)
}
