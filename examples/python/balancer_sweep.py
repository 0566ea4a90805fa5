"""Balancer sweep: record a small trace, replay it on 1..N virtual devices with several
balancers (multiray.simulate, virtual time) and plot efficiency against device count.

Run from the repository root after building (the module is in build/python):

    PYTHONPATH=build/python /usr/bin/python3 examples/python/balancer_sweep.py sweep.png

The trace is recorded by multiray.bench(trace=PREFIX) on two one-thread CPU devices
(PREFIX-<balancer>.trace); --trace FILE replays an existing one instead (as written by
`multiray render --trace FILE`). Without matplotlib (Debian: python3-matplotlib) the table
is printed and no plot is drawn.
"""
import argparse
import os
import sys
import tempfile

import multiray


def record_trace(folder, res, frames):
    """A trace of `frames` frames of the default scene, rendered with `queue`."""
    prefix = os.path.join(folder, "sweep")
    multiray.bench(res=res, spp=1, frames=frames, devices="cpu:threads=1,cpu:threads=1",
                   balancers="queue", repeats=1, probe_ms=0, ideal_frames=1, trace=prefix)
    return prefix + "-queue.trace"


def sweep(trace, devices, balancers, link, slowdown, frames):
    """{balancer: [(devices, efficiency), ...]} from one simulate() over every pair: devices
    `slowdown` times slower than the recording one, speeds random in [0.3, 1] and 5% noise
    per frame (as bench/scaling.sh), the trace's frames cycled to `frames`."""
    doc = multiray.simulate(trace, devices=devices, balancers=balancers, link=link,
                            slowdown=slowdown, speeds="random:0.3", noise=0.05, frames=frames)
    series = {}
    # runs come device count by device count, balancer by balancer, in the order given
    for k, run in enumerate(doc["runs"]):
        name = balancers[k % len(balancers)]
        series.setdefault(name, []).append((run["devices"], run["efficiency"]))
    return doc, series


def print_table(series, devices):
    print("efficiency (ideal / simulated frame time), virtual time")
    print(f"{'balancer':<12}" + "".join(f"{n:>8}" for n in devices))
    for name, points in series.items():
        print(f"{name:<12}" + "".join(f"{e:>8.3f}" for _, e in points))


def plot(series, png, title):
    try:
        import matplotlib
    except ImportError:
        print(f"matplotlib is not installed (Debian: python3-matplotlib): no plot, {png} "
              "not written")
        return False
    matplotlib.use("Agg")  # files only, no display
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4))
    for name, points in series.items():
        ax.plot([n for n, _ in points], [e for _, e in points], marker="o", label=name)
    ax.set_xscale("log", base=2)
    ax.set_xlabel("devices")
    ax.set_ylabel("efficiency")
    ax.set_ylim(0, 1.05)
    ax.set_title(title)
    ax.legend()
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    print(f"wrote {png}")
    return True


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("png", help="where the plot goes (PNG)")
    p.add_argument("--trace", help="replay this trace instead of recording one")
    p.add_argument("--res", default="640x360", help="resolution of the recorded trace")
    p.add_argument("--frames", type=int, default=8, help="frames of the recorded trace")
    p.add_argument("--sim-frames", type=int, default=40,
                   help="frames simulated (the trace's, cycled); a tenth are warm-up")
    p.add_argument("--slowdown", type=float, default=20,
                   help="virtual devices this many times slower than the recording one "
                        "(a 640x360 frame on a few slow devices, not on 32 fast cores)")
    p.add_argument("--devices", default="1,2,4,8,16,32", help="device counts to simulate")
    p.add_argument("--balancers", default="uniform,static,queue,dlb,hybrid")
    p.add_argument("--link", default="lan", help="emulated link (as simulate --link)")
    a = p.parse_args(argv)
    devices = [int(n) for n in a.devices.split(",")]
    balancers = a.balancers.split(",")
    with tempfile.TemporaryDirectory() as folder:
        trace = a.trace or record_trace(folder, a.res, a.frames)
        doc, series = sweep(trace, devices, balancers, a.link, a.slowdown, a.sim_frames)
    print(f"{doc['frames']} frames, warm-up {doc['warmup']}, link {doc['link']}, "
          f"{doc['result_bytes_per_pixel']:g} result bytes a pixel")
    print_table(series, devices)
    plot(series, a.png, f"efficiency vs devices (simulated, link {a.link})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
