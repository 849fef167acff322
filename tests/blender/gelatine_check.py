"""Checks that `wobble blend` mapped a gelatine body and a thin lens onto Cycles (issue 29), run inside Blender:

    blender OUT/scene.blend --python-exit-code 1 --python gelatine_check.py -- EXPECTED.json

EXPECTED.json: the body's name and its gelatine keys (ior, roughness, absorption_color, absorption_depth, scatter,
scatter_albedo, print), the lens's aperture (m), the focus distance (m), the camera's shutter and the number of
frames. Checked, independently of
make_blend.py's arithmetic: a Glass BSDF at the IOR and roughness (GGX), the print mixed in by its coverage over a textured diffuse
BSDF, a volume whose absorption and scattering coefficients (Cycles: sigma_a = (1 - colour) density, sigma_s =
colour density) are wobble's, and the camera's f-stop giving the lens radius (radius = lens / (2 f-stop)) with the
focus distance keyed at every frame to the followed body's distance along the view; and the shutter (a fraction of the frame interval, closing at the frame) as
Cycles' motion blur.
"""
import json
import math
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
with open(args[0]) as f:
    e = json.load(f)


def close(a, b, tol=1e-4):
    return abs(a - b) <= tol * max(1.0, abs(b))


obj = bpy.data.objects[e["name"]]
mat = obj.data.materials[0]
nodes = mat.node_tree.nodes
glass = [n for n in nodes if n.type == "BSDF_GLASS"][0]
assert glass.distribution == "GGX", glass.distribution
assert close(glass.inputs["IOR"].default_value, e["ior"]), glass.inputs["IOR"].default_value
# Cycles' GGX alpha is its roughness squared; wobble's roughness is alpha.
assert close(glass.inputs["Roughness"].default_value ** 2, e["roughness"]), glass.inputs["Roughness"].default_value
mixes = [n for n in nodes if n.type == "MIX_SHADER"]
assert len(mixes) == 1 and close(mixes[0].inputs["Fac"].default_value, e["print"]), "print coverage"
assert any(n.type == "BSDF_DIFFUSE" for n in nodes), "no diffuse print"
assert any(n.type == "TEX_IMAGE" and n.image.size[0] > 0 for n in nodes), "print texture not loaded"
out = nodes["Material Output"]
assert out.inputs["Volume"].is_linked, "no volume inside"
absorb = [n for n in nodes if n.type == "VOLUME_ABSORPTION"][0]
scatter = [n for n in nodes if n.type == "VOLUME_SCATTER"][0]
density = absorb.inputs["Density"].default_value
colour = absorb.inputs["Color"].default_value
sigma_s = 1.0 / e["scatter"]
for k in range(3):
    sigma_a = -math.log(e["absorption_color"][k]) / e["absorption_depth"] + (1 - e["scatter_albedo"][k]) * sigma_s
    assert close((1 - colour[k]) * density, sigma_a), (k, (1 - colour[k]) * density, sigma_a)
    assert close(scatter.inputs["Color"].default_value[k] * scatter.inputs["Density"].default_value,
                 e["scatter_albedo"][k] * sigma_s), k
camera = bpy.context.scene.camera.data
assert camera.dof.use_dof, "depth of field off"
assert close(camera.lens * 1e-3 / (2 * camera.dof.aperture_fstop), e["aperture"]), camera.dof.aperture_fstop
keys = {int(k.co.x) for fc in camera.animation_data.action.fcurves if fc.data_path == "dof.focus_distance"
        for k in fc.keyframe_points}
assert len(keys) == e["frames"], f"focus keyframes {sorted(keys)}"
values = [k.co.y for fc in camera.animation_data.action.fcurves if fc.data_path == "dof.focus_distance"
          for k in fc.keyframe_points]
assert all(close(v, e["focus"]) for v in values), f"focus keyframes' values {values} against {e['focus']}"
render = bpy.context.scene.render
assert render.use_motion_blur == (e["shutter"] > 0), "motion blur"
assert close(render.motion_blur_shutter, e["shutter"]), render.motion_blur_shutter
assert bpy.context.scene.cycles.motion_blur_position == "END", bpy.context.scene.cycles.motion_blur_position
print("gelatine check ok")
