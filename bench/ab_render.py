#!/usr/bin/python3
"""Alternating A/B timing of two multiray binaries on one render.

  bench/ab_render.py OLD_BINARY NEW_BINARY ROUNDS RENDER_ARGS...

Each round runs both binaries (the order alternates), each `multiray render RENDER_ARGS`
into a folder of its own, and takes the median frame_ms of frames 1.. from stats.json
(frame 0 holds kernel builds and first touches). Prints each binary's per-run medians and
their min / median / max: call a difference only when the ranges separate. Run it on a
quiet machine (docs/benchmarks.md says how the figures were taken).
"""
import json
import statistics
import subprocess
import sys
import tempfile

if len(sys.argv) < 5:
    sys.exit(__doc__)
old, new, rounds, args = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4:]
bins = [("old", old), ("new", new)]
res = {k: [] for k, _ in bins}
with tempfile.TemporaryDirectory() as tmp:
    for r in range(rounds):
        for k, b in bins if r % 2 == 0 else bins[::-1]:
            out = f"{tmp}/{k}"
            subprocess.run([b, "render"] + args + ["-o", out, "--overwrite", "-q"], check=True,
                           stdout=subprocess.DEVNULL)
            with open(out + "/stats.json") as f:
                frames = json.load(f)["frames"][1:]
            res[k].append(statistics.median(fr["frame_ms"] for fr in frames))
for k, v in res.items():
    print(k, " ".join(f"{x:.1f}" for x in v),
          "| min %.1f median %.1f max %.1f" % (min(v), statistics.median(v), max(v)))
