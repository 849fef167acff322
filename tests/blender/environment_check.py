"""Checks that `wobble blend` mapped an environment map onto Cycles (issue 29), run inside Blender:

    blender OUT/scene.blend --python-exit-code 1 --python environment_check.py -- EXPECTED.json

EXPECTED.json: the map's file, rotation (degrees) and strength, and probes: wobble directions (Y up) with the
radiance wobble's renderer sees along each (render::EnvironmentMap::eval, computed by the test). Checked: the world's
Background shows an Environment Texture of that file's copy beside the .blend (Closest interpolation) at that strength, turned by the
rotation, no sun is added; and Cycles itself, rendering a 1 x 1 picture looking along each probe's direction, sees
the same radiance, so the two renderers agree on the map's orientation, its rotation and its strength.
"""
import filecmp
import json
import math
import os
import sys

import bpy
from mathutils import Vector

args = sys.argv[sys.argv.index("--") + 1:]
with open(args[0]) as f:
    e = json.load(f)

scene = bpy.context.scene
world = scene.world
nodes = world.node_tree.nodes
textures = [n for n in nodes if n.type == "TEX_ENVIRONMENT"]
assert len(textures) == 1, "no Environment Texture"
tex = textures[0]
# The map's copy beside the .blend (OUT/blender/), by a relative path: the same bytes as the scene's file.
assert tex.image.filepath.startswith("//blender/"), tex.image.filepath
assert filecmp.cmp(bpy.path.abspath(tex.image.filepath), e["file"], shallow=False), tex.image.filepath
assert tex.interpolation == "Closest", tex.interpolation
background = nodes["Background"]
assert abs(background.inputs["Strength"].default_value - e["strength"]) < 1e-6


def upstream(node):  # every node that feeds this one
    for socket in node.inputs:
        for link in socket.links:
            yield link.from_node
            yield from upstream(link.from_node)


# The map lights the world (through the cut that keeps it off a path's last vertex, as wobble's sky).
assert tex in set(upstream(background)), "the map does not light the world"
assert not any(o.type == "LIGHT" for o in scene.objects), "a sun besides the map"

# Cycles' own view along each probe: a 1 x 1 camera of a tiny field of view, one sample, no view transform.
camera = bpy.data.objects.new("probe", bpy.data.cameras.new("probe"))
scene.collection.objects.link(camera)
camera.data.angle = math.radians(0.01)
scene.camera = camera
for o in scene.objects:  # only the world: nothing in front of the camera
    if o.type == "MESH":
        o.hide_render = True
scene.render.engine = "CYCLES"
scene.cycles.samples = 1
scene.cycles.use_denoising = False
scene.render.resolution_x = scene.render.resolution_y = 1
scene.render.resolution_percentage = 100
scene.view_settings.view_transform = "Raw"
scene.render.use_compositing = False  # radiance, not the tone curve's display values
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
result = os.path.join(os.path.dirname(args[0]), "probe.exr")
for probe in e["probes"]:
    d = probe["direction"]
    camera.rotation_mode = "QUATERNION"
    camera.rotation_quaternion = Vector((d[0], -d[2], d[1])).to_track_quat("-Z", "Y")  # wobble -> Blender axes
    bpy.ops.render.render()
    bpy.data.images["Render Result"].save_render(result)
    image = bpy.data.images.load(result)
    seen = list(image.pixels)[:3]
    bpy.data.images.remove(image)
    for k in range(3):
        assert abs(seen[k] - probe["radiance"][k]) <= 1e-3 * max(1.0, probe["radiance"][k]), (d, seen, probe)
print("environment check ok: %d probes" % len(e["probes"]))
