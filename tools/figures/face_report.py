"""Build the keys on a head and report how its face moves: one labelled PNG and a table of figures.

    .venv/bin/python -m tools.figures.face_report [--head PATH] [--out DIR] [--object NAME] [--keep-keys]
        [--source transfer]

The head's own shape keys are kept aside and removed first (so the keys come by transfer, as for a head
without keys); where the head had an artist's comparable key (shapekeys/artist_comparisons.toml) the
transferred one is compared with it. The PNG (Cycles on the CPU, small tiles, a couple of minutes) shows
front and three-quarter views of neutral, jawOpen, a, o, u, bpa, fvae, blink and the six emotions.
Figures, in mm where a length: lip aperture at the midline, the bilabial lip gap, the eyelid gap under
the blink, the blink's creases (edges of the seen skin above the upper lid it folds by more than 60
degrees), left-right symmetry (1 = mirror-symmetric), edge stretch p99.9 (deformed / rest length).
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np

from lab.kit.heads import kit_heads, millimetres_per_unit, strip_keys, world_key_deltas
from tools.figures.contact_sheet import _aim, _emission_material
from turkish_lipsync.blender import compat, heads, mesh, shapekeys
from turkish_lipsync.blender.landmarks import read_landmark_markers, show_landmark_markers
from turkish_lipsync.core.base.data import load_table
from turkish_lipsync.core.base.errors import LipSyncError
from turkish_lipsync.core.base.model import BLINK_KEYS, EMOTIONS, emotion_key_name, viseme_key_name
from turkish_lipsync.core.faces.arkit_names import ARKIT_UNITS
from turkish_lipsync.core.faces.closest import nearest_vertices
from turkish_lipsync.core.faces.head_parts import find_parts
from turkish_lipsync.core.faces.landmarks import face_frame
from turkish_lipsync.core.faces.measure import FaceMeasure, displacement_cosine, piece_motion

# Picture rows: label -> the keys set to 1 (on the head and its parts).
ROWS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("neutral", ()),
    ("jawOpen", ("jawOpen",)),
    *((name, (viseme_key_name(name),)) for name in ("a", "o", "u", "bpa", "fvae")),
    ("blink", BLINK_KEYS),
    *((name, (emotion_key_name(name),)) for name in EMOTIONS),
)
# Keys measured in the table, beyond the rows: the ARKit units the cosines are about, more visemes.
MEASURED = (
    "jawOpen",
    "eyeBlinkLeft",
    "mouthPucker",
    "mouthSmileLeft",
    *(viseme_key_name(name) for name in ("a", "e", "o", "oi", "u", "bpa", "ma", "fvae")),
    BLINK_KEYS[0],
    *(emotion_key_name(name) for name in EMOTIONS),
)
BILABIALS = tuple(viseme_key_name(name) for name in ("bpa", "bpe", "bpo", "ma", "me", "mo"))
# The parts' close-ups: the left eye open and closed, the mouth at rest and open (lashes with the lid,
# lower teeth and gums with the jaw).
CLOSE_UPS: tuple[tuple[str, tuple[str, ...], str], ...] = (
    ("eye", (), "eye"),
    ("eye: eyeBlinkLeft", ("eyeBlinkLeft",), "eye"),
    ("mouth", (), "mouth"),
    ("mouth: jawOpen", ("jawOpen",), "mouth"),
)
THREE_QUARTER_DEGREES = 40.0
VIEW_HEIGHT = 2.2  # the picture's height in eyes-to-chin spans
KEYS_PER_ROW = 4  # each key shows front and three-quarter side by side
BACKGROUND = (0.35, 0.37, 0.4)


def measure(
    face: FaceMeasure, built: dict[str, np.ndarray], artist: dict[str, np.ndarray], millimetres: float
) -> list[dict]:
    """One row of figures per measured key the build wrote (lengths times `millimetres` per unit)."""
    comparisons = load_table("artist_comparisons")["compare"]
    # Every ARKit unit the head's artist also made (by its own name, or the table's) is compared too.
    compared_units = [
        unit
        for unit in ARKIT_UNITS
        if unit not in MEASURED and any(name in artist for name in _artist_names(unit, comparisons))
    ]
    rows = []
    for key in (*MEASURED, *compared_units):
        if key not in built:
            continue
        deltas = built[key]
        row = {
            "key": key,
            "aperture_mm": millimetres * face.lip_aperture(deltas),
            "stretch": face.stretch(deltas),
            "symmetry": face.symmetry(deltas),
        }
        if key in BILABIALS:
            row["lip_gap_mm"] = max(row["aperture_mm"], 0.0)
        if key in (BLINK_KEYS[0], "eyeBlinkLeft"):
            row["lid_gap_mm"] = millimetres * face.lid_gap(deltas, "left")
            row["creases"] = face.lid_creases(deltas, "left")
        theirs = next((name for name in _artist_names(key, comparisons) if name in artist), None)
        if theirs is not None:
            row["artist_key"] = theirs
            row["cosine"] = displacement_cosine(deltas, artist[theirs])
            row["artist_stretch"] = face.stretch(artist[theirs])
            row["artist_aperture_mm"] = millimetres * face.lip_aperture(artist[theirs])
            if "lid_gap_mm" in row:
                row["artist_lid_gap_mm"] = millimetres * face.lid_gap(artist[theirs], "left")
                row["artist_creases"] = face.lid_creases(artist[theirs], "left")
        rows.append(row)
    return rows


def _artist_names(key: str, comparisons) -> tuple[str, ...]:
    """The artist key names that show the same shape as our key: the table's, else an ARKit unit's own."""
    if key in comparisons:
        return tuple(comparisons[key])
    return (key, key[0].upper() + key[1:]) if key in ARKIT_UNITS else ()


def print_table(rows: list[dict], rest_aperture: float, rest_lid_gap: float) -> None:
    print(f"at rest: lip aperture {rest_aperture:.1f} mm, left eyelid gap {rest_lid_gap:.1f} mm")
    print(
        f"{'key':22s} {'aperture':>8s} {'lip gap':>7s} {'lid gap':>7s} {'crease':>6s} {'symm':>5s}"
        f" {'stretch':>7s}"
        f"  {'artist key':22s} {'cosine':>6s} {'art.str':>7s} {'art.ap':>6s} {'art.lid':>7s} {'art.cr':>6s}"
    )

    def cell(row, name, form):
        return format(row[name], form) if name in row else "-"

    for row in rows:
        print(
            f"{row['key']:22s} {cell(row, 'aperture_mm', '8.1f'):>8s} {cell(row, 'lip_gap_mm', '7.1f'):>7s} "
            f"{cell(row, 'lid_gap_mm', '7.1f'):>7s} {cell(row, 'creases', '6.0f'):>6s} "
            f"{row['symmetry']:5.2f} {row['stretch']:7.1f}  "
            f"{row.get('artist_key', '-'):22s} {cell(row, 'cosine', '6.2f'):>6s} "
            f"{cell(row, 'artist_stretch', '7.1f'):>7s} {cell(row, 'artist_aperture_mm', '6.1f'):>6s} "
            f"{cell(row, 'artist_lid_gap_mm', '7.1f'):>7s} {cell(row, 'artist_creases', '6.0f'):>6s}"
        )
    cosines = [row["cosine"] for row in rows if "cosine" in row]
    if cosines:
        print(f"mean cosine against the artist's keys: {np.mean(cosines):.2f} over {len(cosines)} keys")


# What each kind of piece does under jawOpen and a blink: goes with the skin it touches, or stays.
PART_KEYS = ("jawOpen", "eyeBlinkLeft")
STAYS = {
    ("upper_teeth", "jawOpen"),
    ("eyeball", "eyeBlinkLeft"),
    ("cornea", "eyeBlinkLeft"),
    ("eyeball", "jawOpen"),
    ("cornea", "jawOpen"),
}


def part_rows(objects, landmarks, built: dict, artist: dict, millimetres: float) -> list[dict]:
    """Per piece of the head and its parts (found as a build finds them): under jawOpen and the blink,
    its share of our motion (and of the artist's, with the cosine, where the head had such a key), how
    far it moves against the skin it touches (mm, mean), and whether it does what it should: go with
    that skin (moving 0.5 to 2 times as far), or stay (the upper teeth under jawOpen, eyes under both)."""
    vertices = np.concatenate([mesh.world_rest_coordinates(obj) for obj in objects]).astype(np.float64)
    offsets = np.cumsum([0] + [len(obj.data.vertices) for obj in objects])
    triangles = np.concatenate(
        [mesh.triangles(obj) + offset for obj, offset in zip(objects, offsets, strict=False)]
    )
    parts = find_parts(vertices, triangles, landmarks)
    pieces: dict[str, np.ndarray] = {}
    for piece in parts.pieces:
        name = f"{piece.kind} {piece.side}".strip()
        pieces[name] = np.concatenate((pieces.get(name, np.empty(0, np.int64)), piece.indices))
    comparisons = load_table("artist_comparisons")["compare"]
    eye_width = float(np.linalg.norm(landmarks["eye_outer_left"] - landmarks["eye_inner_left"]))
    rows = []
    for key in PART_KEYS:
        ours = np.concatenate(
            [built[obj.name].get(key, np.zeros((len(obj.data.vertices), 3))) for obj in objects]
        )
        theirs = next(
            (name for name in _artist_names(key, comparisons) if name in artist[objects[0].name]), None
        )
        truth = None
        if theirs is not None:
            truth = np.concatenate(
                [artist[obj.name].get(theirs, np.zeros((len(obj.data.vertices), 3))) for obj in objects]
            )
        for name, figures in piece_motion(pieces, ours, truth).items():
            indices = pieces[name]
            near, _ = nearest_vertices(vertices[indices], vertices[parts.skin], 0.3 * eye_width)
            touched = parts.skin[near[near >= 0]]
            moves = float(np.linalg.norm(ours[indices], axis=1).mean())
            skin = float(np.linalg.norm(ours[touched], axis=1).mean()) if len(touched) else 0.0
            kind = name.split()[0]
            if (kind, key) in STAYS:
                follows = moves < 1e-4 * eye_width
            else:
                follows = skin < 1e-4 * eye_width or 0.5 <= moves / skin <= 2.0
            rows.append(
                {
                    "key": key,
                    "piece": name,
                    "vertices": len(indices),
                    **figures,
                    "artist_key": theirs,
                    "moves_mm": millimetres * moves,
                    "skin_mm": millimetres * skin,
                    "follows": follows,
                }
            )
    return rows


def print_parts(rows: list[dict]) -> None:
    print(
        f"{'key':13s} {'piece':20s} {'verts':>6s} {'ours':>5s} {'moves':>6s} {'skin':>6s} {'follows':>7s}"
        f"  {'artist':>6s} {'cosine':>6s}"
    )
    for row in rows:
        share = f"{row['share']:6.2f}" if "share" in row else "     -"
        cosine = f"{row['cosine']:6.2f}" if "cosine" in row else "     -"
        print(
            f"{row['key']:13s} {row['piece']:20s} {row['vertices']:6d} {row['ours']:5.2f} "
            f"{row['moves_mm']:6.1f} {row['skin_mm']:6.1f} {'yes' if row['follows'] else 'NO':>7s}  "
            f"{share} {cosine}"
        )


# ---------------------------------------------------------------- the picture


def setup_scene(landmarks, tile: int, samples: int) -> tuple[bpy.types.Object, bpy.types.Object]:
    """An orthographic camera on the face and a label under it; returns (camera, label)."""
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.render.resolution_x = tile
    scene.render.resolution_y = tile
    world = bpy.data.worlds.new("TR_FaceReportWorld")
    world.color = BACKGROUND
    scene.world = world
    _, axes = face_frame(landmarks)
    view = VIEW_HEIGHT * eyes_and_chin(landmarks)[2]
    camera_data = bpy.data.cameras.new("TR_FaceReportCamera")
    camera_data.type = "ORTHO"
    camera_data.ortho_scale = view
    camera_data.clip_start = 0.01 * view  # the label bar rides close in front of a close-up's camera
    camera_data.clip_end = 100 * view
    camera = bpy.data.objects.new("TR_FaceReportCamera", camera_data)
    scene.collection.objects.link(camera)
    scene.camera = camera
    for name, energy, offset in (("key", 4.0, (-1.0, -2.0, 1.6)), ("fill", 1.5, (1.5, -2.0, 0.2))):
        light_data = bpy.data.lights.new(f"TR_FaceReport_{name}", "SUN")
        light_data.energy = energy
        light = bpy.data.objects.new(light_data.name, light_data)
        light.rotation_euler = _aim(-(axes @ np.array(offset)))
        scene.collection.objects.link(light)
    # A dark bar along the bottom of the picture with the key's name on it, both riding on the camera.
    bar_mesh = bpy.data.meshes.new("TR_FaceReportBar")
    half = view / 2
    bar_mesh.from_pydata(
        [(-half, -half, 0), (half, -half, 0), (half, -0.8 * half, 0), (-half, -0.8 * half, 0)],
        [],
        [(0, 1, 2, 3)],
    )
    bar_mesh.materials.append(_emission_material("TR_FaceReportBar", (0.0, 0.0, 0.0), 1.0))
    bar = bpy.data.objects.new("TR_FaceReportBar", bar_mesh)
    bar.parent = camera
    bar.location = (0.0, 0.0, -2.0 * view)  # camera space: between the camera and the face
    scene.collection.objects.link(bar)
    label_data = bpy.data.curves.new("TR_FaceReportLabel", "FONT")
    label_data.size = 0.15 * half
    label_data.align_x = "CENTER"
    label_data.align_y = "CENTER"
    label_data.materials.append(_emission_material("TR_FaceReportLabel", (1.0, 0.92, 0.45), 1.0))
    label = bpy.data.objects.new("TR_FaceReportLabel", label_data)
    label.parent = camera
    label.location = (0.0, -0.9 * half, -1.99 * view)
    scene.collection.objects.link(label)
    return camera, label


def eyes_and_chin(landmarks) -> tuple[np.ndarray, np.ndarray, float]:
    """(midpoint of the eye corners, chin, their distance): the span the pictures frame."""
    eyes = np.mean(
        [landmarks[f"eye_{end}_{side}"] for end in ("inner", "outer") for side in ("left", "right")], 0
    )
    return eyes, np.asarray(landmarks["chin"], np.float64), float(np.linalg.norm(eyes - landmarks["chin"]))


def framings(landmarks) -> dict[str, tuple[np.ndarray, float]]:
    """(centre, the picture's height) of each framing: the face, a close-up of the left eye, of the mouth."""
    _, axes = face_frame(landmarks)
    eyes, chin, span = eyes_and_chin(landmarks)
    # From a little below the chin (the label bar covers the bottom) to above the brows.
    face = chin + (0.5 * VIEW_HEIGHT - 0.45) * span * axes[:, 2]
    eye = 0.5 * (landmarks["eye_inner_left"] + landmarks["eye_outer_left"])
    eye_width = float(np.linalg.norm(landmarks["eye_outer_left"] - landmarks["eye_inner_left"]))
    mouth = 0.5 * (landmarks["mouth_corner_left"] + landmarks["mouth_corner_right"])
    mouth_width = float(np.linalg.norm(landmarks["mouth_corner_left"] - landmarks["mouth_corner_right"]))
    return {
        "face": (face, VIEW_HEIGHT * span),
        # A little lower than the eye and the mouth: the label bar covers the bottom tenth.
        "eye": (eye - 0.2 * eye_width * axes[:, 2], 2.4 * eye_width),
        "mouth": (mouth - 0.35 * mouth_width * axes[:, 2], 2.0 * mouth_width),
    }


def place_camera(camera: bpy.types.Object, landmarks, degrees: float, framing: str = "face") -> None:
    """Look at a framing from the front turned by degrees toward the face's left; the camera's scale
    carries the label bar to the framing's size."""
    from mathutils import Matrix, Vector

    _, axes = face_frame(landmarks)
    across, back, up = axes.T
    centre, size = framings(landmarks)[framing]
    view = framings(landmarks)["face"][1]
    camera.data.ortho_scale = size
    angle = math.radians(degrees)
    toward = -back * math.cos(angle) + across * math.sin(angle)  # from the face to the camera
    position = centre + toward * 5 * view
    forward = -toward
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    rotation = Matrix(np.stack((right, true_up, -forward), axis=1).tolist())
    scale = Matrix.Diagonal(Vector((size / view,) * 3)).to_4x4()
    camera.matrix_world = Matrix.Translation(Vector(position.tolist())) @ rotation.to_4x4() @ scale


# Colours of the pieces in the close-ups, for heads without materials of their own.
PART_COLOURS = {
    "skin": (0.8, 0.78, 0.75),
    "eyeball": (0.95, 0.95, 0.95),
    "cornea": (0.6, 0.7, 0.9),
    "upper_teeth": (1.0, 0.97, 0.88),
    "lower_teeth": (0.92, 0.85, 0.6),
    "tongue": (0.85, 0.4, 0.45),
    "mouth": (0.9, 0.6, 0.5),
    "lashes": (0.05, 0.04, 0.04),
    "eye_shell": (0.45, 0.55, 0.75),
    "rider": (0.3, 0.6, 0.3),
}


def colour_the_parts(objects, landmarks) -> None:
    """Paint each piece of the objects without materials by what the parts finder took it for."""
    plain = [obj for obj in objects if not obj.data.materials]
    if not plain:
        return
    vertices = np.concatenate([mesh.world_rest_coordinates(obj) for obj in plain]).astype(np.float64)
    offsets = np.cumsum([0] + [len(obj.data.vertices) for obj in plain])
    triangles = np.concatenate(
        [mesh.triangles(obj) + offset for obj, offset in zip(plain, offsets, strict=False)]
    )
    colours = np.tile([*PART_COLOURS["skin"], 1.0], (len(vertices), 1))
    for piece in find_parts(vertices, triangles, landmarks).pieces:
        colours[piece.indices, :3] = PART_COLOURS[piece.kind]
    material = bpy.data.materials.new("TR_FaceReportParts")
    compat.enable_material_nodes(material)
    nodes, links = material.node_tree.nodes, material.node_tree.links
    attribute = nodes.new("ShaderNodeAttribute")
    attribute.attribute_name = "TR_parts"
    shader = next(node for node in nodes if node.type == "BSDF_PRINCIPLED")
    links.new(attribute.outputs["Color"], shader.inputs["Base Color"])
    for obj, start, stop in zip(plain, offsets[:-1], offsets[1:], strict=True):
        layer = obj.data.color_attributes.new("TR_parts", "FLOAT_COLOR", "POINT")
        layer.data.foreach_set("color", colours[start:stop].astype(np.float32).ravel())
        obj.data.materials.append(material)


def render_sheet(objects, landmarks, out: Path, tile: int, samples: int, shots, per_row: int) -> None:
    """One PNG of shots (label, keys set to 1, framing), each from the front and three-quarter."""
    camera, label = setup_scene(landmarks, tile, samples)
    views = (0.0, THREE_QUARTER_DEGREES)
    rows = math.ceil(len(shots) / per_row)
    sheet = np.zeros((rows * tile, per_row * len(views) * tile, 4), np.float32)
    sheet[..., 3] = 1.0
    with tempfile.TemporaryDirectory() as folder:
        for index, (name, keys, framing) in enumerate(shots):
            row, slot = divmod(index, per_row)
            for obj in objects:
                if obj.data.shape_keys is not None:
                    for block in obj.data.shape_keys.key_blocks[1:]:
                        block.value = 1.0 if block.name in keys else 0.0
            label.data.body = name
            for column, degrees in enumerate(views):
                place_camera(camera, landmarks, degrees, framing)
                path = Path(folder) / f"{index}_{column}.png"
                bpy.context.scene.render.filepath = str(path)
                bpy.ops.render.render(write_still=True)
                image = bpy.data.images.load(str(path))
                pixels = np.empty(tile * tile * 4, np.float32)
                image.pixels.foreach_get(pixels)
                bpy.data.images.remove(image)
                top = (rows - 1 - row) * tile  # Blender's pixels start at the bottom row
                left = (slot * len(views) + column) * tile
                sheet[top : top + tile, left : left + tile] = pixels.reshape(tile, tile, 4)
            print(f"rendered {index + 1}/{len(shots)} {name}", flush=True)
    image = bpy.data.images.new(out.stem, sheet.shape[1], sheet.shape[0], alpha=True)
    image.pixels.foreach_set(sheet.ravel())
    image.filepath_raw = str(out)
    image.file_format = "PNG"
    image.save()
    print(f"wrote {out}")


def kit_object(name: str) -> bpy.types.Object:
    """A test head of lab/kit/heads.py as one object, its known motion as its own keys (named as
    our units, so the report compares with them)."""
    made = kit_heads([name])
    if not made:
        raise LipSyncError(f"No test head's name contains {name!r}; see lab/kit/heads.py.")
    kit = made[0]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    obj = bpy.data.objects.new("KitHead", heads.mesh_from_arrays("KitHead", kit.vertices, kit.triangles))
    bpy.context.scene.collection.objects.link(obj)
    obj.shape_key_add(name="Basis", from_mix=False)
    for key, deltas in kit.truth.items():
        block = obj.shape_key_add(name=key, from_mix=False)
        block.points.foreach_set("co", (kit.vertices + deltas).astype(np.float32).ravel())
        block.value = 0.0
    print(f"test head: {kit.name}")
    return obj


def face_report(
    head_path: Path | None,
    out_dir: Path,
    object_name: str | None,
    keep_keys: bool,
    source: str,
    tile: int,
    samples: int,
    render: bool,
    kit: str | None = None,
    parts_only: bool = False,
) -> list[dict]:
    """kit: a test head of lab/kit/heads.py (by a part of its name) instead of a file, its known
    motion as the artist's keys; parts_only: render the close-ups only."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if kit is not None:
        head = kit_object(kit)
    elif head_path is None:
        head = heads.create_reference_head(bpy.context)["head"]
    else:
        imported = heads.import_head(head_path)
        head = bpy.data.objects[object_name] if object_name else heads.find_head(imported)
    parts = heads.find_head_parts(head)
    artist_by_object = {obj.name: world_key_deltas(obj) for obj in [head, *parts]}
    artist = artist_by_object[head.name]
    landmarks = shapekeys.head_landmarks(head)
    if not keep_keys:
        strip_keys([head, *parts])
        if read_landmark_markers(head) is None:
            # Found from the keys just removed (a mouth painted on a texture): kept as the user's markers.
            placed = mesh.world_points_to_local(head, np.array(list(landmarks.values())), "build")
            show_landmark_markers(head, dict(zip(landmarks, placed, strict=True)))
    report = shapekeys.build_shape_keys(head, parts=parts, source=source, arkit_keys=True)
    print(f"{head.name}: {len(report.keys)} keys from source {report.source}")
    for warning in report.warnings:
        print(f"warning: {warning}")
    built = world_key_deltas(head)
    face = FaceMeasure(mesh.world_rest_coordinates(head).astype(np.float64), mesh.triangles(head), landmarks)
    millimetres = millimetres_per_unit(landmarks)
    rows = measure(face, built, artist, millimetres)
    zero = np.zeros((len(head.data.vertices), 3))
    print_table(rows, millimetres * face.lip_aperture(zero), millimetres * face.lid_gap(zero, "left"))
    built_by_object = {obj.name: world_key_deltas(obj) for obj in [head, *parts]}
    print_parts(part_rows([head, *parts], landmarks, built_by_object, artist_by_object, millimetres))
    if render:
        out_dir.mkdir(parents=True, exist_ok=True)
        stem = (
            kit.replace(" ", "_").replace(",", "") if kit else head_path.stem if head_path else "default_head"
        )
        objects = [head, *parts]
        shots = [(name, keys, "face") for name, keys in ROWS]
        if not parts_only:
            sheet = out_dir / f"face_report_{stem}.png"
            render_sheet(objects, landmarks, sheet, tile, samples, shots, KEYS_PER_ROW)
        colour_the_parts(objects, landmarks)
        render_sheet(
            objects, landmarks, out_dir / f"face_report_{stem}_parts.png", tile, samples, CLOSE_UPS, 2
        )
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--head", type=Path, default=None, help="head file (default: the reference head)")
    parser.add_argument("--out", type=Path, default=Path("out"), help="folder for face_report_<head>.png")
    parser.add_argument(
        "--object", default=None, help="the head object's name, when it is not the biggest mesh"
    )
    parser.add_argument(
        "--keep-keys", action="store_true", help="build from the head's own keys, not by transfer"
    )
    parser.add_argument(
        "--source", default="auto", choices=shapekeys.SOURCES, help="where the keys come from (default: auto)"
    )
    parser.add_argument("--tile", type=int, default=200, help="pixels per picture")
    parser.add_argument("--samples", type=int, default=8, help="Cycles samples per picture")
    parser.add_argument("--no-render", action="store_true", help="print the figures only")
    parser.add_argument("--kit", default=None, help="a test head of kit_heads.py (part of its name)")
    parser.add_argument("--parts-only", action="store_true", help="render the parts' close-ups only")
    args = parser.parse_args(argv)
    try:
        face_report(
            args.head,
            args.out,
            args.object,
            args.keep_keys,
            args.source,
            args.tile,
            args.samples,
            not args.no_render,
            kit=args.kit,
            parts_only=args.parts_only,
        )
    except LipSyncError as error:
        print(f"face_report.py: error: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else None))
