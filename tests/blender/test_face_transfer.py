"""Keys built by transfer on real heads, measured as the face report measures them.

Vitruvian arrives with its artists' own keys: they are kept aside, removed, and the transferred keys are
compared with them (cosine of the displacement fields, edge stretch p99.9 of deformed / rest length).
Godette's face shows no mouth (it is painted; only its own "ah" key opens it) and looks toward +Y.
"""

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lab.kit.heads import strip_keys, world_key_deltas  # noqa: E402
from lab.kit.heads_on_disk import HEADS  # noqa: E402
from tests.blender.evaluated import evaluated_world  # noqa: E402
from turkish_lipsync.blender import heads, mesh, shapekeys  # noqa: E402
from turkish_lipsync.core.faces.closest import nearest_vertices  # noqa: E402
from turkish_lipsync.core.faces.landmarks import face_frame  # noqa: E402
from turkish_lipsync.core.faces.measure import FaceMeasure, displacement_cosine  # noqa: E402
from turkish_lipsync.core.faces.reference import load_reference_head  # noqa: E402

VITRUVIAN = HEADS / "vitruvian" / "vitruvian_head_facs.glb"
GODETTE = HEADS / "godette" / "Godette_vrm_v4_named.glb"


def built_head(path, object_name=None, strip=True):
    """(head's name, artist keys, built keys, FaceMeasure) after building by transfer, on a copy without its
    own keys unless strip is False. Only the name is kept: a module-wide Blender reference would outlive
    the next test's new file (and crash Blender 4.2 as it exits)."""
    if not path.exists():
        pytest.skip(f"{path} not present")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    imported = heads.import_head(path)
    head = bpy.data.objects[object_name] if object_name else heads.find_head(imported)
    artist = world_key_deltas(head)
    landmarks = shapekeys.head_landmarks(head)
    if strip:
        strip_keys([head])
    shapekeys.build_shape_keys(head, parts=[], source="transfer", arkit_keys=True)
    vertices = mesh.world_rest_coordinates(head).astype(np.float64)
    return head.name, artist, world_key_deltas(head), FaceMeasure(vertices, mesh.triangles(head), landmarks)


@pytest.fixture(scope="module")
def vitruvian():
    return built_head(VITRUVIAN)


@pytest.mark.parametrize(
    ("ours", "theirs", "cosine"),
    [
        # Targets of issue 14: jawOpen 0.9, TR_viseme_a 0.85, pucker and smile 0.6 (artists differ there).
        # Measured 0.96, 0.86, 0.71, 0.73; before the part-aware transfer 0.78, 0.68, 0.21, 0.39 (the
        # pucker 0.47 before it parted the teeth behind the lips, the a 0.84 before its jaw glided forward).
        ("jawOpen", "Mouth_Large_Opened", 0.9),
        ("TR_viseme_a", "aa_02", 0.85),
        ("mouthPucker", "Kiss", 0.65),
        ("mouthSmileLeft", "Smile_Lips_Closed_Left", 0.65),
        # Target 0.85, not reached: measured 0.74 (0.09 before; 0.52 before the lid margins were
        # landmarks; 0.63 before the lid unrolled from its crease, 0.73 before the skin above it was
        # eased); the artist's blink also brings the lids 1-2 mm forward and pulls the eyeball back.
        ("eyeBlinkLeft", "Eyes_Closed_Left", 0.7),
        # Measured 0.67 and 0.60; 0.34 and 0.38 while the brows were found at the hairline.
        ("browDownLeft", "Eyebrows_Lower_Left", 0.55),
        ("browOuterUpLeft", "Eyebrows_OuterBrow_Raised_Left", 0.5),
    ],
)
def test_transferred_keys_point_the_artists_way(vitruvian, ours, theirs, cosine):
    _, artist, built, _ = vitruvian
    assert displacement_cosine(built[ours], artist[theirs]) >= cosine


@pytest.mark.parametrize(
    ("ours", "theirs", "ceiling"),
    [
        ("jawOpen", "Mouth_Large_Opened", 10.0),
        ("TR_viseme_a", "aa_02", None),
        ("eyeBlinkLeft", "Eyes_Closed_Left", 4.0),
    ]
    + [(f"TR_viseme_{name}", "aa_02", None) for name in ("e", "o", "oi")]
    + [("mouthPucker", "Kiss", None)],
)
def test_no_webbing_the_stretch_stays_near_the_artists(vitruvian, ours, theirs, ceiling):
    """Edge stretch p99.9 within 1.5 times the artist's comparable key (open vowels against aa_02), and
    under 10 for jawOpen and 4 for a blink: a curtain over the mouth stretches its faces 23 to 62 times."""
    _, artist, built, face = vitruvian
    stretch, artists = face.stretch(built[ours]), face.stretch(artist[theirs])
    assert stretch <= 1.5 * artists
    if ceiling is not None:
        assert stretch < ceiling  # measured: jawOpen 9.1 (the artist's 9.0), the blink 3.5 (4.3)


def test_open_vowels_part_the_lips_and_bilabials_close_them(vitruvian):
    _, artist, built, face = vitruvian
    # The artist's Mouth_Large_Opened opens 39 mm at the midline (measured); ours 35 mm, the a 17 mm.
    assert face.lip_aperture(built["jawOpen"]) > 0.5 * face.lip_aperture(artist["Mouth_Large_Opened"])
    for vowel in ("a", "e", "o"):
        assert face.lip_aperture(built[f"TR_viseme_{vowel}"]) > 0.008, vowel
    for bilabial in ("bpa", "ma", "bpo"):
        assert face.lip_aperture(built[f"TR_viseme_{bilabial}"]) < 0.001, bilabial
    # The blink closes the lids as far as the artist's does (measured: 5.8 mm open, -2.9 mm under the
    # blink against the artist's -2.1; -5.1 before the blink was fitted to the opening).
    closed = face.lid_gap(built["eyeBlinkLeft"])
    assert closed < 0 and abs(closed - face.lid_gap(artist["Eyes_Closed_Left"])) < 0.0015
    # And without creasing the skin above the lid (7 edges folded past 60 degrees before the transfer
    # eased that skin's motion; the artist's blink folds none).
    assert face.lid_creases(built["eyeBlinkLeft"]) == 0 == face.lid_creases(artist["Eyes_Closed_Left"])


def test_symmetric_keys_are_symmetric_and_a_blink_is_one_sided(vitruvian):
    _, _, built, face = vitruvian
    assert face.symmetry(built["jawOpen"]) > 0.9
    assert face.symmetry(built["TR_viseme_a"]) > 0.9
    assert face.symmetry(built["eyeBlinkLeft"]) < 0.2


def test_a_painted_mouth_facing_plus_y_builds_from_what_its_own_keys_move():
    head_name, artist, built, face = built_head(GODETTE, "Face", strip=False)
    head = bpy.data.objects[head_name]
    moved = np.linalg.norm(built["jawOpen"], axis=1)
    assert moved.max() > 0
    # The jaw drops the chin (down in the face's own frame: it looks toward +Y), not the brows.
    vertices = mesh.world_rest_coordinates(head)
    chin, brow = (
        np.argmin(np.linalg.norm(vertices - face.landmarks[n], axis=1)) for n in ("chin", "brow_left")
    )
    assert built["jawOpen"][chin] @ face.axes[:, 2] < -0.3 * moved.max()
    assert np.linalg.norm(built["jawOpen"][brow]) < 0.1 * moved.max()
    assert face.stretch(built["jawOpen"]) < 10 and face.stretch(built["eyeBlinkLeft"]) < 4
    # The left blink moves the character's left eye (toward the face's +X), the one its own key closes.
    left = np.linalg.norm(built["eyeBlinkLeft"], axis=1) > 0
    own_left = np.linalg.norm(artist["blink_left"], axis=1) > 0
    assert face.vertices[left, 0].mean() > 0 and face.vertices[own_left, 0].mean() > 0


def game_head_file(folder):
    """A low-poly game head of the kind users export from game tools, made from the MakeHuman head: its
    keys stripped, the lips welded where they touch, decimated to about 2,500 triangulated vertices,
    teeth, tongue and eyes as objects of their own, every mesh scaled 0.0002 under a parent scaled 5000
    that lays the head on its back (the face looks up, +Z); written as glb and read back as a user would."""
    import bmesh

    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = heads.import_head(MAKEHUMAN_HEAD)
    head = heads.find_head(objects)
    strip_keys([obj for obj in objects if obj.type == "MESH"])
    welded = bmesh.new()
    welded.from_mesh(head.data)
    bmesh.ops.remove_doubles(welded, verts=[v for v in welded.verts if abs(v.co.x) < 0.03], dist=0.0012)
    welded.to_mesh(head.data)
    welded.free()
    decimate = head.modifiers.new("Decimate", "DECIMATE")
    decimate.ratio = 0.62
    with bpy.context.temp_override(object=head, active_object=head):
        bpy.ops.object.modifier_apply(modifier=decimate.name)
    root = bpy.data.objects.new("GameRoot", None)
    bpy.context.scene.collection.objects.link(root)
    for obj in objects:
        if obj.type == "MESH":
            obj.parent = root
            obj.scale = (0.0002,) * 3
    root.scale = (5000.0,) * 3
    root.rotation_euler = (-np.pi / 2, 0.0, 0.0)
    path = folder / "game_head.glb"
    bpy.ops.export_scene.gltf(filepath=str(path), export_format="GLB")
    return path


MAKEHUMAN_HEAD = HEADS / "makehuman" / "mh_head_expression_units.glb"


def test_a_low_poly_game_head_on_its_back_builds_with_an_open_mouth_and_closing_lids(tmp_path):
    if not MAKEHUMAN_HEAD.exists():
        pytest.skip(f"{MAKEHUMAN_HEAD} not present")
    path = game_head_file(tmp_path)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    imported = heads.import_head(path)
    head = heads.find_head(imported)
    assert head.data.shape_keys is None and 2000 < len(head.data.vertices) < 3000
    landmarks = shapekeys.head_landmarks(head)
    report = shapekeys.build_shape_keys(head, source="transfer", arkit_keys=True)
    assert report.source == "transfer"
    built = world_key_deltas(head)
    face = FaceMeasure(mesh.world_rest_coordinates(head).astype(np.float64), mesh.triangles(head), landmarks)
    # The face looks up (+Z) in the world: the landmarks found it lying on its back.
    assert face.axes[:, 1] @ np.array([0.0, 0.0, -1.0]) > 0.9
    # Measured: jawOpen 36.3 mm at the midline with stretch 2.5, a 18.4 mm, the blink's lid gap -3.9 mm
    # with stretch 2.8, no creases. Its lips are welded: which side the seam's vertices fall on decides the
    # reading at rest (2.4 mm here, 0.3 with the landmarks found without its eyes), so a bilabial is held
    # to the rest reading: it must not part the lips (measured 0.9 and 0.6 mm, under the rest's 2.4).
    assert face.lip_aperture(built["jawOpen"]) > 0.015 and face.stretch(built["jawOpen"]) < 10
    assert face.lip_aperture(built["TR_viseme_a"]) > 0.008
    rest = face.lip_aperture(np.zeros_like(built["jawOpen"]))
    for bilabial in ("bpa", "ma"):
        assert face.lip_aperture(built[f"TR_viseme_{bilabial}"]) < rest + 0.0005, bilabial
    assert face.lid_creases(built["eyeBlinkLeft"]) == 0  # its eyes, objects of their own, mark the lids
    assert face.lid_gap(built["eyeBlinkLeft"]) < 0 and face.stretch(built["eyeBlinkLeft"]) < 4
    assert face.symmetry(built["jawOpen"]) > 0.9


def test_the_face_report_reads_millimetres_whatever_the_units():
    """A head modelled in centimetres or decimetres reports its lip and lid gaps in millimetres too: the
    MediaPipe mask (cm) opens 39.7 mm, not 3,970 (measured)."""
    from lab.kit.heads import millimetres_per_unit
    from turkish_lipsync.core.faces.reference import load_reference_head
    from turkish_lipsync.core.faces.transfer import reference_landmarks_of

    landmarks = reference_landmarks_of(load_reference_head())
    for unit, expected in ((1.0, 1000.0), (100.0, 10.0), (10.0, 100.0), (1.3, 1000.0), (0.001, 1e6)):
        scaled = {name: point * unit for name, point in landmarks.items()}
        assert millimetres_per_unit(scaled) == pytest.approx(expected)


def _set_keys(obj, values: dict[str, float]) -> None:
    for block in obj.data.shape_keys.key_blocks[1:]:
        block.value = values.get(block.name, 0.0)


def joined_default_head():
    """The default head with its teeth, tongue, eyes and lashes joined into its skin's mesh (one object,
    each part an island with its own material), and which of its vertices each part was."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = heads.create_reference_head(bpy.context)
    head = objects.pop("head")
    positions = {name: mesh.world_rest_coordinates(obj) for name, obj in objects.items()}
    for obj in objects.values():
        obj.parent = None
        obj.matrix_world = obj.matrix_world  # keeps where it is
        obj.pop(heads.REFERENCE_PART_PROPERTY, None)
    head.pop(heads.REFERENCE_PART_PROPERTY, None)
    bpy.context.view_layer.update()
    with bpy.context.temp_override(
        active_object=head, selected_editable_objects=[head, *objects.values()], object=head
    ):
        bpy.ops.object.join()
    world = mesh.world_rest_coordinates(head).astype(np.float64)
    parts = {name: np.unique(nearest_vertices(points, world)[0]) for name, points in positions.items()}
    return head, parts


def test_the_default_head_joined_into_one_mesh_closes_its_lashes_and_drops_its_lower_gums():
    """Its parts islands of its skin's mesh, materials and all, keys by transfer, measured on the
    evaluated mesh: the lashes come down with the closing lid, the lower teeth and gums with the jaw."""
    head, parts = joined_default_head()
    assert len(head.data.materials) >= 4 and head.data.shape_keys is None
    report = shapekeys.build_shape_keys(head, parts=[], source="transfer", arkit_keys=True)
    assert report.source == "transfer"
    landmarks = shapekeys.head_landmarks(head, [])
    rest = mesh.world_rest_coordinates(head).astype(np.float64)
    reference = load_reference_head()
    _set_keys(head, {"eyeBlinkLeft": 1.0})
    blink = evaluated_world(head) - rest
    _set_keys(head, {"jawOpen": 1.0})
    jaw = evaluated_world(head) - rest
    _set_keys(head, {})
    origin, axes = face_frame(landmarks)
    lashes = parts["left_eyelashes"]
    height = (rest[lashes] - origin) @ axes[:, 2]
    eye = np.mean([(landmarks[f"eye_{end}_left"] - origin) @ axes[:, 2] for end in ("inner", "outer")])
    upper = lashes[height > eye]
    # Every upper lash vertex hangs below where the open lid's margin was (measured: the highest 6.6 mm
    # below it; left where they were, the lashes reach 3.1 mm above it).
    margin = (landmarks["upper_lid_left"] - origin) @ axes[:, 2]
    closed = (rest[upper] + blink[upper] - origin) @ axes[:, 2]
    assert closed.max() < margin - 0.003
    # The lower teeth and gums go down with the jaw as the reference's do, the upper stay (measured:
    # cosine 0.9998, the upper teeth still).
    lower = parts["lower_teeth"]
    expected = reference.units["jawOpen"][reference.parts["lower_teeth"]]
    assert displacement_cosine(jaw[lower], expected) > 0.97
    assert np.abs(jaw[parts["upper_teeth"]]).max() < 1e-6


def test_teeth_beside_a_head_that_are_nobodys_children_are_its_parts():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = heads.create_reference_head(bpy.context)
    for name in ("upper_teeth", "lower_teeth", "tongue"):
        world = objects[name].matrix_world.copy()
        objects[name].parent = None
        objects[name].matrix_world = world
    bpy.context.view_layer.update()
    found = set(heads.find_head_parts(objects["head"]))
    assert {objects[name] for name in ("upper_teeth", "lower_teeth", "tongue", "left_eye")} <= found


def test_lash_cards_and_eye_shells_added_to_vitruvian_close_with_its_lids():
    """Vitruvian with lash cards along its lid margins and occlusion shells over its eyes, islands of
    its mesh (lab/kit/joined_heads.py); the truth turns them about the eyeball as their lid point does
    under the artist's blink. Measured: upper cards 0.88, shells 0.61 (our lid closes further than the
    artist's), the whole mesh's blink 0.717 against the skin's own 0.771; before, the shells stood still
    with the eye and the upper cards, taken for lashes, sampled the reference's (0.90)."""
    from lab.kit.heads import kit_heads, measure_head

    if not VITRUVIAN.exists():
        pytest.skip(f"{VITRUVIAN} not present")
    head = next(head for head in kit_heads(["vitruvian + lash cards"]))
    blink = measure_head(head)["eyeBlinkLeft"]
    assert blink["parts"]["upper lash card"]["found"] == "lashes"
    assert blink["parts"]["upper lash card"]["cosine"] > 0.8
    assert blink["parts"]["occlusion shell"]["found"] == "eye_shell"
    assert blink["parts"]["occlusion shell"]["cosine"] > 0.5
    assert blink["whole"] > blink["skin"] - 0.08
    assert blink["stretch"] < 1.5 * blink["truth_stretch"]
