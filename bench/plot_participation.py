#!/usr/bin/python3
"""Plot of devices left out over a run, from a `multiray bench --regret --json` document.

Usage: bench/plot_participation.py BENCH.json OUT.svg [DEVICE]

Top: the frame time of every lane per frame (block 0): the default (auto), each device
alone and all devices without the participation rule. Bottom: the default's planned share
of DEVICE (default 1) per frame, log scale, with the frames it was left out shaded and
its fitted fixed cost per frame (right axis). Plain SVG, no plotting library.
"""
import json
import math
import sys

W, H, PAD_L, PAD_R, PAD_T, GAP = 760, 520, 64, 64, 36, 56
PANEL = (H - PAD_T - GAP - 40) // 2
COLORS = ["#1b6ac9", "#d1495b", "#2e933c", "#edae49", "#6c4f9e", "#888888"]


def lanes(doc):
    out = []
    for run in doc["runs"]:
        label = run.get("lane") or run.get("balancer")
        if label.startswith("hybrid:bands=1:leave=0:probe=0"):
            continue  # --regret's filler lane, the same as the first
        out.append((label, run["frames"]))
    return out


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    doc = json.load(open(sys.argv[1]))
    device = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    runs = lanes(doc)
    auto = next(f for label, f in runs if label == "auto")
    n = len(auto)
    shown = [(l, f) for l, f in runs if max(x["frame_ms"] for x in f) < 40 * min(
        x["frame_ms"] for x in auto)]
    # Up to 3x the default's median frame: frame 0 (an even split while nothing is known)
    # would flatten every other frame; lines above it are clipped at the top.
    times = sorted(x["frame_ms"] for x in auto)
    top = min(max(max(x["frame_ms"] for x in f) for _, f in shown) * 1.1,
              3 * times[len(times) // 2])
    x_of = lambda i: PAD_L + (W - PAD_L - PAD_R) * i / max(n - 1, 1)
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
           'font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>',
           f'<text x="{W / 2}" y="20" text-anchor="middle" font-size="14">'
           f"{doc.get('scene', '')}: devices left out by the default "
           '(bench --regret, block 0)</text>']
    # Panel 1: frame times.
    y0 = PAD_T
    y_of = lambda v: y0 + PANEL - PANEL * min(v, top) / top
    half = (x_of(1) - x_of(0)) / 2
    band = lambda i: (max(x_of(i) - half, PAD_L), min(x_of(i) + half, W - PAD_R))
    for i, f in enumerate(auto):  # shade the frames the device was left out
        if f["left_out"][device]:
            a, b = band(i)
            for y in (y0, y0 + PANEL + GAP):
                svg.append(f'<rect x="{a:.1f}" y="{y}" width="{b - a:.1f}" height="{PANEL}" '
                           'fill="#eeeeee"/>')
    for k, (label, frames) in enumerate(shown):
        pts = " ".join(f"{x_of(i):.1f},{y_of(x['frame_ms']):.1f}" for i, x in enumerate(frames))
        svg.append(f'<polyline fill="none" stroke="{COLORS[k % len(COLORS)]}" '
                   f'stroke-width="{2.5 if label == "auto" else 1.5}" points="{pts}"/>')
        svg.append(f'<text x="{PAD_L + 8}" y="{y0 + 14 + 14 * k}" '
                   f'fill="{COLORS[k % len(COLORS)]}">{label}</text>')
    for v in range(0, int(top) + 1, max(int(top / 5 / 10) * 10, 10)):
        svg.append(f'<text x="{PAD_L - 6}" y="{y_of(v) + 4:.1f}" text-anchor="end">{v}</text>')
    svg.append(f'<text x="16" y="{y0 + PANEL / 2}" transform="rotate(-90 16 {y0 + PANEL / 2})"'
               ' text-anchor="middle">frame ms</text>')
    svg.append(f'<rect x="{PAD_L}" y="{y0}" width="{W - PAD_L - PAD_R}" height="{PANEL}" '
               'fill="none" stroke="#444"/>')
    # Panel 2: the device's planned share (log) and its fitted fixed cost.
    y1 = PAD_T + PANEL + GAP
    lo, hi = -3.0, 0.0  # shares 0.001 .. 1
    ys = lambda s: y1 + PANEL - PANEL * (max(math.log10(max(s, 1e-3)), lo) - lo) / (hi - lo)
    # Lines only between consecutive frames it took part in (none across its absences).
    for i in range(1, n):
        a, b = auto[i - 1]["planned_share"][device], auto[i]["planned_share"][device]
        if a > 0 and b > 0:
            svg.append(f'<line x1="{x_of(i - 1):.1f}" y1="{ys(a):.1f}" x2="{x_of(i):.1f}" '
                       f'y2="{ys(b):.1f}" stroke="{COLORS[0]}" stroke-width="2"/>')
    for i, f in enumerate(auto):
        if f["planned_share"][device] > 0:
            svg.append(f'<circle cx="{x_of(i):.1f}" cy="{ys(f["planned_share"][device]):.1f}" '
                       f'r="3" fill="{COLORS[0]}"/>')
    fixed = [(i, f["device_model"][device]["fixed_ms"]) for i, f in enumerate(auto)
             if f.get("device_model") and f["device_model"][device]["determined"]]
    fmax = max([v for _, v in fixed] + [1]) * 1.2
    yf = lambda v: y1 + PANEL - PANEL * v / fmax
    if fixed:
        pts = " ".join(f"{x_of(i):.1f},{yf(v):.1f}" for i, v in fixed)
        svg.append(f'<polyline fill="none" stroke="{COLORS[1]}" stroke-dasharray="5,3" '
                   f'stroke-width="1.5" points="{pts}"/>')
    for e in range(-3, 1):
        svg.append(f'<text x="{PAD_L - 6}" y="{ys(10 ** e) + 4:.1f}" text-anchor="end">'
                   f'{10 ** e:g}</text>')
    for v in range(0, int(fmax) + 1, max(int(fmax / 4 / 10) * 10, 10)):
        svg.append(f'<text x="{W - PAD_R + 6}" y="{yf(v) + 4:.1f}" fill="{COLORS[1]}">{v}</text>')
    svg.append(f'<text x="16" y="{y1 + PANEL / 2}" transform="rotate(-90 16 {y1 + PANEL / 2})" '
               f'text-anchor="middle" fill="{COLORS[0]}">share of device {device}</text>')
    svg.append(f'<text x="{W - 14}" y="{y1 + PANEL / 2}" transform="rotate(90 {W - 14} '
               f'{y1 + PANEL / 2})" text-anchor="middle" fill="{COLORS[1]}">'
               'its fixed ms per frame (fit)</text>')
    svg.append(f'<rect x="{PAD_L}" y="{y1}" width="{W - PAD_L - PAD_R}" height="{PANEL}" '
               'fill="none" stroke="#444"/>')
    for i in range(0, n, max(n // 12, 1)):
        svg.append(f'<text x="{x_of(i):.1f}" y="{y1 + PANEL + 16}" text-anchor="middle">{i}</text>')
    svg.append(f'<text x="{W / 2}" y="{H - 6}" text-anchor="middle">frame (grey: device '
               f'{device} left out, not started)</text>')
    svg.append("</svg>")
    with open(sys.argv[2], "w") as out:
        out.write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main()
