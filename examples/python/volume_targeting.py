"""Volume frame-time targeting: how close does each adaptation mode keep a volume's frame
time to a target? For a few targets, multiray.bench renders the same frames with
`target_ms` set (as `multiray bench VOLUME --target-ms T --adapt MODES`, docs/volumes.md)
and the frame time, the error and the step scale chosen are printed (and plotted).

Run from the repository root after building (the module is in build/python):

    PYTHONPATH=build/python /usr/bin/python3 examples/python/volume_targeting.py targeting.png

Without a VOLUME argument a small synthetic volume is made here (a soft ball of 8-bit
density, written as raw bytes next to nothing else), so the study needs no data set; with
one (e.g. ../shared/data/volumes/neghip_64x64x64_uint8.nhdr) that volume is used. Frame
times are measured, so they vary from run to run and with the machine's load. Without
matplotlib (Debian: python3-matplotlib) the table is printed and no plot is drawn.
"""
import argparse
import os
import sys
import tempfile

import multiray


def synthetic_volume(folder, n):
    """An n^3 uint8 volume: density falling from 255 at the centre to 0 at radius n/2.
    Returns (path, raw spec) for bench(scene=..., raw=...)."""
    c = (n - 1) / 2
    data = bytearray()
    for z in range(n):
        for y in range(n):
            for x in range(n):
                r = ((x - c) ** 2 + (y - c) ** 2 + (z - c) ** 2) ** 0.5 / (n / 2)
                data.append(max(0, min(255, int(255 * (1 - r)))))
    path = os.path.join(folder, "ball.raw")
    with open(path, "wb") as f:
        f.write(bytes(data))
    return path, f"{n}x{n}x{n}:uint8"


def study(volume, raw, targets, modes, res, frames):
    """[(target, lane, mean frame ms, targeting dict)] over every target and mode."""
    rows = []
    extra = dict(raw=raw, tf="grey") if raw else {}
    for target in targets:
        doc = multiray.bench(volume, **extra, res=res, frames=frames, warmup=min(2, frames - 1),
                             target_ms=target, adapt=modes, balancers="static",
                             devices="cpu:threads=1,cpu:threads=1", repeats=1, probe_ms=0,
                             ideal_frames=1)
        for run in doc["runs"]:
            rows.append((target, run["lane"], run["summary"]["mean_frame_ms"],
                         run["targeting"]))
    return rows


def print_table(rows):
    print("frame time vs target (measured; frames after the warm-up)")
    print(f"{'target ms':>9} {'frame ms':>9} {'rmse ms':>8} {'step x':>7}  lane")
    for target, lane, ms, t in rows:
        print(f"{target:>9g} {ms:>9.2f} {t['rmse_ms']:>8.2f} {t['mean_step_scale']:>7.2f}  "
              f"{lane}")


def plot(rows, png):
    try:
        import matplotlib
    except ImportError:
        print(f"matplotlib is not installed (Debian: python3-matplotlib): no plot, {png} "
              "not written")
        return False
    matplotlib.use("Agg")  # files only, no display
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    lanes = sorted({lane for _, lane, _, _ in rows})
    for lane in lanes:
        pts = [(t, ms) for t, l, ms, _ in rows if l == lane]
        ax.plot([t for t, _ in pts], [ms for _, ms in pts], marker="o", label=lane)
    top = max(t for t, _, _, _ in rows)
    ax.plot([0, top], [0, top], "k--", linewidth=0.8, label="frame time = target")
    ax.set_xlabel("target ms")
    ax.set_ylabel("mean frame ms")
    ax.legend()
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    print(f"wrote {png}")
    return True


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("png", help="where the plot goes (PNG)")
    p.add_argument("volume", nargs="?", help="a .nhdr/.nrrd volume (default: synthetic)")
    p.add_argument("--targets", default="2,5,10", help="target frame times in ms")
    p.add_argument("--adapt", default="none,last-frame,predict", help="modes, as --adapt")
    p.add_argument("--res", default="160x120")
    p.add_argument("--frames", type=int, default=12)
    p.add_argument("--size", type=int, default=48, help="edge of the synthetic volume")
    a = p.parse_args(argv)
    targets = [float(t) for t in a.targets.split(",")]
    with tempfile.TemporaryDirectory() as folder:
        volume, raw = (a.volume, None) if a.volume else synthetic_volume(folder, a.size)
        rows = study(volume, raw, targets, a.adapt, a.res, a.frames)
    print_table(rows)
    plot(rows, a.png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
