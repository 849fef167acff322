"""Builds a wobble run's Blender scene: `wobble blend OUT` runs it (the binary carries this file) as

    blender -b --factory-startup --python-exit-code 1 --python make_blend.py -- MANIFEST.json OUT.blend

MANIFEST.json (written by app/blend_command.cpp; wobble's Y-up coordinates, metres; paths relative to the run's
folder, where the .blend is saved) lists the frame range and rate, the bodies (base OBJ, PC2 point cache, colour,
texture, material), the colliders (plane, sphere, box, mesh; moving ones with a centre per frame), the camera (one view, or
one per frame for a follow camera; the shutter) and the sun, or the environment map that replaces the sun and the sky
(its file an absolute path). Each body becomes one object: its base OBJ, imported with Blender's
default OBJ axes (forward -Z, up Y, which map wobble's (x, y, z) to Blender's (x, -z, y) by the object's rotation),
with a Mesh Cache modifier playing its PC2 (whose points are the OBJ's vertices in order) and one material. Moving
colliders and the follow camera are baked as keyframes, one per frame, linear. Paths in the .blend are relative to
it, so the run's folder can be moved as a whole. Gelatine and the environment map come from cycles_nodes.py (written
beside this script by `wobble blend`; bench/cycles_scene.py uses it too).
"""
import json
import math
import os
import struct
import sys

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_nodes  # noqa: E402  (found beside this script)


def fail(message):
    print("make_blend.py: " + message, file=sys.stderr)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(1)


def to_blender(v):
    """wobble (Y up) -> Blender (Z up): the OBJ importer's default mapping, (x, y, z) -> (x, -z, y)."""
    return Vector((v[0], -v[2], v[1]))


def pc2_points(path):
    with open(path, "rb") as f:
        header = f.read(32)
    if len(header) < 32 or header[:12] != b"POINTCACHE2\0":
        fail("%s: not a PC2 point cache" % path)
    return struct.unpack("<i", header[16:20])[0]


def principled(name, color, roughness, glossy=False):
    """A Principled BSDF material of the given colour; a jelly gets a clear coat."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Base Color"].default_value = tuple(color) + (1.0,)
    if glossy:
        bsdf.inputs["Clearcoat"].default_value = 1.0
        bsdf.inputs["Clearcoat Roughness"].default_value = 0.05
    return mat, bsdf


def tinted(mat, color, texture):
    """Colour x texture, as wobble's renderer (and the MTL's Kd with map_Kd): the socket of the product."""
    mul = mat.node_tree.nodes.new("ShaderNodeMixRGB")
    mul.blend_type = "MULTIPLY"
    mul.inputs["Fac"].default_value = 1.0
    mul.inputs["Color1"].default_value = tuple(color) + (1.0,)
    mat.node_tree.links.new(texture, mul.inputs["Color2"])
    return mul.outputs["Color"]


def tint(mat, bsdf, color, texture):
    """Base colour = colour x texture."""
    mat.node_tree.links.new(tinted(mat, color, texture), bsdf.inputs["Base Color"])


def gelatine_material(b):
    """wobble's gelatine (docs/materials.md) in Cycles (cycles_nodes.gelatine): glass at the body's IOR and
    roughness, the print (colour x texture) mixed in by its coverage, and a volume with wobble's coefficients: sigma_a
    from the colour seen through absorption_depth, sigma_s = 1 / scatter (the mean free path)."""
    g = b["gelatine"]
    mat = bpy.data.materials.new(b["name"])
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    print_color = tuple(b["color"]) + (1.0,)
    if b["texture"]:
        tex = nodes.new("ShaderNodeTexImage")
        tex.image = bpy.data.images.load("//" + b["texture"], check_existing=True)
        print_color = tinted(mat, b["color"], tex.outputs["Color"])
    cycles_nodes.gelatine(nodes, mat.node_tree.links, nodes["Material Output"], {
        "ior": g["ior"],
        "roughness": g["roughness"],
        "sigma_a": [-math.log(max(c, 1e-6)) / g["absorption_depth"] for c in g["absorption_color"]],
        "sigma_s": 1.0 / g["scatter"] if g["scatter"] > 0 else 0.0,
        "scatter_albedo": g["scatter_albedo"],
        "print": g["print"],
    }, print_color)
    return mat


def body_material(b):
    if b["material"] == "gelatine":
        return gelatine_material(b)
    jelly = b["material"] == "jelly"
    mat, bsdf = principled(b["name"], b["color"], 0.4 if jelly else 0.9, glossy=jelly)
    if b["texture"]:
        tex = mat.node_tree.nodes.new("ShaderNodeTexImage")
        tex.image = bpy.data.images.load("//" + b["texture"], check_existing=True)
        tint(mat, bsdf, b["color"], tex.outputs["Color"])
    return mat


def add_body(b, out_dir, first_frame):
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
    obj.data.materials.append(body_material(b))
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


def collider_material(c):
    """Colour x the procedural texture over the UVs (a tile per unit): grey checks, or wooden planks."""
    mat, bsdf = principled(c["name"], c["color"], 0.8)
    kind = c.get("texture", "none")
    if kind == "none":
        return mat
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    uv = nodes.new("ShaderNodeTexCoord").outputs["UV"]
    if kind == "checker":  # two squares per tile, as wobble's renderer
        tex = nodes.new("ShaderNodeTexChecker")
        tex.inputs["Scale"].default_value = 2.0
        tex.inputs["Color1"].default_value = (0.75, 0.75, 0.72, 1.0)
        tex.inputs["Color2"].default_value = (0.3, 0.3, 0.3, 1.0)
        links.new(uv, tex.inputs["Vector"])
        color = tex.outputs["Color"]
    else:  # wood: four planks per tile, with a grain
        wave = nodes.new("ShaderNodeTexWave")
        wave.wave_type = "BANDS"
        wave.bands_direction = "X"
        wave.inputs["Scale"].default_value = 4.0
        wave.inputs["Distortion"].default_value = 2.0
        links.new(uv, wave.inputs["Vector"])
        ramp = nodes.new("ShaderNodeValToRGB")
        ramp.color_ramp.elements[0].color = (0.33, 0.17, 0.07, 1.0)
        ramp.color_ramp.elements[1].color = (0.6, 0.36, 0.17, 1.0)
        links.new(wave.outputs["Fac"], ramp.inputs["Fac"])
        color = ramp.outputs["Color"]
    tint(mat, bsdf, c["color"], color)
    return mat


def add_plane(c):
    n = to_blender(c["normal"]).normalized()
    u = n.orthogonal().normalized()
    v = n.cross(u)
    p, h = to_blender(c["point"]), c["size"] / 2.0
    corners = [p + (su * u + sv * v) * h for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    mesh = bpy.data.meshes.new(c["name"])
    mesh.from_pydata(corners, [], [(0, 1, 2, 3)])
    tiles = c["size"] / c["texture_scale"]
    uv = mesh.uv_layers.new()
    for loop, (a, b) in zip(uv.data, ((0, 0), (tiles, 0), (tiles, tiles), (0, tiles))):
        loop.uv = (a, b)
    return link(c["name"], mesh)


def add_moving(c):
    if c["type"] == "sphere":
        bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=c["radius"])
        obj = bpy.context.active_object
        bpy.ops.object.shade_smooth()
    elif c["type"] == "mesh":  # points where they start; `centers` are the offsets from there
        mesh = bpy.data.meshes.new(c["name"])
        mesh.from_pydata([to_blender(p) for p in c["points"]], [], [tuple(t) for t in c["triangles"]])
        uv = mesh.uv_layers.new()  # the x-z floor plan in metres, as wobble's renderer
        for poly in mesh.polygons:
            for li in poly.loop_indices:
                co = mesh.vertices[mesh.loops[li].vertex_index].co
                uv.data[li].uv = (co.x, -co.y)
        obj = link(c["name"], mesh)
    else:
        bpy.ops.mesh.primitive_cube_add(size=1.0)
        obj = bpy.context.active_object
        sx, sy, sz = c["size"]
        obj.scale = (sx, sz, sy)  # wobble's y (thickness) is Blender's z
    obj.name = obj.data.name = c["name"]
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


def add_sun(sun):
    data = bpy.data.lights.new("sun", type="SUN")
    data.energy = 4.0
    data.angle = math.radians(sun["angle_deg"])
    obj = link("sun", data)
    obj.rotation_mode = "QUATERNION"
    obj.rotation_quaternion = to_blender(sun["direction"]).normalized().to_track_quat("Z", "Y")  # shines along -Z


def add_sky(env):
    """A sky colour, or the environment map (cycles_nodes.environment) at its strength."""
    world = bpy.data.worlds.new("environment" if env else "sky")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (0.45, 0.6, 0.9, 1.0)
    background.inputs["Strength"].default_value = 1.0
    if env:
        color = cycles_nodes.environment(world.node_tree.nodes, world.node_tree.links, env)
        world.node_tree.links.new(color, background.inputs["Color"])
        background.inputs["Strength"].default_value = env["strength"]
    bpy.context.scene.world = world


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
    scene.cycles.samples = 64
    # Debian's Blender is built without Open Image Denoise: Cycles' default denoising would make every render fail.
    scene.cycles.use_denoising = False
    # Motion blur (camera.shutter): open for that fraction of a frame, closing at the frame (wobble's shutter ends at
    # the frame's time). The Mesh Cache modifiers, baked colliders and follow camera blur with it.
    shutter = m["camera"].get("shutter", 0.0)
    if shutter > 0:
        scene.render.use_motion_blur = True
        scene.render.motion_blur_shutter = shutter
        scene.cycles.motion_blur_position = "END"

    for b in m["bodies"]:
        add_body(b, out_dir, m["frame_start"])
    for c in m["colliders"]:
        if c["type"] == "plane":
            obj = add_plane(c)
        else:
            obj, centers = add_moving(c)
            if any((p - centers[0]).length > 0 for p in centers):
                bake(obj, {"location": centers}, m["frame_start"])
        obj.data.materials.append(collider_material(c))
    add_camera(m["camera"], m["frame_start"])
    env = m.get("environment")
    if not env:  # an environment map holds its own sun
        add_sun(m["sun"])
    add_sky(env)
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
