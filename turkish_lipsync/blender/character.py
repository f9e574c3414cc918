"""The character as a studio has it, for Generate: its face rig or its keys, linked or its own.

Before anything changes: what the head speaks through (its face rig's set-up, bones that drive its keys,
its own TR keys, linkable ones in a shot) and a clear refusal where it has none of these, naming the file
where the keys must be built when the character is linked. Then the speech is keyed: the rig's bones take
the tracks it moves, the head's keys (or the properties that drive linkable ones) the rest.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import bpy
import numpy as np

from ..core.base.errors import HeadError
from ..core.base.model import BLINK_KEYS, VISEME_KEY_PREFIX, WeightTracks
from . import compat, face_rig, keyframes, linking, living, rig_drivers
from .face_rig import FaceRig
from .living_rig import LivingRig, find_rig
from .marked_curves import FACE_RIG, LINKED_KEYS, marked_paths
from .owned_keys import owned_keys


@dataclass(frozen=True)
class KeyedSpeech:
    action_names: tuple[str, ...]
    driven: frozenset[str]  # the tracks the face rig moved
    warnings: tuple[str, ...]


def has_own_keys(head: bpy.types.Object) -> bool:
    return any(name.startswith(VISEME_KEY_PREFIX) for name in owned_keys(head))


def has_face_rig(head: bpy.types.Object) -> bool:
    armature = face_rig.face_armature(head)
    return (
        armature is not None and bool(armature.get(face_rig.RIG_PROPERTY))
    ) or rig_drivers.has_driven_keys(head)


# Why a head cannot speak yet, as a button's tooltip says it (translated: blender/translations.py).
LINKED_WITHOUT_KEYS = (
    "The head is linked and its library has no lip-sync keys or face rig yet: build them in the character's "
    "own file"
)
LINKED_KEYS_NOT_LINKABLE = (
    "The head is linked and its keys are not linkable: press Make Keys Linkable in the character's own file"
)
NOTHING_TO_SPEAK_THROUGH = "The head has no lip-sync shape keys or face rig yet: build the keys first"


def speech_problem(head: bpy.types.Object) -> str | None:
    """Why the head cannot speak yet, as its button says it (None: it can)."""
    rigged = has_face_rig(head)
    if rigged or (has_own_keys(head) and (not face_rig.is_linked(head) or linking.is_linkable(head))):
        return None
    if face_rig.is_linked(head):
        return LINKED_KEYS_NOT_LINKABLE if has_own_keys(head) else LINKED_WITHOUT_KEYS
    return NOTHING_TO_SPEAK_THROUGH


def check_can_speak(head: bpy.types.Object, objects) -> None:
    """A HeadError saying what is missing and in which file, before anything is changed."""
    problem = speech_problem(head)
    library = face_rig.library_path(head)
    if problem == LINKED_WITHOUT_KEYS:
        raise HeadError(
            f"The head {head.name!r} is linked from {library}, which holds no lip-sync shape keys or "
            f"face-rig set-up for it yet: open {library}, press Build Shape Keys there (then Make Keys "
            "Linkable) or set up its face rig, save it, and reload the library here."
        )
    if problem == LINKED_KEYS_NOT_LINKABLE:
        raise HeadError(
            f"The head {head.name!r} is linked from {library} and its keys are not linkable, so this file "
            f"cannot animate them: open {library}, press Make Keys Linkable, save it, and reload the library "
            "here."
        )
    if problem == NOTHING_TO_SPEAK_THROUGH:
        raise HeadError(
            f"The head {head.name!r} has no {VISEME_KEY_PREFIX}* shape keys and no face rig yet: press Build "
            "Shape Keys first, or set up its face rig (Face Rig section)."
        )
    armature = face_rig.face_armature(head)
    for owner in [*objects, *(o.data.shape_keys for o in objects if o.type == "MESH"), armature]:
        action = owner.animation_data.action if owner is not None and owner.animation_data else None
        if action is not None and action.library is not None:
            raise HeadError(
                f"{owner.name!r} plays the action {action.name!r} linked from {action.library.filepath}, "
                "which this file cannot change: make it local (or assign none) and generate again."
            )


def face_rig_for(context: bpy.types.Context, head: bpy.types.Object, rig: LivingRig | None) -> FaceRig | None:
    """The head's face rig resolved (in the character's frame: the living rig's, else found at rest)."""
    if not has_face_rig(head):
        return None
    if rig is None:
        with living.at_rest(context.scene):
            rig = find_rig(head)
    return face_rig.find_face_rig(head, rig.frame)


def key_speech(
    head: bpy.types.Object,
    objects,
    tracks: WeightTracks,
    start: float,
    action_name: str,
    face: FaceRig | None,
) -> KeyedSpeech:
    """The rig's bones keyed with what it moves, the head's keys (or the properties driving linkable ones)
    with the rest."""
    warnings: list[str] = []
    driven: frozenset[str] = frozenset()
    if face is not None:
        result = face_rig.key_face_rig(face, tracks, start)
        driven, warnings = result.driven, list(result.warnings)
    else:
        face_rig.remove_face_rig_motion(head)
    rest = dataclasses.replace(tracks, tracks=tuple(t for t in tracks.tracks if t.name not in driven))
    if linking.is_linkable(head):
        keyframes.remove_weight_tracks(objects)
        name, _count = linking.write_property_tracks(head, rest, start)
        names = (name,) if name else ()
    else:
        names = tuple(w.action_name for w in keyframes.write_weight_tracks(objects, rest, start, action_name))
    if face is not None:
        names += (bpy.data.objects[face.armature].animation_data.action.name,)
        blinks = [t for t in tracks.tracks if t.name in BLINK_KEYS and np.any(t.values > 0)]
        if blinks and not any(t.name in driven or t.name in owned_keys(head) for t in blinks):
            warnings.append(
                f"{head.name!r} blinks through neither its face rig nor shape keys: record poses for "
                "eyeBlinkLeft and eyeBlinkRight (Face Rig section), or build its shape keys, to let it blink."
            )
    return KeyedSpeech(tuple(dict.fromkeys(names)), driven, tuple(warnings))


def speech_actions(head: bpy.types.Object) -> list[bpy.types.Action]:
    """The actions that may hold the head's speech, in the order the record is looked for: the head's own
    (its linkable keys' properties), its shape keys', its face rig's."""
    found = []
    action = head.animation_data.action if head.animation_data else None
    if marked_paths(action, LINKED_KEYS):
        found.append(action)
    key = head.data.shape_keys if head.type == "MESH" else None
    action = key.animation_data.action if key is not None and key.animation_data else None
    if action is not None:
        found.append(action)
    armature = face_rig.face_armature(head)
    action = armature.animation_data.action if armature is not None and armature.animation_data else None
    if marked_paths(action, FACE_RIG):
        found.append(action)
    return found


def record_holder(head: bpy.types.Object, record_property: str) -> bpy.types.Action | None:
    """The action keeping what Generate made: the first that has it, else (writing) the first there is."""
    actions = speech_actions(head)
    holding = [action for action in actions if record_property in action]
    return (holding or actions or [None])[0]


def fcurve_count(action: bpy.types.Action | None) -> int:
    return len(compat.all_action_fcurves(action)) if action is not None else 0
