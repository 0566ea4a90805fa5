#!/usr/bin/python3
"""VTK's CPU volume raycaster (vtkFixedPointVolumeRayCastMapper) on multiray's volume setup,
for the equal-work comparison of issue 35 (bench/volume_vs_vtk.sh runs it; every difference
in the work is named at the top of that script).

  xvfb-run -a /usr/bin/python3 bench/vtk_volume.py VOLUME.nhdr --threads 1 --frames 20 \
      --out vtk.png

Renders --frames timed frames (after --warmup untimed ones) from one fixed camera, times each
Render() call by the wall clock, writes the last image and prints one JSON line:
{threads, frames, median_ms, frame_ms: [...], image, image_display}.

Matched to multiray (src/volume, src/render/volume_raycaster.cpp):
- the grid is centred on the origin as multiray's (voxel i's centre at (i + 0.5 - n/2) *
  spacing), so the same --camera means the same view;
- the `angio` preset's points (fractions of the volume's [min, max]) become data values;
- opacity is per --reference-step voxel lengths (ScalarOpacityUnitDistance), rays step
  --step voxel lengths (SampleDistance, no automatic adjustment), one ray per pixel;
- shading: ambient 0.3 + diffuse 0.7 from one white headlight (with a white ambient colour,
  see below), two-sided (the renderer's default), no specular; linear interpolation; black
  background.
- multiray writes its PNG as sRGB-encoded radiance; VTK's colours are the colours
  themselves, so both images written here are sRGB-encoded as multiray encodes. `image` is
  the mapper's own ray-cast image read from its buffer (what the image comparison uses);
  `image_display` is the window as OpenGL drew that image (a textured quad whose filtering
  blurs it by about a pixel, so it is not the rays' result).
"""
import argparse
import ctypes
import json
import os
import re
import statistics
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support

# multiray's `angio` preset (src/volume/transfer_presets.cpp): (fraction of [min, max],
# (r, g, b), opacity per reference step).
ANGIO = [
    (0.0, (0.0, 0.0, 0.0), 0.0),
    (0.1, (0.5, 0.05, 0.05), 0.0),
    (0.3, (0.85, 0.25, 0.15), 0.3),
    (0.6, (1.0, 0.75, 0.5), 0.7),
    (1.0, (1.0, 1.0, 1.0), 0.9),
]
NRRD_TYPES = {"uint8": np.uint8, "uchar": np.uint8, "unsigned char": np.uint8,
              "int8": np.int8, "signed char": np.int8, "uint16": np.uint16,
              "ushort": np.uint16, "unsigned short": np.uint16, "int16": np.int16,
              "short": np.int16}


def fail(message):
    print(f"vtk_volume.py: {message}", file=sys.stderr)
    sys.exit(2)


def load_nhdr(path):
    """A detached NRRD header with raw encoding (what the data folder holds)."""
    fields = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            if ":" in line and not line.startswith("#"):
                key, value = line.split(":", 1)
                fields[key.strip()] = value.strip()
    if fields.get("encoding", "raw") != "raw":
        fail(f"{path}: only raw encoding is read here")
    if fields.get("type") not in NRRD_TYPES:
        fail(f"{path}: voxel type {fields.get('type')!r} is not read here")
    dims = [int(s) for s in fields["sizes"].split()]
    spacing = [float(s) for s in fields.get("spacings", "1 1 1").split()]
    dtype = np.dtype(NRRD_TYPES[fields["type"]])
    if dtype.itemsize > 1:
        dtype = dtype.newbyteorder("<" if fields.get("endian", "little") == "little" else ">")
    raw = os.path.join(os.path.dirname(path), fields["data file"])
    values = np.fromfile(raw, dtype=dtype, count=dims[0] * dims[1] * dims[2])
    if values.size != dims[0] * dims[1] * dims[2]:
        fail(f"{raw}: shorter than {dims}")
    return dims, spacing, values.astype(dtype.newbyteorder("="))


def image_data(dims, spacing, values):
    img = vtk.vtkImageData()
    img.SetDimensions(*dims)
    img.SetSpacing(*spacing)
    # multiray: the grid's box [-n*s/2, n*s/2] is centred on the origin and voxel centres
    # sit half a voxel inside it; VTK's points are the voxel centres.
    img.SetOrigin(*[(0.5 - n / 2) * s for n, s in zip(dims, spacing)])
    arr = numpy_support.numpy_to_vtk(values, deep=True)  # x fastest, as the file
    arr.SetName("scalars")
    img.GetPointData().SetScalars(arr)
    return img


def volume_property(lo, hi, reference_step_world):
    colour = vtk.vtkColorTransferFunction()
    colour.SetColorSpaceToRGB()
    opacity = vtk.vtkPiecewiseFunction()
    for frac, rgb, alpha in ANGIO:
        value = lo + frac * (hi - lo)
        colour.AddRGBPoint(value, *rgb)
        opacity.AddPoint(value, alpha)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(reference_step_world)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOn()
    prop.SetAmbient(0.3)
    prop.SetDiffuse(0.7)
    prop.SetSpecular(0.0)
    return prop


def srgb8(rgb8):
    """multiray's PNG encoding (src/core/image.cpp) applied to VTK's 8-bit colours."""
    v = rgb8.astype(np.float64) / 255.0
    s = np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1 / 2.4) - 0.055)
    return np.clip(np.rint(s * 255.0), 0, 255).astype(np.uint8)


def write_png(path, rgb):
    h, w, _ = rgb.shape
    img = vtk.vtkImageData()
    img.SetDimensions(w, h, 1)
    # VTK images are bottom-up; PNG rows top-down.
    arr = numpy_support.numpy_to_vtk(np.ascontiguousarray(rgb[::-1]).reshape(-1, 3), deep=True)
    img.GetPointData().SetScalars(arr)
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputData(img)
    writer.Write()


def raycast_image(mapper, w, h):
    """The mapper's own ray-cast image, before OpenGL draws it: 15-bit fixed-point RGBA with
    premultiplied colours, as 8-bit colours over black, rows top-down; None where the
    wrapper's pointer cannot be read."""
    image = mapper.GetRayCastImage()
    pointer = image.GetImage()  # the wrapper gives a void pointer as "_<hex>_p_void"
    match = re.fullmatch(r"_([0-9a-fA-F]+)_p_void", pointer if isinstance(pointer, str) else "")
    if not match or image.GetImageSampleDistance() != 1.0:
        return None
    mw, mh = image.GetImageMemorySize()
    uw, uh = image.GetImageInUseSize()
    ox, oy = image.GetImageOrigin()
    if not (0 <= ox and ox + uw <= w and 0 <= oy and oy + uh <= h and uw <= mw and uh <= mh):
        return None
    buf = (ctypes.c_ushort * (mw * mh * 4)).from_address(int(match.group(1), 16))
    rgba = np.ctypeslib.as_array(buf).reshape(mh, mw, 4)
    out = np.zeros((h, w, 3), np.uint8)  # bottom-up, as the viewport
    rgb = rgba[:uh, :uw, :3].astype(np.float64) / 32767.0
    out[oy:oy + uh, ox:ox + uw] = np.clip(np.rint(rgb * 255.0), 0, 255)
    return out[::-1].copy()


def framebuffer(window):
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.Update()
    out = grab.GetOutput()
    w, h, _ = out.GetDimensions()
    rgb = numpy_support.vtk_to_numpy(out.GetPointData().GetScalars()).reshape(h, w, 3)
    return rgb[::-1].copy()  # top-down


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("volume")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--warmup", type=int, default=2)
    ap.add_argument("--res", default="256x192")
    ap.add_argument("--step", type=float, default=0.5, help="voxel lengths")
    ap.add_argument("--reference-step", type=float, default=1.0, help="voxel lengths")
    ap.add_argument("--camera", required=True, help="ex,ey,ez,tx,ty,tz,ux,uy,uz,fov")
    ap.add_argument("--out", default="vtk.png")
    a = ap.parse_args()
    if a.threads < 1 or a.frames < 1 or a.warmup < 0:
        fail("--threads and --frames must be >= 1, --warmup >= 0")
    try:
        w, h = (int(s) for s in a.res.split("x"))
        cam = [float(s) for s in a.camera.split(",")]
    except ValueError:
        fail("--res is WIDTHxHEIGHT and --camera ten numbers")
    if len(cam) != 10:
        fail("--camera takes ten numbers: ex,ey,ez,tx,ty,tz,ux,uy,uz,fov")
    if not os.path.isfile(a.volume):
        fail(f"no volume at {a.volume}")

    dims, spacing, values = load_nhdr(a.volume)
    voxel_length = min(spacing)
    lo, hi = float(values.min()), float(values.max())

    vtk.vtkMultiThreader.SetGlobalMaximumNumberOfThreads(a.threads)
    mapper = vtk.vtkFixedPointVolumeRayCastMapper()
    mapper.SetInputData(image_data(dims, spacing, values))
    mapper.SetNumberOfThreads(a.threads)
    mapper.SetBlendModeToComposite()
    mapper.AutoAdjustSampleDistancesOff()  # no coarser steps while "interactive"
    mapper.LockSampleDistanceToInputSpacingOff()
    mapper.SetSampleDistance(a.step * voxel_length)  # world units
    mapper.SetInteractiveSampleDistance(a.step * voxel_length)
    mapper.SetImageSampleDistance(1.0)  # one ray per pixel
    mapper.SetMinimumImageSampleDistance(1.0)
    mapper.SetMaximumImageSampleDistance(1.0)
    mapper.IntermixIntersectingGeometryOff()

    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(volume_property(lo, hi, a.reference_step * voxel_length))

    ren = vtk.vtkRenderer()
    ren.SetBackground(0, 0, 0)
    ren.AddVolume(volume)
    ren.TwoSidedLightingOn()  # |cos|, as multiray's shading
    # The shading tables scale the ambient term by the light's ambient colour, which is
    # black for a default vtkLight (the renderer's automatic one too): a headlight of our
    # own with a white ambient colour gives multiray's 0.3 ambient.
    light = vtk.vtkLight()
    light.SetLightTypeToHeadlight()
    light.SetAmbientColor(1, 1, 1)
    light.SetDiffuseColor(1, 1, 1)
    light.SetSpecularColor(1, 1, 1)
    light.SetIntensity(1.0)
    ren.AddLight(light)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(w, h)
    window.SetMultiSamples(0)
    window.AddRenderer(ren)
    camera = ren.GetActiveCamera()
    camera.SetPosition(*cam[0:3])
    camera.SetFocalPoint(*cam[3:6])
    camera.SetViewUp(*cam[6:9])
    camera.SetViewAngle(cam[9])  # vertical, as multiray's fov
    ren.ResetCameraClippingRange()

    times = []
    for i in range(a.warmup + a.frames):
        t = time.perf_counter()
        window.Render()
        ms = (time.perf_counter() - t) * 1e3
        if i >= a.warmup:
            times.append(ms)
    if ren.GetLights().GetNumberOfItems() != 1:
        fail("expected our headlight as the renderer's only light")

    shown = framebuffer(window)
    cast = raycast_image(mapper, w, h)
    if cast is None:
        print("vtk_volume.py: cannot read the mapper's own image; `image` is the displayed "
              "one", file=sys.stderr)
        cast = shown
    base, ext = os.path.splitext(a.out)
    shown_path = base + "_display" + (ext or ".png")
    write_png(a.out, srgb8(cast))
    write_png(shown_path, srgb8(shown))
    print(json.dumps({"threads": a.threads, "frames": a.frames,
                      "median_ms": statistics.median(times), "frame_ms": times,
                      "image": a.out, "image_display": shown_path}))


if __name__ == "__main__":
    main()
