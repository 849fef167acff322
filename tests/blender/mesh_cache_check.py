# Run by Blender (3.4+), from tests/app/blender_test.cpp:
#   blender -b --factory-startup --python-exit-code 1 --python mesh_cache_check.py -- by-hand OUT BODY
#   blender -b OUT/SCENE.blend --python-exit-code 1 --python mesh_cache_check.py -- blend OUT EXPECTED.json
# by-hand: what docs/blender.md's "By hand, with the point cache" says: import OUT/mesh/BODY.obj, add a Mesh Cache
#   modifier playing OUT/mesh/BODY.pc2 from the run's first frame.
# blend: the file `wobble blend` built: its bodies, modifiers, colliders, camera keyframes, frame range and rate
#   against EXPECTED.json.
# Both then compare the evaluated mesh, at the first, middle and last frame, vertex by vertex with the OBJ sequence's
# `v` lines of that frame (mapped to Blender's Z up as the importer does: (x, y, z) -> (x, -z, y)).
import json
import os
import sys

import bpy
from mathutils import Vector

args = sys.argv[sys.argv.index("--") + 1:]
mode, out = args[0], args[1]
with open(os.path.join(out, "run.json")) as f:
    run = json.load(f)
first = run["frames"]["first"]
last = first + run["frames"]["written"] - 1


def obj_vertices(path):
    with open(path) as f:
        return [Vector((float(x), -float(z), float(y)))
                for x, y, z in (line.split()[1:4] for line in f if line.startswith("v "))]


def check_frames(obj, body):
    scene = bpy.context.scene
    for frame in (first, (first + last) // 2, last):
        scene.frame_set(frame)
        mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
        got = [obj.matrix_world @ v.co for v in mesh.vertices]
        want = obj_vertices(os.path.join(out, "mesh", "%s_%04d.obj" % (body, frame)))
        assert len(got) == len(want), f"frame {frame}: {len(got)} vertices, the OBJ has {len(want)}"
        worst = max((g - w).length for g, w in zip(got, want))
        assert worst < 1e-5, f"{body} frame {frame}: a vertex is {worst} m from the OBJ frame's"
        print(f"{body} frame {frame}: {len(got)} vertices, largest distance to the OBJ frame {worst:.2e} m")
        obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh_clear()


if mode == "by-hand":
    body = args[2]
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    bpy.ops.wm.obj_import(filepath=os.path.join(out, "mesh", body + ".obj"))
    obj = bpy.context.selected_objects[0]
    cache = obj.modifiers.new("cache", "MESH_CACHE")
    cache.cache_format = "PC2"
    cache.filepath = os.path.join(out, "mesh", body + ".pc2")
    cache.frame_start = first
    check_frames(obj, body)
else:
    with open(args[2]) as f:
        expected = json.load(f)
    scene = bpy.context.scene
    assert (scene.frame_start, scene.frame_end) == (first, last), (scene.frame_start, scene.frame_end)
    assert abs(scene.render.fps / scene.render.fps_base - run["fps"]) < 1e-6, scene.render.fps
    for body in expected["bodies"]:
        obj = bpy.data.objects[body["name"]]
        caches = [m for m in obj.modifiers if m.type == "MESH_CACHE"]
        assert len(caches) == 1 and caches[0].cache_format == "PC2", f"{body['name']}: {list(obj.modifiers)}"
        assert bpy.path.abspath(caches[0].filepath) == os.path.join(out, "mesh", body["name"] + ".pc2")
        assert len(obj.data.materials) == 1, f"{body['name']}: materials {list(obj.data.materials)}"
        nodes = obj.data.materials[0].node_tree.nodes
        colours = [tuple(n.inputs["Color1"].default_value)[:3] for n in nodes if n.type == "MIX_RGB"]
        if not colours:  # no texture, no coat: the colour is the Diffuse BSDF's own
            colours = [tuple(n.inputs["Color"].default_value)[:3] for n in nodes if n.type == "BSDF_DIFFUSE"]
        assert max(abs(a - b) for a, b in zip(colours[0], body["color"])) < 1e-6, (colours, body["color"])
        images = [n.image for n in nodes if n.type == "TEX_IMAGE"]
        assert bool(images) == body["textured"], f"{body['name']}: images {images}"
        if images:
            assert images[0].size[0] > 0, f"{body['name']}: texture not loaded"
        check_frames(obj, body["name"])
    for name in expected["colliders"]:
        assert name in bpy.data.objects, f"collider {name} missing: {list(bpy.data.objects.keys())}"
    for name in expected.get("moving", []):
        action = bpy.data.objects[name].animation_data.action
        keys = {int(k.co.x) for fc in action.fcurves for k in fc.keyframe_points}
        assert keys == set(range(first, last + 1)), f"{name}: keyframes {sorted(keys)}"
    camera = scene.camera
    assert camera is not None, "no scene camera"
    if expected["camera_follows"]:
        keys = {int(k.co.x) for fc in camera.animation_data.action.fcurves for k in fc.keyframe_points}
        assert keys == set(range(first, last + 1)), f"camera keyframes {sorted(keys)}"
        scene.frame_set(first)
        start = camera.matrix_world.translation.copy()
        scene.frame_set(last)
        assert (camera.matrix_world.translation - start).length > 0.01, "the follow camera does not move"
    assert any(o.type == "LIGHT" and o.data.type == "SUN" for o in bpy.data.objects), "no sun"
print("mesh cache check ok:", mode)
