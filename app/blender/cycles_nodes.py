"""Cycles node setups shared by `wobble blend` (app/blender/make_blend.py, which the binary carries together with this
file) and the Cycles comparison (bench/cycles_scene.py): one place says how wobble's gelatine and environment map
look in Cycles, so the .blend a user gets and the picture the comparison measures are the same model.

gelatine(nodes, links, out, g, print_color): wobble's gelatine (render/dielectric.h, docs/materials.md) on a
    material's node tree: a Glass BSDF (exact dielectric Fresnel, GGX or sharp; Cycles' roughness is sqrt of wobble's
    GGX alpha) mixed with a Diffuse print coloured print_color (a socket, or an RGBA tuple) by the print's coverage,
    and a volume inside with wobble's coefficients: Volume Absorption (Cycles: sigma_a = (1 - colour) density) and
    Volume Scatter (isotropic, sigma_s = colour density). wobble's scattering events keep scatter_albedo of the light,
    so the rest of sigma_s counts as absorption. g: ior, roughness (alpha), sigma_a (3 values, 1/m), sigma_s (1/m),
    scatter_albedo (3 values), print (coverage).

environment(nodes, links, env): wobble's environment map (render/environment.h) on a world's node tree: an
    Environment Texture of the file (equirectangular, "Closest" interpolation: wobble's texels are constant) looked up
    through a Mapping node of type Texture that turns it by rotation_deg about Z (wobble's up). Returns the colour
    socket; the caller feeds it (times env["strength"]) to the Background. Blender's equirectangular mapping under
    wobble's axes (Blender's (x, y, z) = wobble's (x, -z, y)) is wobble's own, so the file is used unchanged.
"""
import math

import bpy


def gelatine(nodes, links, out, g, print_color):
    glass = nodes.new("ShaderNodeBsdfGlass")
    glass.distribution = "GGX" if g["roughness"] > 0 else "SHARP"
    glass.inputs["Roughness"].default_value = math.sqrt(g["roughness"])
    glass.inputs["IOR"].default_value = g["ior"]
    glass.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    surface = glass.outputs["BSDF"]
    if g["print"] > 0:
        diffuse = nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Roughness"].default_value = 0.0  # Lambert
        if isinstance(print_color, bpy.types.NodeSocket):
            links.new(print_color, diffuse.inputs["Color"])
        else:
            diffuse.inputs["Color"].default_value = tuple(print_color)
        mix = nodes.new("ShaderNodeMixShader")
        mix.inputs["Fac"].default_value = g["print"]
        links.new(glass.outputs["BSDF"], mix.inputs[1])
        links.new(diffuse.outputs["BSDF"], mix.inputs[2])
        surface = mix.outputs["Shader"]
    links.new(surface, out.inputs["Surface"])
    sigma_s = g["sigma_s"]
    sigma_a = [a + (1 - albedo) * sigma_s for a, albedo in zip(g["sigma_a"], g["scatter_albedo"])]
    volume = None
    density = max(sigma_a)
    if density > 0:
        absorb = nodes.new("ShaderNodeVolumeAbsorption")
        absorb.inputs["Density"].default_value = density
        absorb.inputs["Color"].default_value = tuple(1 - a / density for a in sigma_a) + (1.0,)
        volume = absorb.outputs["Volume"]
    if sigma_s > 0:
        scatter = nodes.new("ShaderNodeVolumeScatter")
        scatter.inputs["Density"].default_value = sigma_s
        scatter.inputs["Color"].default_value = tuple(g["scatter_albedo"]) + (1.0,)
        scatter.inputs["Anisotropy"].default_value = 0.0
        if volume is not None:
            add = nodes.new("ShaderNodeAddShader")
            links.new(volume, add.inputs[0])
            links.new(scatter.outputs["Volume"], add.inputs[1])
            volume = add.outputs["Shader"]
        else:
            volume = scatter.outputs["Volume"]
    if volume is not None:
        links.new(volume, out.inputs["Volume"])


def environment(nodes, links, env):
    image = bpy.data.images.load(env["file"], check_existing=True)  # HDR and EXR load as linear data
    tex = nodes.new("ShaderNodeTexEnvironment")
    tex.image = image
    tex.interpolation = "Closest"
    tex.projection = "EQUIRECTANGULAR"
    coord = nodes.new("ShaderNodeTexCoord")  # in a world, Generated is the ray's direction
    mapping = nodes.new("ShaderNodeMapping")
    mapping.vector_type = "TEXTURE"  # turns the map by the rotation (a Point mapping would turn the lookup)
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(env["rotation_deg"]))
    links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
    return tex.outputs["Color"]
