//! Writing a big temporary file past the page cache (`O_DIRECT`): text is gathered into
//! aligned buffers that a writer thread hands to the disk whole, while the caller goes on
//! producing the next one.
//!
//! Direct writes must start at an aligned file offset, from an aligned address, with an
//! aligned length. Every buffer but the last is full ([`BUFFER`] bytes, a multiple of
//! [`ALIGN`]); the last is padded with zeros to [`ALIGN`] and the file is then cut back to the
//! bytes written. Should the file system refuse a direct write after all (`EINVAL`), the
//! writer thread turns direct I/O off for the file and writes through the page cache.

use rustix::fs::{OFlags, fcntl_getfl, fcntl_setfl};
use std::fs::File;
use std::io::{self, Write};
use std::sync::mpsc::{Receiver, SyncSender, channel, sync_channel};

/// The alignment direct writes need: 4096 covers the logical block size of every disk that
/// driftlab is likely to meet (512 or 4096 bytes).
const ALIGN: usize = 4096;

/// Bytes a buffer holds: large enough that the disk sees long writes, small enough that the
/// three buffers in flight stay a few tens of MB.
const BUFFER: usize = 8 << 20;

/// Turns direct I/O on for `file`; false where the file system or system does not offer it.
pub(super) fn enable(file: &File) -> bool {
    match fcntl_getfl(file) {
        Ok(flags) => fcntl_setfl(file, flags | OFlags::DIRECT).is_ok(),
        Err(_) => false,
    }
}

/// Fills `file` (direct I/O already on) through `fill`, then cuts it to the bytes written.
pub(super) fn fill<F>(file: &File, fill: F) -> io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let written = std::thread::scope(|scope| {
        let (full_tx, full_rx) = sync_channel::<(Aligned, usize)>(1);
        let (free_tx, free_rx) = channel::<Aligned>();
        let disk = scope.spawn(move || write_buffers(file, full_rx, free_tx));
        let mut w = Gather {
            buf: Aligned::new(),
            len: 0,
            written: 0,
            full_tx,
            free_rx,
        };
        let filled = fill(&mut w).and_then(|()| w.finish());
        // Closing the channel lets the writer thread finish what it holds and stop.
        drop(w);
        let on_disk = disk
            .join()
            .unwrap_or_else(|_| Err(io::Error::other("the disk writer thread failed")));
        // The writer's own error says more than the "stopped" that the producer then met.
        on_disk.and(filled)
    })?;
    file.set_len(written)
}

/// The writer thread: writes each full buffer and hands it back for reuse.
fn write_buffers(
    file: &File,
    full: Receiver<(Aligned, usize)>,
    free: std::sync::mpsc::Sender<Aligned>,
) -> io::Result<()> {
    let mut direct = true;
    for (buf, len) in full {
        write_all(file, &buf.bytes()[..len], &mut direct)?;
        // The producer may have finished: a buffer it no longer wants is freed.
        let _ = free.send(buf);
    }
    Ok(())
}

/// Writes all of `bytes`; on a refused direct write, turns direct I/O off and goes on
/// through the page cache.
fn write_all(mut file: &File, mut bytes: &[u8], direct: &mut bool) -> io::Result<()> {
    while !bytes.is_empty() {
        match file.write(bytes) {
            Ok(0) => return Err(io::ErrorKind::WriteZero.into()),
            Ok(n) => bytes = &bytes[n..],
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e)
                if *direct && e.raw_os_error() == Some(rustix::io::Errno::INVAL.raw_os_error()) =>
            {
                let flags = fcntl_getfl(file)?;
                fcntl_setfl(file, flags - OFlags::DIRECT)?;
                *direct = false;
            }
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

/// A buffer of [`BUFFER`] bytes starting at an [`ALIGN`]ed address.
struct Aligned {
    raw: Vec<u8>,
    start: usize,
}

impl Aligned {
    fn new() -> Aligned {
        let raw = vec![0u8; BUFFER + ALIGN];
        // Where no aligned start can be found, the first direct write is refused and the
        // file goes through the page cache.
        let start = match raw.as_ptr().align_offset(ALIGN) {
            s if s < ALIGN => s,
            _ => 0,
        };
        Aligned { raw, start }
    }

    fn bytes(&self) -> &[u8] {
        &self.raw[self.start..self.start + BUFFER]
    }

    fn bytes_mut(&mut self) -> &mut [u8] {
        &mut self.raw[self.start..self.start + BUFFER]
    }
}

/// The producer's side: copies what it is given into the current buffer and sends each full
/// one to the writer thread.
struct Gather {
    buf: Aligned,
    len: usize,
    written: u64,
    full_tx: SyncSender<(Aligned, usize)>,
    free_rx: Receiver<Aligned>,
}

impl Gather {
    /// Sends the current buffer's first `len` bytes (a multiple of [`ALIGN`]).
    fn send(&mut self, len: usize) -> io::Result<()> {
        let next = self.free_rx.try_recv().unwrap_or_else(|_| Aligned::new());
        let full = std::mem::replace(&mut self.buf, next);
        self.len = 0;
        self.full_tx
            .send((full, len))
            .map_err(|_| io::Error::other("the disk writer stopped"))
    }

    /// Sends what is left, padded with zeros to [`ALIGN`]; returns the bytes written.
    fn finish(&mut self) -> io::Result<u64> {
        if self.len > 0 {
            let padded = self.len.next_multiple_of(ALIGN);
            let len = self.len;
            self.buf.bytes_mut()[len..padded].fill(0);
            self.send(padded)?;
        }
        Ok(self.written)
    }
}

impl Write for Gather {
    fn write(&mut self, data: &[u8]) -> io::Result<usize> {
        let n = data.len().min(BUFFER - self.len);
        let len = self.len;
        self.buf.bytes_mut()[len..len + n].copy_from_slice(&data[..n]);
        self.len += n;
        self.written += n as u64;
        if self.len == BUFFER {
            self.send(BUFFER)?;
        }
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}
