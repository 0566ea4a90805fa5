"""Blender Cycles' balancer in Python: the twin of multiray's C++ `cycles`
(src/balance/peers_cycles.h), plan for plan, bit for bit, while no device dies.
Row slices by weight; weights move 1/N of the way toward the mean time when a device is
more than 2% off, right after the first frame, after a change, else every interval_ms.

Run from the repository root after building (the module is in build/python; it was built
for Debian's /usr/bin/python3, which has numpy):

    PYTHONPATH=build/python /usr/bin/python3 examples/python/cycles_balancer.py

registers it as `pycycles` and benches it beside the C++ `cycles` on a fast and an emulated
3x slower core (20 frames), printing each one's mean frame time and whether their images
agree. Imported (`from cycles_balancer import Cycles`), it only defines the class."""
import math

import multiray


def _round(x):  # C's round() for x >= 0: halves away from zero (Python's round() is to even)
    return math.floor(x) + (x - math.floor(x) >= 0.5)


def _sum(xs):  # in order, as the C++ sums (sum() of floats is compensated from 3.12)
    s = 0.0
    for x in xs:
        s += x
    return s


def _normalised(ws):
    s = _sum(ws)
    return [w / s for w in ws]


class Cycles(multiray.Balancer):
    def __init__(self, devices, interval_ms=1000.0):
        super().__init__(devices)
        self.interval_ms, self.w, self.spent = interval_ms, [1.0 / devices] * devices, [0.0] * devices
        self.clock = self.last = 0.0
        self.measured = self.changed = False

    def plan(self, shape, frame):
        ratios, y, assigned = _normalised(self.w), 0, []
        for i, r in enumerate(ratios):
            left = shape.height - y
            rows = left if i == len(ratios) - 1 else min(max(_round(shape.height * min(r, 1.0)), 1), left)
            assigned.append([multiray.WorkItem(v, 0, y, shape.width, y + rows) for v in range(shape.views)] if rows else [])
            y += rows
        return multiray.Plan(assigned, ratios)

    def update(self, stats):
        times = [d.time_ms for d in stats.devices]
        if len(times) != self.devices or not all(math.isfinite(t) and t > 0 for t in times):
            return  # Cycles times every device: a frame without that is not used
        self.spent = [s + t for s, t in zip(self.spent, times)]
        self.clock += max(times)
        if self.measured and not self.changed and self.clock - self.last <= self.interval_ms:
            return
        self.measured, self.last, n = True, self.clock, self.devices
        mean = _sum(self.spent) / n
        targets = [t + (mean - t) * (1.0 / n) for t in self.spent]
        self.changed = any(abs(1.0 - g / mean) > 0.02 for g in targets)
        if self.changed:
            self.w = _normalised(_normalised([w * (g / t) for w, g, t in zip(self.w, targets, self.spent)]))
            self.spent = [0.0] * n


if __name__ == "__main__":
    multiray.register_balancer("pycycles", Cycles, help="Cycles' balancer in Python",
                               params={"interval_ms": 1000.0})
    doc = multiray.bench(res="160x90", frames=20, balancers="cycles,pycycles", repeats=1,
                         devices="cpu:threads=1,cpu:threads=1:speed=0.33", probe_ms=0)
    for run in doc["runs"]:
        print(f"{run['balancer']:>10}: {run['summary']['mean_frame_ms']:.1f} ms a frame")
    same = all(a["image_hash"] == b["image_hash"]
               for a, b in zip(doc["runs"][0]["frames"], doc["runs"][1]["frames"]))
    print("images: " + ("identical, frame for frame" if same else "DIFFERENT"))
