# Blender Cycles (CPU) rendering an OBJ scene as multiray does by default, for the
# equal-noise comparison of bench/cycles_noise.sh (docs/benchmarks.md, "Equal noise against
# Cycles"). Run by Blender, not by python3:
#   blender -b --factory-startup --python bench/cycles_sponza.py -- SETTINGS.json
# SETTINGS.json (written by cycles_noise.sh from multiray's own stats.json, so both render
# the same camera, sky and sun):
#   {"scene": OBJ, "width": W, "height": H, "threads": N, "bounces": B,
#    "camera": {"eye": [...], "target": [...], "up": [...], "fov_y_deg": F},
#    "sky": [r, g, b], "sun": {"direction": [...], "irradiance": E, "half_angle_rad": A},
#    "renders": [{"spp": S, "seed": K, "out": "FILE.exr"}, ...],
#    "times": "TIMES.json"}
# Each render's wall time (the render only: the scene is imported and its BVH built by a
# 1-sample warm-up render first, and kept with persistent data) goes to TIMES.json.
#
# The work is rebuilt to match multiray's: the OBJ's coordinates unchanged (no axis
# conversion; the camera and sun are placed in the file's own frame), every material a
# Lambertian diffuse of Kd times the sRGB-decoded map_Kd texture (multiray ignores Ks, Ns
# and bump maps: render/surface.cpp, scene/load_obj.cpp), bilinear texture lookups, a box
# pixel filter one pixel wide (multiray jitters uniformly inside the pixel), no clamping,
# no denoising, no adaptive sampling, all bounce limits at B, light threshold 0, a
# constant world colour and a sun lamp of the same irradiance and angular size, linear
# 32-bit EXR output with the Standard view transform.
import json
import math
import os
import sys
import time

import bpy
from mathutils import Matrix, Vector


def fail(msg):
    print("cycles_sponza: " + msg, file=sys.stderr)
    sys.exit(2)


def read_mtl(obj_path):
    """{material name: (Kd, texture path or None)} from the OBJ's mtllib files."""
    folder = os.path.dirname(obj_path)
    by_lower = {f.lower(): f for f in os.listdir(folder)}
    mats, name = {}, None
    with open(obj_path, errors="replace") as f:
        libs = [ln.split(None, 1)[1].strip() for ln in f if ln.startswith("mtllib")]
    for lib in libs:
        with open(os.path.join(folder, lib), errors="replace") as f:
            for ln in f:
                parts = ln.split()
                if not parts:
                    continue
                if parts[0] == "newmtl":
                    name = parts[1]
                    mats[name] = [(0.8, 0.8, 0.8), None]
                elif parts[0] == "Kd" and name:
                    mats[name][0] = tuple(float(v) for v in parts[1:4])
                elif parts[0] == "map_Kd" and name:
                    found = by_lower.get(parts[-1].lower())
                    mats[name][1] = os.path.join(folder, found) if found else None
    return mats


def obj_bounds(obj_path):
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    with open(obj_path, errors="replace") as f:
        for ln in f:
            if ln.startswith("v "):
                p = [float(v) for v in ln.split()[1:4]]
                lo = [min(a, b) for a, b in zip(lo, p)]
                hi = [max(a, b) for a, b in zip(hi, p)]
    return lo, hi


def import_scene(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Blender's own frame is forward +Y, up +Z: asking for it leaves the coordinates as
    # they are in the file (checked against the file's bounds below).
    bpy.ops.wm.obj_import(filepath=path, forward_axis="Y", up_axis="Z")
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    if not meshes:
        fail(path + ": no meshes imported")
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for o in meshes:
        for c in o.bound_box:
            p = o.matrix_world @ Vector(c)
            lo = [min(a, b) for a, b in zip(lo, p)]
            hi = [max(a, b) for a, b in zip(hi, p)]
    want_lo, want_hi = obj_bounds(path)
    if max(abs(a - b) for a, b in zip(lo + hi, want_lo + want_hi)) > 1e-3:
        fail("the import moved the scene: bounds %s %s, the file's %s %s"
             % (lo, hi, want_lo, want_hi))
    return meshes


def lambertian(mat, kd, texture):
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Roughness"].default_value = 0.0  # Lambert, not Oren-Nayar
    links.new(diffuse.outputs["BSDF"], out.inputs["Surface"])
    colour = (kd[0], kd[1], kd[2], 1.0)
    if texture is None:
        diffuse.inputs["Color"].default_value = colour
        return
    image = nodes.new("ShaderNodeTexImage")
    image.image = bpy.data.images.load(texture, check_existing=True)
    image.image.colorspace_settings.name = "sRGB"
    image.interpolation = "Linear"
    image.extension = "REPEAT"
    multiply = nodes.new("ShaderNodeMixRGB")
    multiply.blend_type = "MULTIPLY"
    multiply.inputs["Fac"].default_value = 1.0
    links.new(image.outputs["Color"], multiply.inputs["Color1"])
    multiply.inputs["Color2"].default_value = colour
    links.new(multiply.outputs["Color"], diffuse.inputs["Color"])


def rebuild_materials(meshes, mtl):
    for o in meshes:
        for slot in o.material_slots:
            if slot.material is None:
                continue
            kd, tex = mtl.get(slot.material.name.split(".")[0], ((0.8, 0.8, 0.8), None))
            lambertian(slot.material, kd, tex)


def look_at(eye, target, up):
    """Camera-to-world: Blender cameras look down -Z with +Y up."""
    f = (target - eye).normalized()
    r = f.cross(up).normalized()
    u = r.cross(f)
    m = Matrix.Identity(4)
    for i in range(3):
        m[i][0], m[i][1], m[i][2], m[i][3] = r[i], u[i], -f[i], eye[i]
    return m


def setup(cfg):
    scene = bpy.context.scene
    cam_cfg = cfg["camera"]
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    cam.matrix_world = look_at(Vector(cam_cfg["eye"]), Vector(cam_cfg["target"]),
                               Vector(cam_cfg["up"]))
    cam.data.sensor_fit = "VERTICAL"
    cam.data.angle_y = math.radians(cam_cfg["fov_y_deg"])
    cam.data.clip_start = 1e-4
    cam.data.clip_end = 1e6
    scene.camera = cam

    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = tuple(cfg["sky"]) + (1.0,)
    bg.inputs["Strength"].default_value = 1.0
    scene.world = world

    sun_cfg = cfg["sun"]
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    scene.collection.objects.link(sun)
    d = Vector(sun_cfg["direction"]).normalized()  # from the scene towards the sun
    sun.matrix_world = d.to_track_quat("Z", "Y").to_matrix().to_4x4()  # the lamp shines down -Z
    sun.data.energy = sun_cfg["irradiance"]  # W/m^2, as multiray's --sun
    sun.data.angle = 2.0 * sun_cfg["half_angle_rad"]
    sun.data.cycles.max_bounces = 1024

    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y, r.resolution_percentage = cfg["width"], cfg["height"], 100
    r.threads_mode = "FIXED"
    r.threads = cfg["threads"]
    r.use_persistent_data = True
    r.filter_size = 1.0
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    r.image_settings.color_mode = "RGB"
    r.image_settings.exr_codec = "ZIP"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    c = scene.cycles
    c.device = "CPU"
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    b = cfg["bounces"]
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = b
    c.transmission_bounces = c.transparent_max_bounces = b
    c.volume_bounces = 0
    c.caustics_reflective = c.caustics_refractive = True
    c.use_auto_tile = False
    print("cycles_sponza: sampling pattern %s, min light bounces %d"
          % (c.sampling_pattern, c.min_light_bounces))


def render(spp, seed, out):
    scene = bpy.context.scene
    scene.cycles.samples = spp
    scene.cycles.seed = seed
    scene.render.filepath = out
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=bool(out))
    return time.perf_counter() - t0


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 1:
        fail("usage: blender -b --factory-startup --python cycles_sponza.py -- SETTINGS.json")
    with open(argv[0]) as f:
        cfg = json.load(f)
    meshes = import_scene(cfg["scene"])
    rebuild_materials(meshes, read_mtl(cfg["scene"]))
    setup(cfg)
    render(1, 0, "")  # warm-up: scene sync and BVH, kept by persistent data
    times = []
    for job in cfg["renders"]:
        t = render(job["spp"], job["seed"], job["out"])
        if not os.path.isfile(job["out"]):
            fail("no image written at " + job["out"])
        times.append({"spp": job["spp"], "seed": job["seed"], "seconds": t})
        print("cycles_sponza: %d spp seed %d: %.3f s" % (job["spp"], job["seed"], t))
    with open(cfg["times"], "w") as f:
        json.dump(times, f, indent=1)


main()
