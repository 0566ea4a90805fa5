#!/usr/bin/env python3
# Is a balancer's deviation the noise that last frame's speeds cannot follow? For each lane of
# bench JSON files: the mean deviation after the warm-up, the deviation an oracle would have
# had that split frame f exactly by frame f-1's measured speeds (device times t_i(f) ∝
# s_i(f-1)/s_i(f), speed = samples / device time), and how much each device's speed
# changes from one frame to the next (docs/benchmarks.md, "Each paper like for like").
#   python3 bench/semi_static_noise.py BENCH.json ...
import json, sys, statistics as st
def dev(ts):
    m = sum(ts)/len(ts); return max(abs(t-m) for t in ts)/m
for path in sys.argv[1:]:
    d = json.load(open(path))
    for run in d['runs']:
        fr = [f for f in run['frames'] if f.get('quality',{}).get('image_scale',1) == 1]
        warm = run['summary'].get('from_frame', 10)
        speeds = [[s/t if t > 0 else 0 for s, t in zip(f['samples'], f['device_ms'])] for f in fr]
        actual, lag, change = [], [], []
        for k in range(1, len(fr)):
            if fr[k]['frame'] < warm: continue
            actual.append(fr[k]['deviation'])
            r = [a/b for a, b in zip(speeds[k-1], speeds[k]) if b > 0]
            if len(r) == len(speeds[k]): lag.append(dev(r))
            change += [abs(b/a-1) for a, b in zip(speeds[k-1], speeds[k]) if a > 0]
        print(f"{path.split('/')[-1]} {run['balancer'][:40]:40s} deviation {st.mean(actual):.3f}  "
              f"split-by-last-frame oracle {st.mean(lag):.3f}  speed change per frame "
              f"median {st.median(change):.3f} mean {st.mean(change):.3f}  frames {len(actual)}")
