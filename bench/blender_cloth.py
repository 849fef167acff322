"""Blender's cloth on the folded cloth of bench/body_contact_bench.cpp: a yardstick for the cost of self-contact.

    blender -b --factory-startup -t 2 --python-exit-code 1 --python bench/blender_cloth.py -- SIDE SELF [STEPS] [QUALITY]

Builds tests/sim/folded_cloth.h's cloth shape in Blender: a SIDE x SIDE grid, 2 x 2 m, split into triangles as
wobble's cloth is, folded like a ribbon in four layers (half-circle folds of radius one spacing) 1 cm above a floor,
wobble's Y up turned to Blender's Z up. Blender's cloth (implicit Euler) runs at 60 frames a second, QUALITY steps a
frame (default 5, Blender's default; at 1, wobble's step of 1/60 s, Blender's cloth passes through the floor), with
self-collision on (SELF 1) or off (0) at a quarter of a spacing (wobble's thickness) and the floor a collision object
at 5 mm (the cloth's 4 mm and the floor's outer 1 mm). Mass, stiffness, damping and collision iterations are
Blender's defaults but for bending, limp (0.001) so that the folds collapse onto each other as wobble's do: the
cloths are alike, not the same, and what compares is each solver's cost with self-collision on against off.
Frames 1 to 30 are the warm-up (0.5 s, as the benchmark's: the layers have landed on each other); frames 31 to STEPS
(default 40) are timed one at a time (scene.frame_set, wall and the process's CPU). Prints one line per timed frame
and then
  median_wall_ms=  median_cpu_ms=  intersecting_pairs=  lowest_z=  highest_z=
where intersecting_pairs counts the pairs of triangles sharing no vertex that intersect in the last frame's mesh
(mathutils.bvhtree.BVHTree.overlap, Blender's own triangle-triangle test), and lowest_z / highest_z bound the cloth
(m; the floor is at 0).
"""
import math
import statistics
import sys
import time

import bmesh
import bpy
from mathutils.bvhtree import BVHTree

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if len(argv) < 2:
    sys.exit("usage: blender -b --factory-startup --python bench/blender_cloth.py -- SIDE SELF [STEPS] [QUALITY]")
side, self_collision = int(argv[0]), argv[1] == "1"
steps = int(argv[2]) if len(argv) > 2 else 40
quality = int(argv[3]) if len(argv) > 3 else 5
warm_up = 30
if side < 11 or steps <= warm_up or quality < 1:  # below 11 the four layers and three folds do not fit in 2 m
    sys.exit(f"blender_cloth.py: SIDE {side} must be at least 11, STEPS {steps} more than the {warm_up} warm-up "
             f"frames, QUALITY {quality} at least 1")

size, layers = 2.0, 4
spacing = size / (side - 1)
r = spacing
arc = math.pi * r
width = (size - (layers - 1) * arc) / layers


def folded(s):
    """tests/sim/folded_cloth.h's fold of a point s along x (0..size) into (x, y), Y up."""
    for k in range(layers):
        direction, start = (1, 0) if k % 2 == 0 else (-1, width)
        if s <= width or k == layers - 1:
            return start + direction * s - width / 2, 2 * r * k + 0.01
        s -= width
        if s <= arc:
            return (start + direction * (width + r * math.sin(s / r)) - width / 2,
                    2 * r * k + r * (1 - math.cos(s / r)) + 0.01)
        s -= arc
    raise AssertionError


bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.fps = 60
scene.frame_start, scene.frame_end = 1, steps

mesh = bpy.data.meshes.new("cloth")
bm = bmesh.new()
verts = []
for j in range(side):
    for i in range(side):
        x, y = folded(i * spacing)
        z = j * spacing - size / 2
        verts.append(bm.verts.new((x, -z, y)))  # wobble (x, y, z) -> Blender (x, -z, y)
for j in range(side - 1):
    for i in range(side - 1):
        a, b, c, d = (j * side + i, j * side + i + 1, (j + 1) * side + i + 1, (j + 1) * side + i)
        bm.faces.new((verts[a], verts[b], verts[c]))
        bm.faces.new((verts[a], verts[c], verts[d]))
bm.to_mesh(mesh)
bm.free()
cloth = bpy.data.objects.new("cloth", mesh)
scene.collection.objects.link(cloth)

mod = cloth.modifiers.new("Cloth", "CLOTH")
settings = mod.settings
settings.quality = quality  # steps a frame
settings.bending_stiffness = 0.001
collision = mod.collision_settings
collision.use_collision = True
collision.distance_min = 0.004
collision.use_self_collision = self_collision
collision.self_distance_min = 0.25 * spacing
mod.point_cache.frame_start, mod.point_cache.frame_end = 1, steps

bpy.ops.mesh.primitive_plane_add(size=20, location=(0, 0, 0))
floor = bpy.context.active_object
floor.modifiers.new("Collision", "COLLISION")
floor.collision.thickness_outer = 0.001  # with the cloth's 4 mm: wobble's floor at 5 mm

walls, cpus = [], []
for frame in range(1, steps + 1):
    wall0, cpu0 = time.perf_counter(), time.process_time()
    scene.frame_set(frame)
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    if frame > warm_up:
        walls.append(wall)
        cpus.append(cpu)
        print(f"frame {frame}: wall_ms={1e3 * wall:.2f} cpu_ms={1e3 * cpu:.2f}", flush=True)

depsgraph = bpy.context.evaluated_depsgraph_get()
evaluated = cloth.evaluated_get(depsgraph)
shaped = evaluated.to_mesh()
points = [v.co.copy() for v in shaped.vertices]
triangles = [tuple(p.vertices) for p in shaped.polygons]
tree = BVHTree.FromPolygons(points, triangles, all_triangles=True)
intersecting = sum(1 for a, b in tree.overlap(tree) if a < b and not set(triangles[a]) & set(triangles[b]))
lowest, highest = min(p.z for p in points), max(p.z for p in points)
evaluated.to_mesh_clear()
print(f"median_wall_ms={1e3 * statistics.median(walls):.2f} median_cpu_ms={1e3 * statistics.median(cpus):.2f} "
      f"intersecting_pairs={intersecting} lowest_z={lowest:.4f} highest_z={highest:.4f}")
