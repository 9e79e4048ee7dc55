#!/usr/bin/env python3
"""Summary of one bench/scale.sh run: per block of 1000 images, then the totals (issue 9)."""
import csv
import os
import re
import statistics
import sys

name, folder, time_limit = sys.argv[1], sys.argv[2], float(sys.argv[3])
rows = list(csv.DictReader(open(os.path.join(folder, name + ".csv"))))
times = [float(r["iteration_ms"]) for r in rows]
rss = {}  # rows written -> RSS in MB
steal = []  # (rows written, the machine's steal time so far in ms), when sampled
tick_ms = 1000 / os.sysconf("SC_CLK_TCK")
for line in open(os.path.join(folder, name + ".rss")):
    fields = line.split()
    if len(fields) < 2:
        continue
    rss[int(fields[0])] = int(fields[1]) / 1024
    if len(fields) > 2:
        steal.append((int(fields[0]), int(fields[2]) * tick_ms))


def steal_around(row):
    """Steal time (ms) of the sampling second in which row `row` (0-based) was written."""
    for (written0, steal0), (written1, steal1) in zip(steal, steal[1:]):
        if written0 <= row < written1:
            return steal1 - steal0
    return float("nan")

print(f"\n### {name}\n")
print("| images | median ms | max ms | WM | dictionary | RSS MB |")
print("| --- | ---: | ---: | ---: | ---: | ---: |")
for start in range(0, len(rows), 1000):
    block = rows[start:start + 1000]
    block_times = times[start:start + 1000]
    block_rss = [mb for written, mb in rss.items() if start < written <= start + 1000]
    print(f"| {start + 1}-{start + len(block)} | {statistics.median(block_times):.1f} | "
          f"{max(block_times):.1f} | {block[-1]['wm_size']} | {block[-1]['dictionary_size']} | "
          f"{max(block_rss) if block_rss else float('nan'):.0f} |")

# Loop closures from the demo's lines: "image I -> location L: loop closure with location M
# (image J), p=...  [true]"; through retrieval when M was brought back from LTM before.
first_retrieved = {}  # location -> the image at which it was first retrieved
for r in rows:
    for x in r["retrieved"].split(";"):
        if x:
            first_retrieved.setdefault(int(x), int(r["image"]))
found = false_positives = through_retrieval = 0
text = open(os.path.join(folder, name + ".txt")).read()
for image, location, verdict in re.findall(
        r"image (\d+) -> location \d+: loop closure with location (\d+) .*\[(true|FALSE)\]", text):
    if verdict == "FALSE":
        false_positives += 1
        continue
    found += 1
    through_retrieval += first_retrieved.get(int(location), int(image)) < int(image)
revisit = re.search(r"(\d+) revisits \((\d+) images\)", text)
revisit_images = int(revisit.group(2)) if revisit else 0
# Only the revisit images within the rows written count (the baseline is stopped early).
peak = open(os.path.join(folder, name + ".peak")).read().split()
peak_mb = int(peak[-1]) / 1024 if peak and peak[-1].isdigit() else max(rss.values(), default=0)
db = sum(os.path.getsize(os.path.join(folder, f)) for f in os.listdir(folder)
         if f.startswith(name + ".db"))
first = statistics.median(times[1000:2000]) if len(times) >= 2000 else float("nan")
last = statistics.median(times[-1000:])
# RSS while images were processed: samples taken once every row was written are the close
# (Detector::Close stores WM and its words in LTM), reported apart. Growth over the last 10,000
# images (the last half when the run is shorter than 20,000): the highest RSS of its last 1,000
# images against that of its first 1,000 (under T_time, RSS follows WM up and down).
running = {written: mb for written, mb in rss.items() if written < len(rows)}
tail = 10000 if len(rows) >= 20000 else len(rows) // 2
def block_peak(start, end):
    return max((mb for written, mb in running.items() if start <= written < end), default=float("nan"))
rss_start = block_peak(len(rows) - tail, len(rows) - tail + 1000)
rss_end = block_peak(len(rows) - 1000, len(rows))
rss_growth = (rss_end / rss_start - 1) * 100
# The same over halves of that tail: a block of 1,000 images holds ~10 one-second samples, and RSS
# swings with the forest's rebuilds (two forests during a catch-up), so one block's peak may miss
# them.
half = tail // 2
rss_half_start = block_peak(len(rows) - tail, len(rows) - half)
rss_half_end = block_peak(len(rows) - half, len(rows))
rss_half_growth = (rss_half_end / rss_half_start - 1) * 100
running_peak = max(running.values(), default=float("nan"))
print(f"\nimages: {len(rows)}; median iteration: images 1000-2000 {first:.1f} ms, last 1000 "
      f"{last:.1f} ms (ratio {last / first:.2f}); max {max(times):.1f} ms")
if time_limit > 0 and name == "time":
    over = sum(t > time_limit for t in times)
    print(f"T_time {time_limit:g} ms: {over} iterations over ({100 * over / len(times):.2f}%), "
          f"max / T_time {max(times) / time_limit:.2f}")
    # What the slowest ones were: the thread running (cpu_ms near the time) or not (waiting, or
    # descheduled: the host's steal time in that second tells the host).
    slowest = sorted(range(len(rows)), key=lambda i: -times[i])[:max(over, 5)]
    print("\n| image | ms | cpu ms | LTM wait ms | map file read ms | slowest step "
          "| host steal in its second (ms) |")
    print("| ---: | ---: | ---: | ---: | ---: | --- | ---: |")
    steps = ["signature", "rehearsal", "likelihood", "filter", "selection", "retrieval",
             "transfer", "checkpoint"]
    for i in sorted(slowest):
        row = rows[i]
        step = max(steps, key=lambda s: float(row[s + "_ms"]))
        cpu = row.get("cpu_ms") or "nan"
        read = row.get("ltm_read_ms") or "nan"
        print(f"| {i} | {times[i]:.1f} | {float(cpu):.1f} | {float(row.get('ltm_wait_ms') or 'nan'):.1f} "
              f"| {float(read):.1f} | {step} {float(row[step + '_ms']):.1f} | {steal_around(i):.0f} |")
print(f"peak RSS {running_peak:.0f} MB while processing, {peak_mb:.0f} MB with the close; RSS "
      f"growth over the last {tail} images {rss_growth:.1f}% ({rss_start:.0f} -> {rss_end:.0f} MB); "
      f"map file {db / 1e6:.0f} MB")
print(f"the highest RSS over the first and the second half of the last {tail} images: "
      f"{rss_half_start:.0f} -> {rss_half_end:.0f} MB ({rss_half_growth:+.1f}%)")
print(f"revisit images found: {found} of {revisit_images} in the sequence "
      f"({through_retrieval} on locations retrieved from LTM); false positives: {false_positives}")

# What grows with LTM (issue 39): each stage's median over the 1,000 images from the first at which
# LTM holds 1,000, 10,000, 100,000... locations, and over the last 1,000.
starts = []
for size in (1000, 10000, 100000, 1000000):
    first_at = next((i for i, r in enumerate(rows) if int(r["ltm_size"]) >= size), None)
    if first_at is not None and first_at + 1000 <= len(rows):
        starts.append((f"LTM {size:,}", first_at))
if len(rows) >= 2000:
    starts.append(("last 1,000", len(rows) - 1000))
if starts:
    print("\n| images from | LTM locations | iteration | detector CPU | signature "
          "| likelihood + filter + selection | retrieval | transfer | checkpoint |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
for label, start in starts:
    block = rows[start:start + 1000]
    def median(*columns):
        return statistics.median(sum(float(r[c] or 0) for c in columns) for r in block)
    print(f"| {start + 1:,} ({label}) | {int(block[0]['ltm_size']):,} | {median('iteration_ms'):.2f} "
          f"| {median('cpu_ms'):.2f} | {median('signature_ms'):.2f} "
          f"| {median('likelihood_ms', 'filter_ms', 'selection_ms'):.2f} "
          f"| {median('retrieval_ms'):.2f} | {median('transfer_ms'):.2f} "
          f"| {median('checkpoint_ms'):.2f} |")
