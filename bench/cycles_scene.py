"""Render a frame exported by `wobble study render` (OUT/frame: scene.obj, scene.json, textures) with Blender Cycles.

    blender -b --factory-startup [--python-exit-code 1] --python bench/cycles_scene.py -- FRAME_DIR OUT.exr SPP
        [--seed N] [--threads N] [--bounces N] [--sky-bounces wobble|cycles] [--blend FILE.blend]

Writes OUT.exr (linear scene-referred RGB, 32-bit float, no view transform) and prints
  render_seconds=        Cycles' path tracing: from its first sample to "Finished", read from Blender's own progress
                         lines (10 ms resolution). This leaves out the scene synchronisation (mesh upload, BVH build,
                         texture loading, the world's importance map), as `wobble study render` times render() on
                         an already built Embree scene; it is the figure the comparison uses.
  sync_seconds=          the synchronisation before the first sample
  total_render_seconds=  the whole bpy.ops.render.render() call (perf_counter), Python scene building excluded

How wobble's model (render/material.h, bsdf.h, lights.h, integrator.h) is matched; see bench/cycles_compare.sh for
the known mismatches:
  - Axes: wobble is Y up; everything is converted to Blender's Z up with the OBJ importer's own default mapping
    (forward -Z, up Y): (x, y, z) -> (x, -z, y), a rotation. The script checks that the imported vertices land there.
  - Camera: position / look_at / up, vertical field of view (sensor fit vertical), the exported resolution.
  - Materials, the sun, the sky (or the environment map), wobble's light paths (with --sky-bounces wobble, the
    default, the world lights no path's last vertex, as wobble's sky) and the integrator's settings:
    app/blender/cycles_nodes.py, which `wobble blend` uses too, so the comparison measures the .blend's model.
    Cycles' "Sampling Method" Automatic importance-samples the world as wobble does.
"""
import argparse
import json
import math
import os
import sys
import time

import bpy
from mathutils import Matrix

# The materials, sky, sun and light paths, shared with `wobble blend` (app/blender/cycles_nodes.py).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "app", "blender"))
import cycles_nodes  # noqa: E402


def fail(message, code=2):
    print("cycles_scene.py: " + message, file=sys.stderr)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)  # sys.exit inside Blender's --python leaves Blender running its own exit path; be definite


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="cycles_scene.py")
    p.add_argument("frame_dir")
    p.add_argument("out_exr")
    p.add_argument("spp", type=int)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--threads", type=int, default=0, help="0: all cores (Blender's default)")
    p.add_argument("--bounces", type=int, default=2, help="wobble's render.bounces (default 2)")
    p.add_argument("--sky-bounces", choices=("wobble", "cycles"), default="wobble",
                   help="wobble: no sky light at the last vertex, as wobble; cycles: Cycles' own (sky at every vertex)")
    p.add_argument("--blend", help="also save the built scene as this .blend file (for inspection)")
    try:
        a = p.parse_args(argv)
    except SystemExit as e:
        os._exit(2 if e.code else 0)
    if a.spp < 1:
        fail("SPP %d: must be at least 1" % a.spp)
    if a.bounces < 0:
        fail("--bounces %d: must be >= 0" % a.bounces)
    return a


to_blender = cycles_nodes.to_blender  # wobble (Y up) -> Blender (Z up), as the OBJ importer


def reset_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    return scene


def load_json(frame_dir):
    path = os.path.join(frame_dir, "scene.json")
    try:
        with open(path) as f:
            return json.load(f)
    except OSError as e:
        fail("%s: cannot read (%s)" % (path, e.strerror))
    except ValueError as e:
        fail("%s: not valid JSON (%s)" % (path, e))


# ---------------------------------------------------------------------------------------------- materials


def make_material(m, frame_dir):
    def load_image(texture):  # baked sRGB over UV [0, 1]^2, repeated like wobble's UVs
        path = os.path.join(frame_dir, texture)
        try:
            return bpy.data.images.load(path, check_existing=True)
        except RuntimeError:
            fail("%s: cannot load the texture image" % path)

    return cycles_nodes.material(m, load_image)


# ---------------------------------------------------------------------------------------------- scene


def import_obj(frame_dir):
    path = os.path.join(frame_dir, "scene.obj")
    if not os.path.isfile(path):
        fail("%s: no such file" % path)
    before = set(bpy.data.objects)
    # The importer's default axes (forward -Z, up Y) map wobble's Y-up (x, y, z) to Blender's (x, -z, y).
    bpy.ops.wm.obj_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
    objects = {o.name: o for o in bpy.data.objects if o not in before}
    # Check the mapping on the first vertex of the file.
    first = None
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                first = [float(x) for x in line.split()[1:4]]
                break
    if first is not None and objects:
        want = to_blender(first)
        best = min(((o.matrix_world @ v.co - want).length for o in objects.values() if o.type == "MESH"
                    for v in o.data.vertices[:1]), default=0.0)
        if best > 1e-3 * (1.0 + want.length):
            fail("the OBJ importer's axis mapping is not (x, -z, y): first vertex off by %g" % best)
    return objects


def add_sphere(name, center, radius):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=128, ring_count=64, radius=radius, location=to_blender(center))
    obj = bpy.context.active_object
    obj.name = name
    bpy.ops.object.shade_smooth()
    return obj


def setup_camera(scene, cam):
    data = bpy.data.cameras.new("camera")
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(cam["vfov_deg"])
    data.clip_start = 1e-3
    data.clip_end = 1e6
    obj = bpy.data.objects.new("camera", data)
    scene.collection.objects.link(obj)
    pos, target, up = to_blender(cam["position"]), to_blender(cam["look_at"]), to_blender(cam["up"])
    forward = (target - pos).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    # Blender cameras look along local -Z with local +Y up.
    rot = Matrix((right, true_up, -forward)).transposed()
    obj.matrix_world = Matrix.Translation(pos) @ rot.to_4x4()
    scene.camera = obj
    scene.render.resolution_x = int(cam["width"])
    scene.render.resolution_y = int(cam["height"])
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0


def add_area_light(scene, i, light):
    """A one-sided emitting rectangle, invisible to camera and shadow rays (wobble's RectLight is no geometry)."""
    corner, eu, ev = (to_blender(light[k]) for k in ("corner", "edge_u", "edge_v"))
    mesh = bpy.data.meshes.new("area_%d" % i)
    mesh.from_pydata([corner, corner + eu, corner + eu + ev, corner + ev], [], [(0, 1, 2, 3)])
    obj = bpy.data.objects.new("area_%d" % i, mesh)
    scene.collection.objects.link(obj)
    mat = bpy.data.materials.new("area_%d" % i)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    em = nodes.new("ShaderNodeEmission")
    rad = [float(c) for c in light["radiance"]]
    em.inputs["Color"].default_value = rad + [1.0]
    em.inputs["Strength"].default_value = 1.0
    geo = nodes.new("ShaderNodeNewGeometry")
    mix = nodes.new("ShaderNodeMixShader")  # back face: black (wobble's rectangle emits on one side)
    links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
    links.new(em.outputs["Emission"], mix.inputs[1])
    links.new(mix.outputs["Shader"], out.inputs["Surface"])
    obj.data.materials.append(mat)
    obj.visible_camera = False
    obj.visible_shadow = False
    print("cycles_scene.py: warning: area light %d as an emitting mesh: BSDF rays stop at it (wobble's pass through)"
          % i, file=sys.stderr)


def setup_render(scene, a):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = a.spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.use_preview_denoising = False
    c.seed = a.seed
    c.use_animated_seed = False
    cycles_nodes.light_paths(scene, a.bounces, a.dielectric)
    c.use_auto_tile = False
    scene.render.film_transparent = False
    scene.render.threads_mode = "FIXED" if a.threads > 0 else "AUTO"
    if a.threads > 0:
        scene.render.threads = a.threads
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.use_compositing = False
    scene.render.use_sequencer = False
    s = scene.render.image_settings
    s.file_format = "OPEN_EXR"
    s.color_mode = "RGB"
    s.color_depth = "32"
    s.exr_codec = "ZIP"


def render_logged():
    """bpy.ops.render.render() with Blender's C-level stdout (its progress lines) captured into a file."""
    import ctypes
    import tempfile
    libc = ctypes.CDLL(None)
    sys.stdout.flush()
    libc.fflush(None)
    saved = os.dup(1)
    with tempfile.TemporaryFile(mode="w+b") as f:
        os.dup2(f.fileno(), 1)
        try:
            t0 = time.perf_counter()
            bpy.ops.render.render(write_still=False)
            total = time.perf_counter() - t0
        finally:
            sys.stdout.flush()
            libc.fflush(None)
            os.dup2(saved, 1)
            os.close(saved)
        f.seek(0)
        log = f.read().decode("utf-8", "replace")
    return total, log


def parse_clock(text):
    """Blender's 'MM:SS.ss' or 'HH:MM:SS.ss' -> seconds."""
    seconds = 0.0
    for part in text.split(":"):
        seconds = seconds * 60.0 + float(part)
    return seconds


def parse_render_log(log):
    """Cycles' path-tracing time from Blender's progress lines ('Fra:1 ... | Time:00:00.86 | ... | Sample 0/16',
    then '... | Finished'): from the first sample to the end, without the scene synchronisation before it (BVH
    build, image loading, the world's importance map), as wobble's study times render() on a built scene.
    Returns (render_seconds, sync_seconds) with Blender's 10 ms resolution, or (None, None)."""
    import re
    start = end = None
    for line in log.splitlines():
        m = re.search(r"\| Time:([0-9:.]+) \|", line)
        if not m:
            continue
        t = parse_clock(m.group(1))
        if start is None and re.search(r"\| Sample 0/\d+", line):
            start = t
        if line.rstrip().endswith("| Finished"):
            end = t
    if start is None or end is None:
        return None, None
    return end - start, start


def main():
    a = parse_args()
    frame_dir = os.path.abspath(a.frame_dir)
    j = load_json(frame_dir)
    a.dielectric = any(m.get("dielectric") for m in j["materials"])
    scene = reset_scene()
    setup_render(scene, a)
    try:
        setup_camera(scene, j["camera"])
        materials = [make_material(m, frame_dir) for m in j["materials"]]
        objects = import_obj(frame_dir)
        for shape in j["shapes"]:
            mat = materials[shape["material"]]
            if "sphere" in shape:
                obj = add_sphere(shape["name"], shape["sphere"]["center"], shape["sphere"]["radius"])
            else:
                obj = objects.get(shape["obj_object"])
                if obj is None:
                    fail("%s: no object %r in scene.obj" % (frame_dir, shape["obj_object"]))
            obj.data.materials.clear()
            obj.data.materials.append(mat)
            for poly in obj.data.polygons:
                poly.material_index = 0
        for i, sun in enumerate(j["suns"]):
            cycles_nodes.sun(scene, "sun_%d" % i, sun)
        for i, light in enumerate(j.get("area_lights", [])):
            add_area_light(scene, i, light)
        cycles_nodes.world(scene, j["sky"], j.get("environment"), a.bounces if a.sky_bounces == "wobble" else None)
    except (KeyError, IndexError, TypeError, ValueError) as e:
        fail("%s/scene.json: unexpected content (%s: %s)" % (frame_dir, type(e).__name__, e))
    if a.blend:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(a.blend))

    bpy.context.view_layer.update()
    total, log = render_logged()
    render_seconds, sync_seconds = parse_render_log(log)
    if render_seconds is None:
        print(log, file=sys.stderr)
        fail("could not find Cycles' progress lines (Sample 0/N ... Finished) in Blender's output", code=1)

    out = os.path.abspath(a.out_exr)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    tmp = out + ".tmp.exr"
    bpy.data.images["Render Result"].save_render(filepath=tmp, scene=scene)
    os.replace(tmp, out)
    print("render_seconds=%.3f" % render_seconds)
    print("sync_seconds=%.3f" % sync_seconds)
    print("total_render_seconds=%.6f" % total)
    print("threads=%d" % scene.render.threads)
    sys.stdout.flush()


if __name__ == "__main__":
    try:
        main()
    except SystemExit:
        raise
    except Exception as e:  # a Blender API difference or unexpected input: say so and exit non-zero
        import traceback
        traceback.print_exc()
        fail("failed: %s: %s" % (type(e).__name__, e), code=1)
    sys.stdout.flush()
    os._exit(0)
