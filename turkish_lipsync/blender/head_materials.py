"""Materials of the default head: skin, lips, brows, eyes, mouth, built as node trees from MPFB's data.

The skin follows MPFB's enhanced skin (a Principled BSDF with coat, subsurface and noise pores) and takes
MPFB's CC0 masks in MakeHuman's UV layout for the lips, the eyelids and the inside of the mouth; the brows
are a mask of painted hairs on a UV map of their own. The eyes are procedural, as MPFB's are, but from the
angle to the eye's axis in its undeformed coordinates rather than from UVs (MakeHuman's low-poly eyeballs
have none fit for an iris), so iris and pupil turn with the eyeball's keys. Every node used exists in
Cycles and EEVEE from Blender 4.2 on; the viewport colour is set too, for Workbench.
"""

from __future__ import annotations

import bpy
import numpy as np

from ..core.faces.reference import ReferenceHead, reference_materials, reference_texture
from . import compat

MATERIAL_PREFIX = "TR_"
EYEBROW_UV = "Eyebrows"
EYEBROW_IMAGE = "TR_eyebrows"
HAIR_ATTRIBUTE = "TR_hair"


def _new_material(name: str) -> tuple[bpy.types.Material, bpy.types.NodeTree, bpy.types.Node]:
    """An empty material with a Principled BSDF wired to the output."""
    material = bpy.data.materials.new(MATERIAL_PREFIX + name)
    compat.enable_material_nodes(material)
    tree = material.node_tree
    output = next(node for node in tree.nodes if node.type == "OUTPUT_MATERIAL")
    shader = next((node for node in tree.nodes if node.type == "BSDF_PRINCIPLED"), None)
    if shader is None:
        shader = tree.nodes.new("ShaderNodeBsdfPrincipled")
        tree.links.new(shader.outputs["BSDF"], output.inputs["Surface"])
    return material, tree, shader


def _rgba(color) -> tuple[float, float, float, float]:
    return (*(float(value) for value in color[:3]), 1.0)


def _set_surface(material: bpy.types.Material, shader: bpy.types.Node, settings: dict, color) -> None:
    """Roughness, coat and subsurface of a settings table, and the viewport colour for Workbench."""
    shader.inputs["Roughness"].default_value = float(settings.get("roughness", 0.5))
    shader.inputs["Coat Weight"].default_value = float(settings.get("coat", 0.0))
    if "coat_roughness" in settings:
        shader.inputs["Coat Roughness"].default_value = float(settings["coat_roughness"])
    if "subsurface" in settings:
        shader.inputs["Subsurface Weight"].default_value = float(settings["subsurface"])
        shader.inputs["Subsurface Radius"].default_value = tuple(
            settings.get("subsurface_radius", (1.0, 0.2, 0.1))
        )
        shader.inputs["Subsurface Scale"].default_value = float(settings.get("subsurface_scale", 0.004))
        shader.subsurface_method = "BURLEY"  # cheaper than random walk, and alike at a face's scale
    material.diffuse_color = _rgba(color)
    material.roughness = float(settings.get("roughness", 0.5))


def plain_material(name: str) -> bpy.types.Material:
    """A one-colour material of [materials.<name>] (teeth, tongue), reused when it exists."""
    existing = bpy.data.materials.get(MATERIAL_PREFIX + name)
    if existing is not None:
        return existing
    settings = reference_materials()[name]
    material, _, shader = _new_material(name)
    shader.inputs["Base Color"].default_value = _rgba(settings["color"])
    _set_surface(material, shader, settings, settings["color"])
    return material


def eyelash_material(uv_map: str) -> bpy.types.Material:
    """Dark lashes drawn on MakeHuman's lash shells: a lash line at the lid, strands thinning to the tips.

    The shells' UVs run along the lid (u) and from root to tip (v: one range per shell, see the settings).
    """
    existing = bpy.data.materials.get(MATERIAL_PREFIX + "eyelashes")
    if existing is not None:
        return existing
    settings = reference_materials()["eyelashes"]
    material, tree, shader = _new_material("eyelashes")
    shader.inputs["Base Color"].default_value = _rgba(settings["color"])
    _set_surface(material, shader, settings, settings["color"])
    coordinates = tree.nodes.new("ShaderNodeUVMap")
    coordinates.uv_map = uv_map
    uv = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(coordinates.outputs["UV"], uv.inputs[0])
    (upper_root, upper_tip), (lower_root, lower_tip) = settings["upper_v"], settings["lower_v"]
    is_lower = _math(tree, "GREATER_THAN", uv.outputs["Y"], (upper_tip + lower_tip) / 2)
    along = _mix(
        tree, "FLOAT", is_lower, _ramp(tree, uv.outputs["Y"], upper_root, upper_tip),
        _ramp(tree, uv.outputs["Y"], lower_root, lower_tip),
    )  # fmt: skip
    strands = tree.nodes.new("ShaderNodeTexWave")
    strands.wave_type = "BANDS"
    strands.bands_direction = "X"
    strands.inputs["Scale"].default_value = float(settings["strands"])
    strands.inputs["Distortion"].default_value = 2.0
    tree.links.new(coordinates.outputs["UV"], strands.inputs["Vector"])
    # Strands cover less toward the tips and end before the shell does; the lash line at the root is solid.
    coverage = _math(tree, "MULTIPLY", float(settings["coverage"]), _math(tree, "SUBTRACT", 1.0, along))
    hairs = _math(tree, "LESS_THAN", strands.outputs["Fac"], coverage)
    hairs = _math(tree, "MULTIPLY", hairs, _smooth_below(tree, along, float(settings["length"]), 0.2))
    opacity = _mix(tree, "FLOAT", is_lower, float(settings["opacity"]), float(settings["lower_opacity"]))
    alpha = _math(tree, "MAXIMUM", hairs, _smooth_below(tree, along, float(settings["line"]), 0.1))
    tree.links.new(_math(tree, "MULTIPLY", alpha, opacity), shader.inputs["Alpha"])
    if hasattr(material, "surface_render_method"):
        material.surface_render_method = "DITHERED"  # EEVEE: alpha without sorting
    return material


def _ramp(tree, value, start: float, end: float) -> bpy.types.NodeSocket:
    """0 at start, 1 at end (either way round), clamped."""
    node = tree.nodes.new("ShaderNodeMapRange")
    node.clamp = True
    tree.links.new(value, node.inputs["Value"])
    node.inputs["From Min"].default_value = start
    node.inputs["From Max"].default_value = end
    return node.outputs["Result"]


def _mask_image(name: str) -> bpy.types.Image:
    """An MPFB mask texture, packed so a saved .blend keeps it."""
    image = bpy.data.images.get(MATERIAL_PREFIX + name)
    if image is None:
        image = bpy.data.images.load(str(reference_texture(name)))
        image.name = MATERIAL_PREFIX + name
        image.pack()
    image.colorspace_settings.name = "Non-Color"
    return image


def _eyebrow_image(reference: ReferenceHead) -> bpy.types.Image:
    image = bpy.data.images.get(EYEBROW_IMAGE)
    if image is None:
        rows, columns = reference.eyebrow_mask.shape
        image = bpy.data.images.new(EYEBROW_IMAGE, columns, rows, alpha=False, is_data=True)
        value = reference.eyebrow_mask.astype(np.float32) / 255.0
        pixels = np.repeat(value[:, :, None], 4, axis=2)
        pixels[:, :, 3] = 1.0
        image.pixels.foreach_set(pixels.ravel())
        image.pack()
    return image


def _attribute(tree, name: str) -> bpy.types.NodeSocket:
    node = tree.nodes.new("ShaderNodeAttribute")
    node.attribute_name = name
    return node.outputs["Fac"]


def _hair_strands(tree, uv_map: str) -> bpy.types.NodeSocket:
    """0.75..1: fine variation that makes painted hair read as short hairs rather than paint."""
    coordinates = tree.nodes.new("ShaderNodeUVMap")
    coordinates.uv_map = uv_map
    noise = tree.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 4000.0
    noise.inputs["Detail"].default_value = 0.0
    tree.links.new(coordinates.outputs["UV"], noise.inputs["Vector"])
    return _mix(tree, "FLOAT", noise.outputs["Fac"], 0.75, 1.0)


def _texture(tree, image: bpy.types.Image, uv_map: str, clip: bool = False) -> bpy.types.NodeSocket:
    """The red channel of an image looked up through a UV map: a mask in 0..1."""
    coordinates = tree.nodes.new("ShaderNodeUVMap")
    coordinates.uv_map = uv_map
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.extension = "CLIP" if clip else "EXTEND"
    tree.links.new(coordinates.outputs["UV"], texture.inputs["Vector"])
    return texture.outputs["Color"]


def _mix(tree, data_type: str, factor, first, second) -> bpy.types.NodeSocket:
    """Mix node (Blender 3.4+): first where factor is 0, second where 1; sockets or constant values."""
    node = tree.nodes.new("ShaderNodeMix")
    node.data_type = data_type
    node.clamp_factor = True
    index = {"FLOAT": (2, 3, 0), "RGBA": (6, 7, 2)}[data_type]
    _connect(
        tree, ((node.inputs[0], factor), (node.inputs[index[0]], first), (node.inputs[index[1]], second))
    )
    return node.outputs[index[2]]


def _connect(tree, pairs) -> None:
    """Link each (input socket, value) pair: a socket value is linked, a constant is set."""
    for socket, value in pairs:
        if isinstance(value, bpy.types.NodeSocket):
            tree.links.new(value, socket)
        else:
            socket.default_value = value


def _math(tree, operation: str, first, second=0.0) -> bpy.types.NodeSocket:
    node = tree.nodes.new("ShaderNodeMath")
    node.operation = operation
    _connect(tree, ((node.inputs[0], first), (node.inputs[1], second)))
    return node.outputs[0]


def skin_material(
    reference: ReferenceHead, uv_map: str, tone=None, tone_name: str = ""
) -> bpy.types.Material:
    """Skin with lips, eyelids, inner mouth, painted eyebrows and short hair; in another skin and hair tone
    (a conversation's tones: core/scene/tables.py's Tone) where one is given, named after it."""
    name = f"skin {tone_name}" if tone is not None else "skin"
    existing = bpy.data.materials.get(MATERIAL_PREFIX + name)
    if existing is not None:
        return existing
    tables = reference_materials() if tone is None else _toned(reference_materials(), tone)
    skin = tables["skin"]
    material, tree, shader = _new_material(name)
    color = _rgba(skin["color"])
    # Surface values each layer may change, and the Principled inputs they drive.
    surface = {"roughness": float(skin["roughness"]), "coat": float(skin["coat"]), "specular": 0.5}
    inputs = {"roughness": "Roughness", "coat": "Coat Weight", "specular": "Specular IOR Level"}
    masks = {name: _texture(tree, _mask_image(name), uv_map) for name in ("lips", "eyelids", "inside_mouth")}
    masks["eyebrows"] = _texture(tree, _eyebrow_image(reference), EYEBROW_UV, clip=True)
    masks["hair"] = _math(tree, "MULTIPLY", _attribute(tree, HAIR_ATTRIBUTE), _hair_strands(tree, uv_map))
    for layer, mask in masks.items():
        settings = tables[layer]
        factor = _math(tree, "MULTIPLY", mask, float(settings.get("strength", 1.0)))
        color = _mix(tree, "RGBA", factor, color, _rgba(settings["color"]))
        for name in inputs:
            if name in settings:
                surface[name] = _mix(tree, "FLOAT", factor, surface[name], float(settings[name]))
    tree.links.new(color, shader.inputs["Base Color"])
    _set_surface(material, shader, skin, skin["color"])
    for name, value in surface.items():
        _connect(tree, ((shader.inputs[inputs[name]], value),))

    # Pores: MPFB's noise bump over the UV layout.
    coordinates = tree.nodes.new("ShaderNodeUVMap")
    coordinates.uv_map = uv_map
    noise = tree.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = float(skin["pore_scale"])
    noise.inputs["Detail"].default_value = 2.0
    tree.links.new(coordinates.outputs["UV"], noise.inputs["Vector"])
    bump = tree.nodes.new("ShaderNodeBump")
    bump.inputs["Strength"].default_value = float(skin["pore_strength"])
    bump.inputs["Distance"].default_value = 0.0002
    tree.links.new(noise.outputs["Fac"], bump.inputs["Height"])
    tree.links.new(bump.outputs["Normal"], shader.inputs["Normal"])
    return material


def _toned(tables: dict, tone) -> dict:
    """The head's material settings in another tone: the skin's colour, and the lips and lids as much
    darker or lighter as the skin; the hair's and brows' colour."""
    toned = {name: dict(settings) for name, settings in tables.items()}
    ratio = np.asarray(tone.skin) / np.maximum(np.asarray(tables["skin"]["color"], np.float64), 1e-6)
    toned["skin"]["color"] = list(tone.skin)
    for part in ("lips", "eyelids"):
        toned[part]["color"] = list(np.clip(np.asarray(tables[part]["color"]) * ratio, 0.0, 1.0))
    for part in ("hair", "eyebrows"):
        toned[part]["color"] = list(tone.hair)
    return toned


def eye_material() -> bpy.types.Material:
    """Sclera, iris and pupil by the angle to the eye's forward axis (-Y), in undeformed coordinates."""
    existing = bpy.data.materials.get(MATERIAL_PREFIX + "eye")
    if existing is not None:
        return existing
    eye = reference_materials()["eye"]
    material, tree, shader = _new_material("eye")
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    centred = tree.nodes.new("ShaderNodeVectorMath")
    centred.operation = "SUBTRACT"
    centred.inputs[1].default_value = (0.5, 0.5, 0.5)
    tree.links.new(coordinates.outputs["Generated"], centred.inputs[0])
    direction = tree.nodes.new("ShaderNodeVectorMath")
    direction.operation = "NORMALIZE"
    tree.links.new(centred.outputs["Vector"], direction.inputs[0])
    axes = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(direction.outputs["Vector"], axes.inputs[0])
    # Distance from the axis (the sine of the angle), and whether the point is on the front half.
    across = _math(tree, "SQRT", _math(tree, "ADD", _math(tree, "POWER", axes.outputs["X"], 2.0),
                                       _math(tree, "POWER", axes.outputs["Z"], 2.0)))  # fmt: skip
    front = _math(tree, "LESS_THAN", axes.outputs["Y"], 0.0)
    iris_radius, pupil_radius = float(eye["iris_radius"]), float(eye["pupil_radius"])
    iris = _math(tree, "MULTIPLY", front, _smooth_below(tree, across, iris_radius, 0.03))
    pupil = _math(tree, "MULTIPLY", front, _smooth_below(tree, across, pupil_radius, 0.02))
    # The iris darkens toward its rim, with radial fibres.
    fibres = tree.nodes.new("ShaderNodeTexNoise")
    fibres.inputs["Scale"].default_value = 18.0
    fibres.inputs["Detail"].default_value = 4.0
    tree.links.new(direction.outputs["Vector"], fibres.inputs["Vector"])
    rim = _math(tree, "MULTIPLY", _math(tree, "DIVIDE", across, iris_radius), fibres.outputs["Fac"])
    iris_color = _mix(
        tree, "RGBA", _math(tree, "POWER", rim, 0.7), _rgba(eye["iris_inner"]), _rgba(eye["iris_outer"])
    )
    color = _mix(tree, "RGBA", iris, _rgba(eye["sclera"]), iris_color)
    color = _mix(tree, "RGBA", pupil, color, _rgba(eye["pupil"]))
    tree.links.new(color, shader.inputs["Base Color"])
    _set_surface(material, shader, eye, eye["sclera"])
    return material


def _smooth_below(tree, value, edge: float, softness: float) -> bpy.types.NodeSocket:
    """1 where value < edge, 0 above it, blended over the softness."""
    node = tree.nodes.new("ShaderNodeMapRange")
    node.interpolation_type = "SMOOTHSTEP"
    node.clamp = True
    tree.links.new(value, node.inputs["Value"])
    node.inputs["From Min"].default_value = edge - softness / 2
    node.inputs["From Max"].default_value = edge + softness / 2
    node.inputs["To Min"].default_value = 1.0
    node.inputs["To Max"].default_value = 0.0
    return node.outputs["Result"]
