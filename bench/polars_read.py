#!/usr/bin/env python3
"""Reads a chamber log with polars.read_csv, the reference of requirement 1 (BENCHMARKS.md).

    python3 bench/polars_read.py BIG.csv [--repeat N]

The whole process is what bench/run.sh times (interpreter start and `import polars` included);
the read itself is also timed here and printed on stderr, with the shape, so that the two can
be told apart. The file's first line is a `#` comment, as in every driftlab log.
"""
import argparse
import sys
import time

import polars as pl


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("log")
    ap.add_argument("--repeat", type=int, default=1, help="reads in one process (default 1)")
    a = ap.parse_args()
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        df = pl.read_csv(a.log, comment_prefix="#")
        dt = time.perf_counter() - t0
        print(
            f"polars {pl.__version__} read_csv: {df.height} rows x {df.width} columns "
            f"{list(df.dtypes)} in {dt:.3f} s (threads: {pl.thread_pool_size()})",
            file=sys.stderr,
        )


if __name__ == "__main__":
    main()
