"""Cycles node setups and settings shared by `wobble blend` (app/blender/make_blend.py, which the binary carries
together with this file) and the Cycles comparison (bench/cycles_scene.py): one place says how wobble's picture is
made in Cycles, so the .blend a user gets and the picture the comparison measures are the same model. Every colour is
linear Rec.709, every direction in Blender's axes (wobble's (x, y, z) is Blender's (x, -z, y): to_blender).

material(m, load_image): a material from wobble's render::Material (scene_export.h's and the .blend manifest's
    fields: name, color, coat, ior, roughness, texture, and for gelatine dielectric, absorption, scatter,
    scatter_albedo, print); load_image(texture) gives the bpy image of m["texture"]. The base is a Lambertian
    Diffuse BSDF of colour x texture (the texture sRGB, over the surface's UVs, repeated); coat > 0 adds wobble's
    clear coat (render/bsdf.h): Diffuse weighted by (1 - coat F) plus a GGX Glossy weighted by coat F, F Schlick's
    Fresnel at n.wo (Layer Weight "Facing" = 1 - |n.wo|), Glossy roughness sqrt(alpha) (Cycles squares it).
    Gelatine: gelatine() below.
gelatine(nodes, links, out, g, print_color): wobble's gelatine (render/dielectric.h, docs/materials.md) on a
    material's node tree: a Glass BSDF (exact dielectric Fresnel, GGX or sharp; Cycles' roughness is sqrt of wobble's
    GGX alpha) mixed with a Diffuse print coloured print_color (a socket, or an RGBA tuple) by the print's coverage,
    and a volume inside with wobble's coefficients: Volume Absorption (Cycles: sigma_a = (1 - colour) density) and
    Volume Scatter (isotropic, sigma_s = colour density). wobble's scattering events keep scatter_albedo of the light,
    so the rest of sigma_s counts as absorption. g: ior, roughness (alpha), sigma_a (3 values, 1/m), sigma_s (1/m),
    scatter_albedo (3 values), print (coverage).
world(scene, sky, environment, bounces): wobble's sky (render/lights.h: by elevation e = d.up, horizon +
    sqrt(max(e, 0)) (zenith - horizon) + sqrt(clamp(-4 e, 0, 1)) (ground - horizon)) as world nodes, or the
    environment map (environment() below) at its strength. wobble's last path vertex takes sun light but no sky light;
    with bounces set, the world is cut where it would light that vertex (Light Path "Ray Depth" minus "Transmission
    Depth" >= bounces + 2: Cycles reads k + 2 when the world lights vertex k, and wobble's refractions through gelatine
    do not count as vertices), so both renderers carry the same light. bounces None: Cycles' own (sky everywhere).
environment(nodes, links, env): wobble's environment map (render/environment.h) on a world's node tree: an
    Environment Texture of env["file"] (equirectangular, "Closest" interpolation: wobble's texels are constant) looked
    up through a Mapping node of type Texture that turns it by rotation_deg about Z (wobble's up). Returns the colour
    socket; the caller feeds it (times env["strength"]) to the Background. Blender's equirectangular mapping under
    wobble's axes is wobble's own, so the file is used unchanged.
sun(scene, name, s): a Sun light: strength = the irradiance's largest channel (Blender's sun strength is irradiance,
    W/m^2), colour = irradiance / strength, angle = 2 x the angular radius, shining along -s["direction"], unseen by
    camera rays (wobble's camera rays see only the sky).
light_paths(scene, bounces, dielectric, clamp_indirect): Cycles' integrator as wobble's path tracer: `bounces`
    diffuse and glossy bounces (gelatine's interfaces and scattering events get their own budget: 64 transmission, 128
    volume, as wobble's caps), caustics on (wobble filters none), indirect light clamped at wobble's
    render.clamp_indirect (0, the bench's setting, clamps nothing), no direct clamp, no light threshold, no glossy blur,
    a 1-pixel box filter.
shadow_caustics(casters, receivers, lights): Cycles' manifold next-event estimation (Hanika, Droske, Fascione 2015)
    for the sunlight refracted through gelatine, as wobble's caustic photon map carries it (render.caustics =
    "photons"): the gelatine objects cast shadow caustics, every other mesh receives them, the suns light them. Cycles
    3.4 solves the chain through the caster's smooth interfaces but leaves out the volume inside it (no Beer-Lambert
    tint: the caustic comes out white where wobble's is the gelatine's colour) and needs smooth normals.
tone_map(scene, exposure): wobble's display transform (render/color.h): 2^exposure, Narkowicz's ACES fit x (2.51 x +
    0.03) / (x (2.43 x + 0.59) + 0.14) per channel, clamped to [0, 1], as compositor nodes; then the "Standard" view
    transform (the sRGB encoding, no look, exposure 0, gamma 1) and no dither, as wobble's PNG frames.
"""
import math

import bpy
from mathutils import Vector


def to_blender(v):
    """wobble (Y up) -> Blender (Z up): the OBJ importer's default mapping, (x, y, z) -> (x, -z, y)."""
    return Vector((v[0], -v[2], v[1]))


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


def material(m, load_image):
    mat = bpy.data.materials.new(m["name"])
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    out.name = "Material Output"
    out.target = "CYCLES"
    color = tuple(m["color"]) + (1.0,)

    base = None  # colour x texture, a socket; None: the colour alone
    if m.get("texture"):
        tex = nodes.new("ShaderNodeTexImage")
        tex.image = load_image(m["texture"])
        tex.image.colorspace_settings.name = "sRGB"
        tex.interpolation = "Linear"
        tex.extension = "REPEAT"
        uv = nodes.new("ShaderNodeTexCoord")
        links.new(uv.outputs["UV"], tex.inputs["Vector"])
        mul = nodes.new("ShaderNodeMixRGB")
        mul.blend_type = "MULTIPLY"
        mul.inputs["Fac"].default_value = 1.0
        mul.inputs["Color1"].default_value = color
        links.new(tex.outputs["Color"], mul.inputs["Color2"])
        base = mul.outputs["Color"]

    if m.get("dielectric"):  # sigma_a and sigma_s per metre
        g = {k: m[k] for k in ("ior", "roughness", "scatter_albedo", "print")}
        g.update(sigma_a=m["absorption"], sigma_s=float(m["scatter"]))
        gelatine(nodes, links, out, g, base or color)
        return mat
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Roughness"].default_value = 0.0  # Lambert
    coat = float(m.get("coat", 0.0))
    if coat <= 0:
        if base:
            links.new(base, diffuse.inputs["Color"])
        else:
            diffuse.inputs["Color"].default_value = color
        links.new(diffuse.outputs["BSDF"], out.inputs["Surface"])
        return mat

    # Schlick's Fresnel at n.wo: F = f0 + (1 - f0) (1 - |n.wo|)^5; Layer Weight's Facing (blend 0.5) is 1 - |n.wo|.
    f0 = ((m["ior"] - 1.0) / (m["ior"] + 1.0)) ** 2
    lw = nodes.new("ShaderNodeLayerWeight")
    lw.inputs["Blend"].default_value = 0.5
    pw = nodes.new("ShaderNodeMath")
    pw.operation = "POWER"
    links.new(lw.outputs["Facing"], pw.inputs[0])
    pw.inputs[1].default_value = 5.0
    fres = nodes.new("ShaderNodeMath")  # coat F = coat f0 + coat (1 - f0) m^5
    fres.operation = "MULTIPLY_ADD"
    links.new(pw.outputs[0], fres.inputs[0])
    fres.inputs[1].default_value = coat * (1.0 - f0)
    fres.inputs[2].default_value = coat * f0
    one_minus = nodes.new("ShaderNodeMath")
    one_minus.operation = "SUBTRACT"
    one_minus.inputs[0].default_value = 1.0
    links.new(fres.outputs[0], one_minus.inputs[1])
    dcol = nodes.new("ShaderNodeMixRGB")  # diffuse colour = base x (1 - coat F)
    dcol.blend_type = "MULTIPLY"
    dcol.inputs["Fac"].default_value = 1.0
    if base:
        links.new(base, dcol.inputs["Color1"])
    else:
        dcol.inputs["Color1"].default_value = color
    links.new(one_minus.outputs[0], dcol.inputs["Color2"])
    links.new(dcol.outputs["Color"], diffuse.inputs["Color"])
    glossy = nodes.new("ShaderNodeBsdfGlossy")
    glossy.distribution = "GGX"
    glossy.inputs["Roughness"].default_value = math.sqrt(max(float(m["roughness"]), 1e-3))
    links.new(fres.outputs[0], glossy.inputs["Color"])
    add = nodes.new("ShaderNodeAddShader")
    links.new(diffuse.outputs["BSDF"], add.inputs[0])
    links.new(glossy.outputs["BSDF"], add.inputs[1])
    links.new(add.outputs["Shader"], out.inputs["Surface"])
    return mat


def world(scene, sky, env, bounces):
    w = bpy.data.worlds.new("environment" if env else "sky")
    scene.world = w
    w.use_nodes = True
    nodes, links = w.node_tree.nodes, w.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputWorld")
    out.target = "CYCLES"
    bg = nodes.new("ShaderNodeBackground")
    bg.name = "Background"
    bg.inputs["Strength"].default_value = 1.0
    links.new(bg.outputs["Background"], out.inputs["Surface"])

    def node(kind, op, *inputs, clamp=False):
        n = nodes.new(kind)
        n.operation = op
        if kind == "ShaderNodeMath":
            n.use_clamp = clamp
        for k, v in enumerate(inputs):
            if isinstance(v, bpy.types.NodeSocket):
                links.new(v, n.inputs[k])
            else:
                n.inputs[k].default_value = v
        return n

    def scale(vector, factor):
        n = node("ShaderNodeVectorMath", "SCALE", vector)
        links.new(factor, n.inputs["Scale"])
        return n.outputs["Vector"]

    if env:
        bg.inputs["Strength"].default_value = float(env["strength"])
        colour = environment(nodes, links, env)
    else:
        coord = nodes.new("ShaderNodeTexCoord")  # in the world, Generated is the ray's direction (unit)
        e = node("ShaderNodeVectorMath", "DOT_PRODUCT", coord.outputs["Generated"],
                 tuple(to_blender(sky["up"]).normalized())).outputs["Value"]
        up = node("ShaderNodeMath", "SQRT", node("ShaderNodeMath", "MAXIMUM", e, 0.0).outputs[0]).outputs[0]
        down = node("ShaderNodeMath", "SQRT",
                    node("ShaderNodeMath", "MULTIPLY", e, -4.0, clamp=True).outputs[0]).outputs[0]
        zenith, horizon, ground = (Vector(sky[k]) for k in ("zenith", "horizon", "ground"))
        gradient = node("ShaderNodeVectorMath", "ADD", scale(tuple(zenith - horizon), up),
                        scale(tuple(ground - horizon), down)).outputs["Vector"]
        colour = node("ShaderNodeVectorMath", "ADD", gradient, tuple(horizon)).outputs["Vector"]
    if bounces is not None:
        lp = nodes.new("ShaderNodeLightPath")
        depth = node("ShaderNodeMath", "SUBTRACT", lp.outputs["Ray Depth"], lp.outputs["Transmission Depth"])
        keep = node("ShaderNodeMath", "LESS_THAN", depth.outputs[0], bounces + 1.5)
        colour = scale(colour, keep.outputs[0])
    links.new(colour, bg.inputs["Color"])
    return w


def sun(scene, name, s):
    data = bpy.data.lights.new(name, type="SUN")
    irradiance = [float(c) for c in s["irradiance"]]
    peak = max(irradiance)
    data.energy = peak
    data.color = [c / peak for c in irradiance] if peak > 0 else (1.0, 1.0, 1.0)
    data.angle = math.radians(2.0 * float(s["angular_radius_deg"]))
    data.cycles.cast_shadow = True
    data.cycles.use_multiple_importance_sampling = True
    obj = bpy.data.objects.new(name, data)
    scene.collection.objects.link(obj)
    obj.rotation_mode = "QUATERNION"  # the light shines along its local -Z: local +Z points towards the sun
    obj.rotation_quaternion = to_blender(s["direction"]).normalized().to_track_quat("Z", "Y")
    obj.visible_camera = False
    return obj


def light_paths(scene, bounces, dielectric, clamp_indirect=0.0):
    c = scene.cycles
    c.max_bounces = bounces
    c.diffuse_bounces = bounces
    c.glossy_bounces = bounces
    c.transmission_bounces = 0
    c.volume_bounces = 0
    c.transparent_max_bounces = 0
    if dielectric:  # gelatine: wobble's 64 interfaces and 128 scattering events on top of its bounces
        c.max_bounces = bounces + 64
        c.transmission_bounces = 64
        c.volume_bounces = 128
    c.caustics_reflective = True
    c.caustics_refractive = bool(dielectric)
    c.blur_glossy = 0.0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = clamp_indirect  # wobble's render.clamp_indirect (0: off), as in its own picture
    c.light_sampling_threshold = 0.0
    c.filter_type = "BOX"  # wobble's pixel filter is a 1-pixel box
    c.filter_width = 1.0
    c.film_exposure = 1.0


def shadow_caustics(casters, receivers, lights):
    for obj in casters:
        obj.cycles.is_caustics_caster = True
    for obj in receivers:
        obj.cycles.is_caustics_receiver = True
    for obj in lights:
        obj.data.cycles.is_caustics_light = True


def tone_map(scene, exposure):
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.dither_intensity = 0.0
    scene.render.use_compositing = True
    scene.use_nodes = True
    tree = scene.node_tree
    nodes, links = tree.nodes, tree.links
    nodes.clear()
    layers = nodes.new("CompositorNodeRLayers")
    split = nodes.new("CompositorNodeSeparateColor")
    join = nodes.new("CompositorNodeCombineColor")
    links.new(layers.outputs["Image"], split.inputs["Image"])

    def op(kind, a, b, clamp=False):
        n = nodes.new("CompositorNodeMath")
        n.operation = kind
        n.use_clamp = clamp
        for k, v in enumerate((a, b)):
            if isinstance(v, bpy.types.NodeSocket):
                links.new(v, n.inputs[k])
            else:
                n.inputs[k].default_value = v
        return n.outputs[0]

    for k, channel in enumerate(("Red", "Green", "Blue")):
        x = op("MULTIPLY", op("MAXIMUM", split.outputs[channel], 0.0), 2.0 ** exposure)
        numerator = op("MULTIPLY", x, op("ADD", op("MULTIPLY", x, 2.51), 0.03))
        denominator = op("ADD", op("MULTIPLY", x, op("ADD", op("MULTIPLY", x, 2.43), 0.59)), 0.14)
        links.new(op("DIVIDE", numerator, denominator, clamp=True), join.inputs[k])
    composite = nodes.new("CompositorNodeComposite")
    links.new(join.outputs["Image"], composite.inputs["Image"])
    links.new(layers.outputs["Alpha"], join.inputs["Alpha"])
