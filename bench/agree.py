#!/usr/bin/env python3
"""Do two runs of the same `multiray bench --repeats K --json` agree?

Usage: bench/agree.py RUN1.json RUN2.json

Prints both runs side by side as a Markdown table (each balancer's frame time and
efficiency: median [95% interval]; ratio to the run's best), each run's noise gate, and the
check of issue 27: every pair of balancers whose frame-time intervals separate in one run
must keep its order in the other. Exit status 1 when some pair changes order.
"""
import itertools
import json
import sys


def lanes(doc):
    return {l["lane"]: l for l in doc["repeats"]["lanes"]}


def cell(i, fmt):
    if not i:
        return "-"
    return (fmt + " [" + fmt + ", " + fmt + "]") % (i["median"], i["lo"], i["hi"])


def separated(a, b):
    return a["hi"] < b["lo"] or b["hi"] < a["lo"]


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    docs = [json.load(open(p)) for p in sys.argv[1:]]
    runs = [lanes(d) for d in docs]
    names = [l["lane"] for l in docs[0]["repeats"]["lanes"]]
    print("| balancer | run 1 frame ms | run 1 efficiency | run 1 x best "
          "| run 2 frame ms | run 2 efficiency | run 2 x best |")
    print("|---|---|---|---|---|---|---|")
    for n in names:
        row = [n]
        for r in runs:
            l = r[n]
            row += [cell(l["frame_ms"], "%.1f"), cell(l["efficiency"], "%.3f"),
                    "best" if not l["ratio_to_best"] else cell(l["ratio_to_best"], "%.2f")]
        print("| " + " | ".join(row) + " |")
    print()
    for k, d in enumerate(docs):
        z = d["noise"]
        print("run %d: %d blocks; contention probe %.2f before, %.2f after; steal %.1f%%; block "
              "spread %.0f%%; trustworthy: %s; verdict: %s" % (
                  k + 1, d["repeats"]["blocks"], z["contention_probe_before"],
                  z["contention_probe_after"], 100 * z["steal_fraction"],
                  100 * z["block_spread"], z["trustworthy"], d["repeats"]["verdict"]))
    flipped = 0
    for k in range(2):
        this, other = runs[k], runs[1 - k]
        pairs = [(a, b) for a, b in itertools.combinations(names, 2)
                 if separated(this[a]["frame_ms"], this[b]["frame_ms"])]
        kept = 0
        for a, b in pairs:
            first = this[a]["frame_ms"]["median"] < this[b]["frame_ms"]["median"]
            again = other[a]["frame_ms"]["median"] < other[b]["frame_ms"]["median"]
            if first == again:
                kept += 1
            else:
                flipped += 1
                print("ORDER CHANGED: %s vs %s (separated in run %d)" % (a, b, k + 1))
        print("pairs separated in run %d: %d of %d; same order in run %d: %d" % (
            k + 1, len(pairs), len(names) * (len(names) - 1) // 2, 2 - k, kept))
    return 1 if flipped else 0


if __name__ == "__main__":
    sys.exit(main())
