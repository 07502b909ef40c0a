#!/usr/bin/env python3
"""Seeds the corpora of the binary-log fuzz targets (ulog, dataflash, rosbag, mcap) from the
sample logs in ../../shared/data/formats (read by path, never copied into the repository):
each sample whole, its compressed chunks decompressed in place (so that the mutations reach
the records inside), and short slices of its first messages or records (small inputs run
faster). Run from fuzz/ (seed.sh does)."""

import bz2
import os
import struct
import subprocess
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "shared", "data", "formats")
SAMPLES = {
    "ulog": "px4_ulog/sample_log_small.ulg",
    "dataflash": "ardupilot_dataflash/backend_log_80k.bin",
    "rosbag": "ros1_bag/sparkfun_razor.bag",
    "mcap": "ros2_mcap/sparkfun_razor_ros2.mcap",
}


def put(target, name, data):
    d = os.path.join(HERE, "corpus", target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def ulog_messages(b):
    pos, out = 16, []
    while pos + 3 <= len(b):
        (size,) = struct.unpack_from("<H", b, pos)
        if pos + 3 + size > len(b):
            break
        out.append(b[pos:pos + 3 + size])
        pos += 3 + size
    return out


def ulog_seeds(b):
    msgs = ulog_messages(b)
    head = b[:16]
    # Definitions (formats, subscriptions) and the first data, then one of each kind.
    defs = [m for m in msgs if m[2:3] in (b"F", b"A", b"B")]
    data = [m for m in msgs if m[2:3] == b"D"]
    yield "defs_first_data", head + b"".join(defs + data[:200])
    yield "defs_few_data", head + b"".join(defs + data[:20])
    wanted = [m for m in defs if m[2:3] != b"A" or any(
        t in m for t in (b"sensor_gyro", b"sensor_accel", b"sensor_combined", b"vehicle_imu_status"))]
    yield "wanted_only", head + b"".join(wanted + data[:50])


def bag_records(b, pos, end):
    out = []
    while pos + 4 <= end:
        (hlen,) = struct.unpack_from("<I", b, pos)
        if pos + 8 + hlen > end:
            break
        (dlen,) = struct.unpack_from("<I", b, pos + 4 + hlen)
        rend = pos + 8 + hlen + dlen
        if rend > end:
            break
        out.append((b[pos + 4:pos + 4 + hlen], b[pos + 8 + hlen:rend]))
        pos = rend
    return out


def bag_fields(h):
    pos, out = 0, []
    while pos + 4 <= len(h):
        (n,) = struct.unpack_from("<I", h, pos)
        name, _, value = h[pos + 4:pos + 4 + n].partition(b"=")
        out.append((name, value))
        pos += 4 + n
    return out


def bag_record(fields, data):
    h = b"".join(struct.pack("<I", len(k) + 1 + len(v)) + k + b"=" + v for k, v in fields)
    return struct.pack("<I", len(h)) + h + struct.pack("<I", len(data)) + data


def bag_seeds(b):
    magic = b[:13]
    records = bag_records(b, 13, len(b))
    plain = []
    for h, d in records:
        f = bag_fields(h)
        fd = dict(f)
        if fd.get(b"op") == b"\x05" and fd.get(b"compression") == b"bz2":
            inner = bz2.decompress(d)
            f = [(k, b"none" if k == b"compression" else (struct.pack("<I", len(inner)) if k == b"size" else v))
                 for k, v in f]
            plain.append(bag_record(f, inner))
        else:
            plain.append(bag_record(f, d))
    yield "uncompressed", magic + b"".join(plain)
    # The first uncompressed chunk alone, cut to its first records.
    for h, d in records:
        f = bag_fields(h)
        if dict(f).get(b"op") == b"\x05":
            inner = bz2.decompress(d)
            recs = bag_records(inner, 0, len(inner))
            small = b"".join(bag_record(bag_fields(rh), rd) for rh, rd in recs[:40])
            f = [(k, b"none" if k == b"compression" else (struct.pack("<I", len(small)) if k == b"size" else v))
                 for k, v in f]
            yield "one_small_chunk", magic + bag_record(f, small)
            # And its records outside any chunk.
            yield "no_chunk", magic + small
            break


def mcap_records(b, pos, end):
    out = []
    while pos + 9 <= end:
        op = b[pos]
        (n,) = struct.unpack_from("<Q", b, pos + 1)
        if pos + 9 + n > end:
            break
        out.append((op, b[pos + 9:pos + 9 + n]))
        pos += 9 + n
    return out


def mcap_record(op, content):
    return bytes([op]) + struct.pack("<Q", len(content)) + content


def mcap_chunk_inner(c):
    (size, crc, clen) = struct.unpack_from("<QIi", c, 16)
    comp = c[32:32 + clen]
    (rlen,) = struct.unpack_from("<Q", c, 32 + clen)
    data = c[40 + clen:40 + clen + rlen]
    if comp == b"zstd":
        data = subprocess.run(["zstd", "-d", "-c"], input=data, check=True, capture_output=True).stdout
    return c[:16], data


def mcap_chunk(times, inner):
    c = times + struct.pack("<QI", len(inner), zlib.crc32(inner)) + struct.pack("<I", 0)
    return mcap_record(0x06, c + struct.pack("<Q", len(inner)) + inner)


def mcap_seeds(b):
    magic = b[:8]
    records = mcap_records(b, 8, len(b))
    plain = []
    first_inner = None
    for op, c in records:
        if op == 0x06:
            times, inner = mcap_chunk_inner(c)
            first_inner = first_inner or inner
            plain.append(mcap_chunk(times, inner))
        else:
            plain.append(mcap_record(op, c))
    yield "uncompressed", magic + b"".join(plain)
    if first_inner:
        recs = mcap_records(first_inner, 0, len(first_inner))[:40]
        small = b"".join(mcap_record(op, c) for op, c in recs)
        end = mcap_record(0x0F, b"\0\0\0\0")
        yield "one_small_chunk", magic + mcap_chunk(b"\0" * 16, small) + end
        yield "no_chunk", magic + small + end


SEEDS = {"ulog": ulog_seeds, "dataflash": None, "rosbag": bag_seeds, "mcap": mcap_seeds}


def main():
    if not os.path.isdir(DATA):
        sys.exit(f"no sample logs at {DATA}")
    for target, rel in SAMPLES.items():
        with open(os.path.join(DATA, rel), "rb") as f:
            b = f.read()
        put(target, "whole", b)
        n = 1
        if target == "dataflash":
            for k in (2048, 8192, 32768):
                put(target, f"first_{k}", b[:k])
                n += 1
        else:
            for name, data in SEEDS[target](b):
                put(target, name, data)
                n += 1
        print(f"{target}: {n} seeds")


main()
