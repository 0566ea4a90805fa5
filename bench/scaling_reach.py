#!/usr/bin/env python3
"""Reads `multiray simulate --json` files and prints, per file, a markdown table of each
balancer's efficiency by device count and the largest count at which it stays at or above
the goal (0.9 on the LAN, 0.8 on Wi-Fi or any other link): "reach" is the last count of an
unbroken run of counts from the smallest that meet the goal ("-" if the smallest misses).

Usage: bench/scaling_reach.py FILE.json ..."""
import json
import sys


def reach(counts, effs, goal):
    best = "-"
    for n, e in zip(counts, effs):
        if e < goal:
            break
        best = str(n)
    return best


def table(path):
    with open(path) as f:
        doc = json.load(f)
    goal = 0.9 if doc.get("link") == "lan" else 0.8
    rows = {}
    for run in doc["runs"]:
        rows.setdefault(run["balancer"], {})[run["devices"]] = run["efficiency"]
    counts = sorted({n for r in rows.values() for n in r})
    # The name alone where it is unique in the file, else the whole spec.
    short = {}
    for spec in rows:
        name = spec.split(":")[0]
        short[spec] = spec if sum(s.split(":")[0] == name for s in rows) > 1 else name
    print(f"\n{path}: link {doc.get('link')}, results {doc.get('result_encoding')}, "
          f"goal {goal}")
    print("| balancer | " + " | ".join(str(n) for n in counts) + f" | reach ≥ {goal} |")
    print("|---" * (len(counts) + 2) + "|")
    for name, r in rows.items():
        effs = [r.get(n, float("nan")) for n in counts]
        cells = " | ".join(f"{e:.2f}" for e in effs)
        print(f"| {short[name]} | {cells} | {reach(counts, effs, goal)} |")


def main(argv):
    if len(argv) < 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    for path in argv[1:]:
        try:
            table(path)
        except (OSError, ValueError, KeyError) as e:
            print(f"scaling_reach.py: {path}: {e}", file=sys.stderr)
            return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
