#!/usr/bin/env python3
"""What a balancer written in Python costs per frame: plan() + update() of the Cycles twin
(examples/python/cycles_balancer.py), of a trivial Python balancer (even row bands, no
update) and of the C++ `cycles`, each replayed on the same recorded trace. The time is the
balancer's call as the engine makes it (for Python: the GIL, the conversions of the shape,
the stats and the plan, and check_plan). Pulls and steals are served by the C++
Dispatcher and never call Python, so there is no per-pull cost to measure.

Not run by the tests; run it on a quiet machine:
    PYTHONPATH=build/python python3 bench/python_balancer_overhead.py \
        --cli build/src/app/multiray [--trace T] [--res 640x360] [--repeats 20] [--frames 200]
Prints per balancer the mean per-frame time over repeats with a 95% interval (Student t
over the repeats' means), then one JSON line with everything.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import multiray

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples", "python"))
from cycles_balancer import Cycles  # noqa: E402

# Two-sided 95% Student t quantiles by degrees of freedom (then the normal's 1.96).
T95 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306,
       9: 2.262, 10: 2.228, 12: 2.179, 15: 2.131, 20: 2.086, 25: 2.060, 30: 2.042}


class EvenRows(multiray.Balancer):
    """The least a Python balancer can do: even row bands, nothing learnt."""

    def plan(self, shape, frame):
        n, h = self.devices, shape.height
        cuts = [h * i // n for i in range(n + 1)]
        return multiray.Plan([[multiray.WorkItem(v, 0, cuts[i], shape.width, cuts[i + 1])
                               for v in range(shape.views)] if cuts[i + 1] > cuts[i] else []
                              for i in range(n)], [1.0 / n] * n)


def t95(dof):
    return T95.get(dof) or (T95[max(k for k in T95 if k <= dof)] if dof < 30 else 1.96)


def summary(samples):
    n = len(samples)
    mean = sum(samples) / n
    sd = math.sqrt(sum((x - mean) ** 2 for x in samples) / (n - 1)) if n > 1 else 0.0
    half = t95(n - 1) * sd / math.sqrt(n) if n > 1 else float("nan")
    return {"mean_ms": mean, "lo_ms": mean - half, "hi_ms": mean + half, "repeats": n}


def record(cli, res, frames, path):
    subprocess.run([cli, "render", "--res", res, "--spp", "1", "--frames", str(frames),
                    "--devices", "cpu:threads=1,cpu:threads=1:speed=0.5", "--balancer", "queue",
                    "--trace", path, "--out", os.path.dirname(path) + "/out", "--quiet"],
                   check=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trace", help="a recorded trace (else one is recorded with --cli)")
    ap.add_argument("--cli", default="build/src/app/multiray")
    ap.add_argument("--res", default="640x360")
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--frames", type=int, default=200, help="replayed frames per repeat")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = a.trace or os.path.join(tmp, "trace")
        if not a.trace:
            record(a.cli, a.res, 10, path)
        trace = multiray.read_trace(path)
    n = len(trace.devices)
    makers = {"cpp cycles": lambda: "cycles:interval_ms=0",
              "python cycles twin": lambda: Cycles(n, interval_ms=0.0),
              "python even rows": lambda: EvenRows(n)}
    results = {}
    for label, make in makers.items():
        per_repeat = {"plan": [], "update": [], "total": []}
        for _ in range(a.repeats):
            frames = multiray.replay(trace, make(), frames=a.frames)
            plan = sum(f["plan_ms"] for f in frames) / len(frames)
            update = sum(f["update_ms"] for f in frames) / len(frames)
            per_repeat["plan"].append(plan)
            per_repeat["update"].append(update)
            per_repeat["total"].append(plan + update)
        results[label] = {k: summary(v) for k, v in per_repeat.items()}
        s = results[label]["total"]
        print(f"{label:20s} plan+update {s['mean_ms'] * 1e3:9.1f} us/frame "
              f"(95% [{s['lo_ms'] * 1e3:.1f}, {s['hi_ms'] * 1e3:.1f}])")
    shape = trace[0].shape
    print(json.dumps({"bench": "python_balancer_overhead", "devices": n,
                      "res": f"{shape.width}x{shape.height}", "frames": a.frames,
                      "results": results}))


if __name__ == "__main__":
    main()
