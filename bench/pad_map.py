#!/usr/bin/env python3
"""A map whose LTM holds a million locations, without the two million images a run would take.

Issue 39 asks for each stage's median at 1,000,000 LTM locations. bench/scale.sh fills LTM at about
one location every two images, and its map grows ~37 KB an image: a real million would take two
days and ~75 GB. This script copies a map (e.g. the time.db of `bench/scale.sh 18300`) and adds
COPIES copies of its LTM: each copied location keeps its word positions, images, weight,
description for the search by appearance, and the links among LTM locations, under ids shifted by
k x (the map's next id); its words are copies too (the same descriptors under ids shifted by k x the
next word id), so that a word is held by as many LTM locations as in a real run. The next location
and word ids in the checkpoint move past them, so that a run resumed on the result
(bench/late_state.sh) adds its locations and words after the copies. The copies are not linked to
WM, so they come back only through the search by appearance.

What this measures: every per-image cost that depends on how many LTM locations and LTM words there
are (the search by appearance, the graph and id structures held in memory, SQLite's B-trees, the
checkpoint, the writes keyed by a word), not what depends on the variety of the places (the
copies look exactly like their originals). The file grows by about the source's size per copy.

Usage: bench/pad_map.py MAP OUT COPIES   (MAP is read only; OUT must not exist)
"""
import os
import shutil
import sqlite3
import struct
import sys
import time

# The checkpoint's counters (src/detector/checkpoint.cc, kCounters): last image (int32), images
# processed (int64), newest location (int32), next location id (int32), next word id (int32).
COUNTERS = struct.Struct("<iqiii")

# Tables with one row per location (or several, keyed by it) and the columns after the id.
PER_LOCATION = {
    "locations": ("id", "weight"),
    "location_images": ("location_id", "rank, image"),
    "signature_words": ("location_id", "rank, word_id, x, y, size, angle, response, octave"),
    "appearances": ("location_id", "entries"),
    "whole_images": ("location_id", "descriptor"),
    "location_views": ("location_id", "image"),
}


def fail(message):
    sys.exit(f"pad_map.py: {message}")


def main():
    if len(sys.argv) != 4:
        fail("usage: bench/pad_map.py MAP OUT COPIES")
    source, target, copies = sys.argv[1], sys.argv[2], int(sys.argv[3])
    if not os.path.isfile(source):
        fail(f"{source}: no such map")
    if os.path.exists(source + "-wal") and os.path.getsize(source + "-wal") > 0:
        fail(f"{source}: its log {source}-wal is not empty (is a run still writing it?)")
    if os.path.exists(target):
        fail(f"{target}: already exists")
    if copies < 1:
        fail("COPIES must be at least 1")
    shutil.copyfile(source, target)
    db = sqlite3.connect(target, isolation_level=None)
    # A scratch copy: no journal (a failed run leaves OUT to delete), a 4 GB page cache, the
    # index of words made once at the end instead of by random inserts, and the originals' rows
    # selected by a range of ids (below). Without the last two a copy took 30-47 s, and more as
    # the file grew; with them, 4-9 s.
    db.execute("PRAGMA journal_mode=OFF")
    db.execute("PRAGMA synchronous=OFF")
    db.execute("PRAGMA cache_size=-4000000")
    word_index = db.execute("SELECT sql FROM sqlite_master "
                            "WHERE type='index' AND name='signature_words_word'").fetchone()
    if word_index is not None:
        db.execute("DROP INDEX signature_words_word")
    tables = {row[0] for row in db.execute("SELECT name FROM sqlite_master WHERE type='table'")}
    row = db.execute("SELECT value FROM resume_state WHERE key='counters'").fetchone()
    if row is None or len(row[0]) != COUNTERS.size:
        fail(f"{source}: no checkpoint counters of the expected size (format changed?)")
    last_image, processed, newest, next_id, next_word = COUNTERS.unpack(row[0])
    # LTM: the stored locations but those in WM or STM at the checkpoint (a retrieved location
    # keeps its rows; its words are the dictionary's, held by WM, not LTM).
    db.execute("CREATE TEMP TABLE ltm(id INTEGER PRIMARY KEY)")
    db.execute("INSERT INTO ltm SELECT id FROM locations "
               "WHERE id NOT IN (SELECT id FROM memory_locations)")
    ltm = db.execute("SELECT count(*) FROM ltm").fetchone()[0]
    # Each copy has words of its own (ids shifted by k x the next word id, the same descriptors):
    # a word is then held by as many locations as in a real run. Copies sharing the originals'
    # words made every word held by COPIES + 1 times more locations, and every write keyed by a
    # word (a retrieved word replaced, UPDATE ... WHERE word_id) as many times more work.
    db.execute("CREATE TEMP TABLE ltm_words(id INTEGER PRIMARY KEY)")
    db.execute("INSERT INTO ltm_words SELECT DISTINCT word_id FROM signature_words "
               "WHERE location_id IN (SELECT id FROM temp.ltm)")
    if (copies + 1) * next_word >= 2**31:
        fail(f"{copies} copies of {next_word} word ids pass the ids' 32 bits")
    print(f"{source}: {ltm} LTM locations, next id {next_id}; adding {copies} copies", flush=True)
    for k in range(1, copies + 1):
        start = time.time()
        shift, word_shift = k * next_id, k * next_word
        db.execute("BEGIN")
        for table, (key, columns) in PER_LOCATION.items():
            if table not in tables:
                continue
            # `key < next_id`: the originals' rows by a range of the key.
            selected = columns.replace("word_id", f"word_id + {word_shift}")
            db.execute(f"INSERT INTO {table} SELECT {key} + ?, {selected} FROM {table} "
                       f"WHERE {key} < ? AND {key} IN (SELECT id FROM temp.ltm) ORDER BY {key}",
                       (shift, next_id))
        db.execute("INSERT INTO words SELECT id + ?, descriptor FROM words "
                   "WHERE id < ? AND id IN (SELECT id FROM temp.ltm_words) ORDER BY id",
                   (word_shift, next_word))
        # Links among the original LTM locations (not those to WM, which the copies do not join).
        db.execute("INSERT INTO links SELECT from_id + ?, to_id + ?, type FROM links "
                   "WHERE from_id < ? AND from_id IN (SELECT id FROM temp.ltm) "
                   "AND to_id IN (SELECT id FROM temp.ltm)", (shift, shift, next_id))
        db.execute("COMMIT")
        print(f"copy {k}: {time.time() - start:.0f} s, "
              f"{os.path.getsize(target) / 1e9:.1f} GB", flush=True)
    if word_index is not None:
        start = time.time()
        db.execute(word_index[0])
        print(f"index of words: {time.time() - start:.0f} s", flush=True)
    counters = COUNTERS.pack(last_image, processed, newest, (copies + 1) * next_id,
                             (copies + 1) * next_word)
    db.execute("UPDATE resume_state SET value=? WHERE key='counters'", (counters,))
    total = db.execute("SELECT count(*) FROM locations "
                       "WHERE id NOT IN (SELECT id FROM memory_locations)").fetchone()[0]
    db.close()
    print(f"{target}: {total} LTM locations, next id {(copies + 1) * next_id}")


if __name__ == "__main__":
    main()
