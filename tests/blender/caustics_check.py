"""Checks the shadow-caustic flags `wobble blend` sets for Cycles' manifold next-event estimation (issue 51), run
inside Blender:

    blender OUT/scene.blend --python-exit-code 1 --python caustics_check.py -- EXPECTED.json

EXPECTED.json: "casters", "receivers" and "lights", the names of the objects whose Cycles flag
(Object.cycles.is_caustics_caster, Object.cycles.is_caustics_receiver, Light.cycles.is_caustics_light) must be set.
Every other object must have the flag off, and the world never lights caustics (wobble's caustic photons leave the
suns only).
"""
import json
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
with open(args[0]) as f:
    e = json.load(f)

for obj in bpy.data.objects:
    if obj.type == "MESH":
        assert obj.cycles.is_caustics_caster == (obj.name in e["casters"]), f"{obj.name}: caster flag"
        assert obj.cycles.is_caustics_receiver == (obj.name in e["receivers"]), f"{obj.name}: receiver flag"
    elif obj.type == "LIGHT":
        assert obj.data.cycles.is_caustics_light == (obj.name in e["lights"]), f"{obj.name}: caustics light flag"
names = {obj.name for obj in bpy.data.objects}
for key in ("casters", "receivers", "lights"):
    assert set(e[key]) <= names, f"{key}: {sorted(set(e[key]) - names)} not in the .blend ({sorted(names)})"
world = bpy.context.scene.world
assert world is None or not world.cycles.is_caustics_light, "the world lights caustics"
print("caustics check ok")
