#!/usr/bin/python3
"""Compare two 8-bit sRGB PNGs of the same size (issue 35's image check):

  /usr/bin/python3 bench/image_diff.py A.png B.png [--side-by-side OUT.png]

Prints one JSON line: mean_abs (mean absolute difference over all pixels and channels, in
8-bit sRGB levels), within8 (fraction of pixels whose channels all differ by at most 8
levels), the same two over the pixels that are not black in either image (the volume's
footprint: a mostly black frame would otherwise hide differences), and the footprint's size.
"""
import argparse
import json
import sys

import numpy as np
import vtk
from vtk.util import numpy_support


def read_png(path):
    reader = vtk.vtkPNGReader()
    if not reader.CanReadFile(path):
        print(f"image_diff.py: cannot read PNG {path}", file=sys.stderr)
        sys.exit(2)
    reader.SetFileName(path)
    reader.Update()
    out = reader.GetOutput()
    w, h, _ = out.GetDimensions()
    arr = numpy_support.vtk_to_numpy(out.GetPointData().GetScalars())
    return arr.reshape(h, w, -1)[:, :, :3].copy()  # bottom-up rows, as VTK holds them


def write_png(path, rgb):
    h, w, _ = rgb.shape
    img = vtk.vtkImageData()
    img.SetDimensions(w, h, 1)
    img.GetPointData().SetScalars(numpy_support.numpy_to_vtk(rgb.reshape(-1, 3), deep=True))
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputData(img)
    writer.Write()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--side-by-side")
    args = ap.parse_args()
    a, b = read_png(args.a), read_png(args.b)
    if a.shape != b.shape:
        print(f"image_diff.py: sizes differ: {a.shape} and {b.shape}", file=sys.stderr)
        sys.exit(2)
    d = np.abs(a.astype(np.int32) - b.astype(np.int32))
    worst = d.max(axis=2)
    seen = (a.max(axis=2) > 0) | (b.max(axis=2) > 0)
    n = int(seen.sum())
    print(json.dumps({
        "mean_abs": float(d.mean()),
        "within8": float((worst <= 8).mean()),
        "footprint_pixels": n,
        "footprint_mean_abs": float(d[seen].mean()) if n else 0.0,
        "footprint_within8": float((worst[seen] <= 8).mean()) if n else 1.0,
    }))
    if args.side_by_side:
        gap = np.full((a.shape[0], 4, 3), 128, np.uint8)
        write_png(args.side_by_side, np.concatenate([a, gap, b], axis=1))


if __name__ == "__main__":
    main()
