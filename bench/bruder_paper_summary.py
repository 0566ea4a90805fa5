#!/usr/bin/python3
"""The figures of bench/bruder_paper_setting.sh over its repeats: for each targeting lane
the RMSE of the frame time against the target and the worst frame, for each quality run
the PSNR against the 0.1-voxel reference and the mean frame time; each as the median and
the range (min-max) over the runs found, and whether every run was quiet enough to trust.

  /usr/bin/python3 bench/bruder_paper_summary.py OUT
"""
import glob
import json
import os
import re
import statistics
import sys


def spread(values, fmt):
    """'median [min, max] (n)' of values, each printed with fmt."""
    if not values:
        return "-"
    med = statistics.median(values)
    return f"{fmt.format(med)} [{fmt.format(min(values))}, {fmt.format(max(values))}] (n={len(values)})"


def load(out, pattern):
    """{name without -rN: [json, ...]} for the files in out matching pattern."""
    groups = {}
    for path in sorted(glob.glob(os.path.join(out, pattern))):
        name = re.sub(r"-r\d+$", "", os.path.basename(path)[: -len(".json")])
        with open(path, encoding="utf-8") as f:
            groups.setdefault(name, []).append(json.load(f))
    return groups


def main():
    if len(sys.argv) != 2 or not os.path.isdir(sys.argv[1]):
        sys.exit("usage: bruder_paper_summary.py OUT (the folder bench/bruder_paper_setting.sh wrote)")
    out = sys.argv[1]
    print("targeting: RMSE of the frame time against the target (ms), worst frame / target")
    for name, docs in load(out, "targeting-*.json").items():
        lanes = {}
        for doc in docs:
            for run in doc["runs"]:
                lanes.setdefault(run["lane"], []).append(run["targeting"])
        trusted = all(doc.get("trustworthy") for doc in docs)
        for lane, ts in lanes.items():
            print(f"  {name:<24} {lane:<44} RMSE {spread([t['rmse_ms'] for t in ts], '{:.1f}')}"
                  f"  worst {spread([t['worst_frame_over_target'] for t in ts], '{:.2f}')}"
                  f"{'' if trusted else '  (a run not quiet enough to trust)'}")
    print("quality: PSNR against the 0.1-voxel reference (dB), mean frame (ms)")
    for name, docs in load(out, "quality-*.json").items():
        runs = [run for doc in docs for run in doc["runs"]]
        trusted = all(doc.get("trustworthy") for doc in docs)
        print(f"  {name:<24} PSNR {spread([r['targeting']['psnr_db_vs_full_quality'] for r in runs], '{:.1f}')}"
              f"  frame {spread([r['summary']['mean_frame_ms'] for r in runs], '{:.0f}')}"
              f"{'' if trusted else '  (a run not quiet enough to trust)'}")


if __name__ == "__main__":
    main()
