"""Builds a wobble run's Blender scene: `wobble blend OUT` runs it (the binary carries this file) as

    blender -b --factory-startup --python-exit-code 1 --python make_blend.py -- MANIFEST.json OUT.blend

MANIFEST.json (written by app/commands/blend_command.cpp; wobble's Y-up coordinates, metres; file paths relative to
the run's folder, where the .blend is saved) lists the frame range and rate, wobble's render materials (colour,
coat, texture, gelatine), the bodies (base OBJ, PC2 point cache, material), the colliders as wobble draws them (a
sphere, or triangles with UVs around the drawn centre; a centre per frame for a moving one), the camera (one view,
or one per frame for a follow camera; the lens and shutter), the suns and the sky, or the environment map that
replaces them, the bounces, the clamp of indirect light, whether wobble carries shadow caustics (then the gelatine
bodies cast them in Cycles, the other surfaces receive them and the suns light them) and the exposure. Each body
becomes one object: its base OBJ, imported with Blender's default OBJ axes (forward -Z, up Y, which map wobble's
(x, y, z) to Blender's (x, -z, y) by the object's rotation), smooth shaded from its moving vertices, with a Mesh
Cache modifier playing its PC2 (whose points are the OBJ's vertices in order). Moving colliders and the follow
camera are baked as keyframes, one per frame, linear. The materials, world, sun, light paths and tone curve come
from cycles_nodes.py (written beside this script by `wobble blend`; bench/cycles_scene.py uses it too), so Cycles
renders the picture wobble renders. Paths in the .blend are relative to it, so the run's folder can be moved as a
whole; with "pack", the images are packed into it.
"""
import json
import math
import os
import struct
import sys

import bpy
from mathutils import Matrix

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_nodes  # noqa: E402  (found beside this script)


def fail(message):
    print("make_blend.py: " + message, file=sys.stderr)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(1)


to_blender = cycles_nodes.to_blender  # wobble (Y up) -> Blender (Z up), as the OBJ importer maps it


def pc2_points(path):
    with open(path, "rb") as f:
        header = f.read(32)
    if len(header) < 32 or header[:12] != b"POINTCACHE2\0":
        fail("%s: not a PC2 point cache" % path)
    return struct.unpack("<i", header[16:20])[0]


def add_body(b, material, out_dir, first_frame):
    before = set(bpy.data.objects)
    bpy.ops.wm.obj_import(filepath=os.path.join(out_dir, b["obj"]), forward_axis="NEGATIVE_Z", up_axis="Y")
    new = [o for o in bpy.data.objects if o not in before]
    if len(new) != 1:
        fail("%s: expected one object, imported %d" % (b["obj"], len(new)))
    obj = new[0]
    obj.name = obj.data.name = b["name"]
    points = pc2_points(os.path.join(out_dir, b["pc2"]))
    if points != len(obj.data.vertices):
        fail("%s has %d points but %s has %d vertices" % (b["pc2"], points, b["obj"], len(obj.data.vertices)))
    imported = list(obj.data.materials)
    obj.data.materials.clear()
    for m in imported:
        bpy.data.materials.remove(m)
    obj.data.materials.append(material)
    # Normals from the moving vertices (as wobble's surface), not the base OBJ's custom normals frozen at rest.
    obj.data.use_auto_smooth = False
    for poly in obj.data.polygons:
        poly.use_smooth = True
    cache = obj.modifiers.new("wobble point cache", "MESH_CACHE")
    cache.cache_format = "PC2"
    cache.filepath = "//" + b["pc2"]
    cache.time_mode = "FRAME"
    cache.play_mode = "SCENE"
    cache.frame_start = first_frame  # Blender frame first_frame plays the cache's first sample
    return obj


def link(name, data):
    obj = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def sphere_uvs(mesh):
    """wobble's sphere UVs (render/scene.cpp): for the direction d from the centre, in wobble's axes, u = 1/2 +
    atan2(d.x, d.z) / 2 pi, v = 1/2 + asin(d.y) / pi. Per face corner; a face across the seam takes its corners' u
    past 1 (the texture repeats), and a pole takes the u of its face's centre."""
    uv = mesh.uv_layers.active or mesh.uv_layers.new()
    for poly in mesh.polygons:
        corners = []
        for li in poly.loop_indices:
            b = mesh.vertices[mesh.loops[li].vertex_index].co.normalized()
            x, y, z = b.x, b.z, -b.y  # Blender (x, y, z) is wobble's (x, -z, y)
            pole = math.hypot(x, z) < 1e-6
            corners.append((li, None if pole else 0.5 + math.atan2(x, z) / (2 * math.pi),
                            0.5 + math.asin(max(-1.0, min(1.0, y))) / math.pi))
        us = [u for _, u, _ in corners if u is not None]
        if max(us) - min(us) > 0.5:
            us = [u + 1.0 if u < 0.5 else u for u in us]
            corners = [(li, None if u is None else (u + 1.0 if u < 0.5 else u), v) for li, u, v in corners]
        middle = sum(us) / len(us)
        for li, u, v in corners:
            uv.data[li].uv = (middle if u is None else u, v)


def add_collider(c):
    """A sphere, or wobble's own triangles with their UVs (flat shaded, as wobble draws colliders) taken to [0, 1]
    over uv_rect, the rectangle its texture is baked over; around the drawn centre, the object at its first centre."""
    if c["type"] == "sphere":
        bpy.ops.mesh.primitive_uv_sphere_add(segments=128, ring_count=64, radius=c["radius"])
        obj = bpy.context.active_object
        bpy.ops.object.shade_smooth()
        obj.name = obj.data.name = c["name"]
        sphere_uvs(obj.data)
    else:
        mesh = bpy.data.meshes.new(c["name"])
        mesh.from_pydata([to_blender(p) for p in c["points"]], [], [tuple(t) for t in c["triangles"]])
        if c["uv"]:  # over the rectangle its texture is baked on
            u0, v0, u1, v1 = c["uv_rect"]
            su, sv = 1.0 / max(u1 - u0, 1e-12), 1.0 / max(v1 - v0, 1e-12)
            uv = mesh.uv_layers.new()
            for loop in mesh.loops:
                u, v = c["uv"][loop.vertex_index]
                uv.data[loop.index].uv = ((u - u0) * su, (v - v0) * sv)
        obj = link(c["name"], mesh)
    centers = [to_blender(p) for p in c["centers"]]
    obj.location = centers[0]
    return obj, centers


def bake(obj, paths, first_frame):
    """Keyframes every frame from first_frame: paths maps a property to its value per frame."""
    for k in range(len(next(iter(paths.values())))):
        for prop, values in paths.items():
            setattr(obj, prop, values[k])
            obj.keyframe_insert(prop, frame=first_frame + k)
    for fc in obj.animation_data.action.fcurves:
        for key in fc.keyframe_points:
            key.interpolation = "LINEAR"


def view_matrix(view):
    pos, target, up = (to_blender(view[k]) for k in ("position", "look_at", "up"))
    forward = (target - pos).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    rot = Matrix((right, true_up, -forward)).transposed()  # a Blender camera looks along -Z with +Y up
    return pos, rot.to_quaternion()


def add_camera(cam, first_frame):
    data = bpy.data.cameras.new("camera")
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(cam["fov_deg"])
    data.clip_start = 0.01
    data.clip_end = 10000.0
    obj = link("camera", data)
    obj.rotation_mode = "QUATERNION"
    locations, rotations = [], []
    for view in cam["views"]:
        pos, q = view_matrix(view)
        if rotations and rotations[-1].dot(q) < 0:
            q.negate()  # the shorter way between keys
        locations.append(pos)
        rotations.append(q)
    obj.location, obj.rotation_quaternion = locations[0], rotations[0]
    if len(cam["views"]) > 1:
        bake(obj, {"location": locations, "rotation_quaternion": rotations}, first_frame)
    # A thin lens of radius `aperture` (m): Cycles' aperture radius is lens / (2 f-stop), lens in mm.
    aperture = cam["views"][0].get("aperture", 0.0)
    if aperture > 0:
        data.dof.use_dof = True
        data.dof.aperture_fstop = data.lens * 1e-3 / (2 * aperture)
        data.dof.focus_distance = cam["views"][0]["focus"]
        if len(cam["views"]) > 1:  # focused on the followed body: its distance at every frame
            for k, view in enumerate(cam["views"]):
                data.dof.focus_distance = view["focus"]
                data.dof.keyframe_insert("focus_distance", frame=first_frame + k)
            for fc in data.animation_data.action.fcurves:
                for key in fc.keyframe_points:
                    key.interpolation = "LINEAR"
    bpy.context.scene.camera = obj
    return obj


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    if len(argv) != 2:
        fail("usage: blender -b --factory-startup --python make_blend.py -- MANIFEST.json OUT.blend")
    with open(argv[0]) as f:
        m = json.load(f)
    out_dir = m["out_dir"]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.preferences.filepaths.save_version = 0  # no OUT.blend1 backup beside the file
    scene = bpy.context.scene
    scene.name = m["scene"]
    # Relative paths ("//mesh/...") resolve against the file's folder: save an empty file there first.
    bpy.ops.wm.save_as_mainfile(filepath=argv[1])

    fps = float(m["fps"])
    scene.render.fps = max(1, round(fps))
    scene.render.fps_base = scene.render.fps / fps
    scene.frame_start, scene.frame_end = m["frame_start"], m["frame_end"]
    scene.render.resolution_x, scene.render.resolution_y = m["resolution"]
    scene.render.resolution_percentage = 100
    scene.render.engine = "CYCLES"
    scene.render.film_transparent = False
    scene.cycles.samples = 128  # adaptive (Cycles' default threshold): raise for a converged still
    scene.cycles.use_animated_seed = True  # a video's noise changes frame to frame instead of sticking to the picture
    # Debian's Blender is built without Open Image Denoise: Cycles' default denoising would make every render fail.
    scene.cycles.use_denoising = False
    # Motion blur (camera.shutter): open for that fraction of a frame, closing at the frame (wobble's shutter ends at
    # the frame's time). The Mesh Cache modifiers, baked colliders and follow camera blur with it.
    shutter = m["camera"].get("shutter", 0.0)
    if shutter > 0:
        scene.render.use_motion_blur = True
        scene.render.motion_blur_shutter = shutter
        scene.cycles.motion_blur_position = "END"

    def load_image(path):  # relative to OUT, where the .blend already lies
        return bpy.data.images.load("//" + path, check_existing=True)

    materials = [cycles_nodes.material(mat, load_image) for mat in m["materials"]]
    casters, receivers = [], []  # shadow caustics: gelatine casts them, every other surface receives them
    for b in m["bodies"]:
        obj = add_body(b, materials[b["material"]], out_dir, m["frame_start"])
        (casters if m["materials"][b["material"]].get("dielectric") else receivers).append(obj)
    for c in m["colliders"]:
        obj, centers = add_collider(c)
        if any((p - centers[0]).length > 0 for p in centers):
            bake(obj, {"location": centers}, m["frame_start"])
        obj.data.materials.append(materials[c["material"]])
        receivers.append(obj)
    add_camera(m["camera"], m["frame_start"])
    suns = [cycles_nodes.sun(scene, "sun" if i == 0 else "sun.%d" % i, sun)  # none with an environment map
            for i, sun in enumerate(m["suns"])]
    if m["shadow_caustics"] and casters:
        cycles_nodes.shadow_caustics(casters, receivers, suns)
    cycles_nodes.world(scene, m["sky"], m.get("environment"), m["bounces"])
    cycles_nodes.light_paths(scene, m["bounces"], any(mat.get("dielectric") for mat in m["materials"]),
                             m["clamp_indirect"])
    cycles_nodes.tone_map(scene, m["exposure"])
    if m["pack"]:
        bpy.ops.file.pack_all()
    scene.frame_set(m["frame_start"])
    bpy.ops.wm.save_as_mainfile(filepath=argv[1], relative_remap=True)
    print("make_blend.py: wrote %s: %d objects, frames %d..%d" %
          (argv[1], len(bpy.data.objects), scene.frame_start, scene.frame_end))


if __name__ == "__main__":
    try:
        main()
    except Exception as e:  # a Blender API difference or unexpected input: say so and exit non-zero
        import traceback
        traceback.print_exc()
        fail("failed: %s: %s" % (type(e).__name__, e))
    sys.stdout.flush()
    os._exit(0)
