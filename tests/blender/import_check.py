# Run by Blender (3.4+): blender -b --factory-startup --python-exit-code 1 --python import_check.py -- MESH_DIR
# Imports every <body>_NNNN.obj of a wobble run with bpy.ops.wm.obj_import and checks what a user needs: a textured
# mesh with UVs, the same vertex count in every frame, frames in order (the jelly falls), and right side up (wobble's
# +Y up becomes Blender's +Z up).
import glob
import sys

import bpy

mesh_dir = sys.argv[sys.argv.index("--") + 1]
paths = sorted(glob.glob(mesh_dir + "/jelly_*.obj"))
assert len(paths) >= 3, f"expected a sequence in {mesh_dir}, found {paths}"
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)

lowest, counts = [], set()
for path in paths:
    bpy.ops.wm.obj_import(filepath=path)
    obj = bpy.context.selected_objects[0]
    mesh = obj.data
    counts.add(len(mesh.vertices))
    assert mesh.uv_layers, f"{path}: no UVs"
    images = [n.image for n in mesh.materials[0].node_tree.nodes if n.type == "TEX_IMAGE" and n.image]
    assert images and images[0].size[0] > 0, f"{path}: texture not loaded"
    heights = [(obj.matrix_world @ v.co).z for v in mesh.vertices]
    lowest.append(min(heights))
    assert max(heights) - min(heights) > 3.9, f"{path}: the 4 m jelly is not upright along Blender's Z"

assert len(counts) == 1, f"vertex counts differ between frames: {counts}"
assert abs(lowest[0] - 6.78) < 1e-3, f"first frame's lowest point at z = {lowest[0]}, expected 6.78"
assert all(a > b for a, b in zip(lowest, lowest[1:])), f"frames out of order: lowest points {lowest}"
print(f"blender import ok: {len(paths)} frames, {counts.pop()} vertices each, lowest z {lowest}")
