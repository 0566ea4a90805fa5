#!/usr/bin/env python3
"""Writes the augmented-reality example's inputs (docs/ar.md), committed beside this script:
the 'real' ground (ground.obj), the virtual objects (objects.obj), both together for the
reference (ground_and_objects.obj), their materials (ar.mtl) and the capture's camera poses
(poses.json: a slow arc around the objects, 8 frames, 320x240 images)."""
import json, math, os

HERE = os.path.dirname(os.path.abspath(__file__))


def sphere(cx, cy, cz, r, rings=12, segments=24):
    verts, faces = [], []
    for i in range(rings + 1):
        th = math.pi * i / rings
        for j in range(segments):
            ph = 2 * math.pi * j / segments
            verts.append((cx + r * math.sin(th) * math.cos(ph), cy + r * math.cos(th),
                          cz + r * math.sin(th) * math.sin(ph)))
    for i in range(rings):
        for j in range(segments):
            a, b = i * segments + j, i * segments + (j + 1) % segments
            c, d = a + segments, b + segments
            if i > 0: faces.append((a, b, c))
            if i < rings - 1: faces.append((b, d, c))
    return verts, faces


def box(cx, cz, half, height):
    x0, x1, z0, z1 = cx - half, cx + half, cz - half, cz + half
    verts = [(x, y, z) for y in (0.0, height) for z in (z0, z1) for x in (x0, x1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return verts, [f for q in quads for f in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]


def ground():
    e = 20.0
    return [(-e, 0, -e), (-e, 0, e), (e, 0, e), (e, 0, -e)], [(0, 1, 2), (0, 2, 3)]


def write_obj(name, parts):
    lines = ["# made by make_example.py", "mtllib ar.mtl"]
    base = 1
    for material, (verts, faces) in parts:
        lines.append("usemtl " + material)
        lines += ["v %.6f %.6f %.6f" % v for v in verts]
        lines += ["f %d %d %d" % tuple(base + i for i in f) for f in faces]
        base += len(verts)
    with open(os.path.join(HERE, name), "w") as f:
        f.write("\n".join(lines) + "\n")


def camera_to_world(eye, target):
    z = [e - t for e, t in zip(eye, target)]
    n = math.sqrt(sum(c * c for c in z)); z = [c / n for c in z]
    up = (0.0, 1.0, 0.0)
    x = [up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]]
    n = math.sqrt(sum(c * c for c in x)); x = [c / n for c in x]
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    return x + [0] + y + [0] + z + [0] + list(eye) + [1]


objects = [("red", sphere(0.0, 0.6, 0.0, 0.6)), ("blue", box(1.2, -0.6, 0.35, 0.7))]
write_obj("ground.obj", [("ground", ground())])
write_obj("objects.obj", objects)
write_obj("ground_and_objects.obj", [("ground", ground())] + objects)
with open(os.path.join(HERE, "ar.mtl"), "w") as f:
    f.write("# made by make_example.py\nnewmtl ground\nKd 0.5 0.5 0.5\n"
            "newmtl red\nKd 0.7 0.15 0.1\nnewmtl blue\nKd 0.1 0.25 0.7\n")
width, height, fov = 320, 240, 40.0
f = 0.5 * height / math.tan(math.radians(fov) / 2)
poses = []
for i in range(8):
    a = math.radians(-30 + 8 * i)
    eye = (4.5 * math.sin(a), 2.2, 4.5 * math.cos(a))
    poses.append({"transform": [round(v, 6) for v in camera_to_world(eye, (0.3, 0.4, 0.0))]})
with open(os.path.join(HERE, "poses.json"), "w") as out:
    json.dump({"image": [width, height], "intrinsics": [round(f, 4), round(f, 4), width / 2, height / 2],
               "poses": poses}, out, indent=1)
    out.write("\n")
