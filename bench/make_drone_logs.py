#!/usr/bin/env python3
"""Builds 100 MB PX4 ULog and ArduPilot DataFlash logs from the real samples, for the
reader benchmark in BENCHMARKS.md ("Drone and robot logs").

    python3 bench/make_drone_logs.py SAMPLES_DIR OUT_DIR [MEGABYTES]

It also writes big-imu.bin, a DataFlash log whose repeated part is the sample's IMU messages
alone (the heaviest case for a reader: every message is one it decodes).

SAMPLES_DIR is ../shared/data/formats; the logs are written to OUT_DIR (not committed).

ULog: the 16-byte header, then every message of the sample that is not a data ('D') or
remove ('R') message, in file order (flag bits, formats, info, parameters, all the
subscriptions, log strings, dropouts), then the sample's data messages repeated until the
size is reached, each repetition's `timestamp` (the first field of every PX4 topic) shifted
by the sample's time span plus 1 s, so time keeps increasing topic by topic. Every
subscription comes before any data message, and no message is cut.

DataFlash: the sample's schema messages (FMT, FMTU, UNIT, MULT) in file order, then its
other whole messages (PARM, IMU, ...) repeated, each repetition's `TimeUS` shifted the
same way (messages whose first field is the `Q` TimeUS); the 2-byte cut message at the
end of the sample is left out.
"""
import struct
import sys
from pathlib import Path


def ulog(src: bytes, target: int) -> bytes:
    head, pos = src[:16], 16
    keep, data = [], []
    while pos + 3 <= len(src):
        size, typ = struct.unpack_from('<HB', src, pos)
        if pos + 3 + size > len(src):
            break
        msg = src[pos:pos + 3 + size]
        if typ == ord('B'):
            incompat = msg[3 + 8:3 + 16]
            assert not any(incompat), 'appended data is not supported by this script'
        if typ == ord('D'):
            data.append(msg)
        elif typ != ord('R'):
            keep.append(msg)
        pos += 3 + size
    stamps = [struct.unpack_from('<Q', m, 5)[0] for m in data if len(m) >= 13]
    span = max(stamps) - min(stamps) + 1_000_000
    out = bytearray(head + b''.join(keep))
    k = 0
    while len(out) < target:
        for m in data:
            m = bytearray(m)
            if len(m) >= 13:
                t = struct.unpack_from('<Q', m, 5)[0]
                struct.pack_into('<Q', m, 5, t + k * span)
            out += m
        k += 1
    return bytes(out)


def dataflash(src: bytes, target: int, only=None) -> bytes:
    fmts, pos = {}, 0
    schema, body = [], []
    while pos + 3 <= len(src):
        assert src[pos:pos + 2] == b'\xa3\x95', f'no message header at byte {pos}'
        typ = src[pos + 2]
        length = 89 if typ == 0x80 else fmts[typ][0]
        if pos + length > len(src):
            break
        msg = src[pos:pos + length]
        if typ == 0x80:
            t, ln = msg[3], msg[4]
            name = msg[5:9].rstrip(b'\0').decode()
            fmt = msg[9:25].rstrip(b'\0').decode()
            cols = msg[25:89].rstrip(b'\0').decode()
            fmts[t] = (ln, name, fmt, cols)
        name = 'FMT' if typ == 0x80 else fmts[typ][1]
        if name in ('FMT', 'FMTU', 'UNIT', 'MULT'):
            schema.append(msg)
        elif only is None or name == only:
            body.append(msg)
        pos += length

    def timed(m):
        f = fmts[m[2]]
        return f[2].startswith('Q') and f[3].startswith('TimeUS')

    stamps = [struct.unpack_from('<Q', m, 3)[0] for m in body if timed(m)]
    span = max(stamps) - min(stamps) + 1_000_000
    out = bytearray(b''.join(schema))
    k = 0
    while len(out) < target:
        for m in body:
            if timed(m):
                m = bytearray(m)
                t = struct.unpack_from('<Q', m, 3)[0]
                struct.pack_into('<Q', m, 3, t + k * span)
            out += m
        k += 1
    return bytes(out)


def main():
    samples, out = Path(sys.argv[1]), Path(sys.argv[2])
    target = int(float(sys.argv[3]) * 1e6) if len(sys.argv) > 3 else 100_000_000
    out.mkdir(parents=True, exist_ok=True)
    u = ulog((samples / 'px4_ulog/sample_log_small.ulg').read_bytes(), target)
    (out / 'big.ulg').write_bytes(u)
    d = dataflash((samples / 'ardupilot_dataflash/backend_log_80k.bin').read_bytes(), target)
    (out / 'big.bin').write_bytes(d)
    i = dataflash((samples / 'ardupilot_dataflash/backend_log_80k.bin').read_bytes(), target,
                  only='IMU')
    (out / 'big-imu.bin').write_bytes(i)
    for name, b in (('big.ulg', u), ('big.bin', d), ('big-imu.bin', i)):
        print(f'{out / name}: {len(b)} bytes')


if __name__ == '__main__':
    main()
