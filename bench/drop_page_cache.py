#!/usr/bin/env python3
"""Drops a map file's pages (and its WAL's) from the OS page cache every PERIOD seconds, until
killed, as this machine's host does now and then (docs/scale.md): LTM rows are then read from the
device. Uses posix_fadvise(DONTNEED), which needs no privilege.

Usage: bench/drop_page_cache.py MAP.db PERIOD_SECONDS &   (start it once the run has made the map)
"""
import os
import sys
import time


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    path, period = sys.argv[1], float(sys.argv[2])
    while True:
        time.sleep(period)
        for name in (path, path + "-wal"):
            try:
                fd = os.open(name, os.O_RDONLY)
            except FileNotFoundError:
                continue
            os.posix_fadvise(fd, 0, 0, os.POSIX_FADV_DONTNEED)
            os.close(fd)
        print(time.strftime("%H:%M:%S"), "dropped", path, flush=True)


if __name__ == "__main__":
    main()
