"""Several characters from one script: a head per speaker, an action and record each, the lines' sound.

Each speaker is played by the head the cast names (an object of the file, or a head file imported), else by
a default head of its own, made in a tone of its own (conversation.toml [[tones]]) and stood on the arc the
core lays out (core/scene/layout.py), turned toward the others. Generate again reuses those heads where
they are (the user may have moved them) and replaces only what the last Generate made: our keys' curves,
our living motion, our strips (by the names it recorded, scene_record.py).
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass
from pathlib import Path

import bpy
import numpy as np
from mathutils import Vector

from ..core.base.errors import HeadError
from ..core.base.model import OWNED_PREFIX
from ..core.interchange.animation_record import AnimationRecord, record_to_json
from ..core.motion.frames import shown_frame_count
from ..core.pipeline import LipSyncOptions
from ..core.scene import Cast, RoleChoice, SceneResult, Standing, cast_for, scene_motion, scene_speech
from ..core.scene.layout import arc_positions
from ..core.scene.speech import SceneSources
from ..core.scene.tables import conversation_table
from ..core.speech import Synthesis
from ..core.text.script import Script
from . import gltf_export, keyframes, living, pipeline, render, sequencer, shapekeys
from . import heads as head_files
from .character import check_can_speak, key_speech, record_holder
from .face_rig import is_linked
from .living_rig import LivingRig, find_rig
from .scene_record import ConversationRecord, conversation_record, keep_conversation_record

CAST_PROPERTY = "tr_cast_speaker"  # on a default head Generate made for a speaker: the speaker's key


def _quiet(_fraction: float, _message: str) -> None:
    pass


@dataclass(frozen=True, eq=False)
class ConversationResult:
    """What a conversation's Generate made (names only) and the scene it keyed."""

    heads: dict[str, str]  # the speaker's name -> the head object's name
    action_names: tuple[str, ...]
    strip_names: tuple[str, ...]
    wav_path: str | None  # the scene's whole sound
    frame_start: int
    frame_end: int
    duration: float
    fps: float
    scene: SceneResult
    warnings: tuple[str, ...] = ()


def generate_conversation(
    context: bpy.types.Context,
    script: Script,
    choices: dict[str, RoleChoice],
    options: LipSyncOptions,
    *,
    sources: SceneSources | None = None,
    audio_folder: str = "",
    start_frame: int | None = None,
    package: str | None = None,
    progress: pipeline.Progress | None = None,
) -> ConversationResult:
    """Speak the script with its cast: every character keyed, the lines in the sequencer, the frame range.

    choices: what the user chose per speaker (by name); the rest the cast decides. The speech is made
    before anything in the scene changes; a head that cannot be made or built leaves the scene as it was.
    """
    progress = progress or _quiet
    scene = context.scene
    fps = sequencer.scene_fps(scene)
    start = scene.frame_start if start_frame is None else int(start_frame)
    options = dataclasses.replace(options, fps=fps)
    cast = cast_for(script, choices, options.emotion_strength)
    progress(0.05, f"Speaking {len(script.lines)} lines of {len(cast.roles)} speakers")
    speech = scene_speech(script, cast, options, sources)
    progress(0.3, "Saving the lines' audio")
    sounds, mix_path = _write_sounds(speech, start, fps, audio_folder, package)

    # From here on Blender data changes.
    progress(0.35, "Casting the heads")
    heads = cast_heads(context, cast)
    rigs, standings, camera = _standings(context, cast, heads)
    progress(0.45, "Moving every character")
    result = scene_motion(speech, options, standings, camera)
    previous = conversation_record(scene)
    _forget_previous(scene, previous, set(heads.values()))

    progress(0.55, "Keying the characters")
    actions, warnings = [], list(result.warnings)
    for number, character in enumerate(result.characters):
        head = bpy.data.objects[heads[character.role.key]]
        moved = living.key_living_motion(
            context, rigs[character.role.key], character.tracks, start, clear=number == 0
        )
        warnings += moved.warnings
        name = _action_name(character, result, head)
        keyed = key_speech(head, pipeline.head_objects(head), character.tracks, start, name, None)
        actions += list(keyed.action_names)
        _keep_character_record(head, result, character, start)
        warnings += pipeline.own_keys_held_warning(head)

    progress(0.8, "Placing the lines in the sequencer")
    if mix_path is None:
        scene.pop(sequencer.SPEECH_PATH_PROPERTY, None)
    strips = sequencer.place_scene_strips(scene, sounds, mix_path)
    frame_count = shown_frame_count(result.speech.duration, fps)
    warnings += sequencer.fit_frame_range(scene, start, frame_count)
    keep_conversation_record(
        scene,
        ConversationRecord(
            heads=dict(heads),
            names={role.key: role.name for role in cast.roles},
            strips=strips,
            fps=fps,
            duration=speech.duration,
        ),
    )
    progress(1.0, "Conversation generated")
    return ConversationResult(
        heads={cast.role(key).name: name for key, name in heads.items()},
        action_names=tuple(actions),
        strip_names=strips,
        wav_path=str(mix_path) if mix_path else None,
        frame_start=start,
        frame_end=start + frame_count - 1,
        duration=speech.duration,
        fps=fps,
        scene=result,
        warnings=tuple(dict.fromkeys(warnings)),
    )


# ---------------------------------------------------------------- heads


def cast_heads(context: bpy.types.Context, cast: Cast) -> dict[str, str]:
    """Each speaker's head (speaker's key -> object name): the role's object, a head file imported, the
    default head Generate made for the speaker before, or a new default head in the speaker's tone on its
    place of the arc. What was made here is removed again when a head fails."""
    scene = context.scene
    made: list[bpy.types.Object] = []
    heads: dict[str, str] = {}
    slots = arc_positions(len(cast.roles))
    table = conversation_table()
    try:
        for index, role in enumerate(cast.roles):
            if role.head and role.head in bpy.data.objects:
                head = bpy.data.objects[role.head]
            elif role.head:
                path = Path(bpy.path.abspath(role.head))
                if path.suffix.lower() not in head_files.IMPORTABLE_SUFFIXES:
                    raise HeadError(
                        f"{role.name}'s head {role.head!r} is neither an object of this file nor a head file "
                        f"({', '.join(head_files.IMPORTABLE_SUFFIXES)}); choose one, or leave it empty for "
                        "the default head."
                    )
                imported = head_files.import_head(path)
                made += imported
                head = head_files.find_head(imported)
            else:
                head = next(
                    (o for o in scene.objects if o.get(CAST_PROPERTY) == role.key and o.type == "MESH"), None
                )
                if head is None:
                    tone = table.tones[index % len(table.tones)] if index else None
                    parts = head_files.create_reference_head(
                        context, _head_name(role.name), tone, tone_name=role.name if tone else ""
                    )
                    made += parts.values()
                    head = parts["head"]
                    head[CAST_PROPERTY] = role.key
                    position, turn = slots[index]
                    head.location = head.location + Vector(position.tolist())
                    head.rotation_euler.z += math.radians(turn)
            if head.type != "MESH":
                raise HeadError(
                    f"{role.name}'s head {head.name!r} is not a mesh; choose the head mesh itself."
                )
            if is_linked(head):  # a linked character's keys are built in its own file
                check_can_speak(head, [head])
            elif not pipeline.has_lipsync_keys(head):
                context.view_layer.update()
                shapekeys.build_shape_keys(head)
            heads[role.key] = head.name
    except Exception:
        for obj in made:
            data = obj.data
            bpy.data.objects.remove(obj, do_unlink=True)
            if data is not None and data.users == 0 and isinstance(data, bpy.types.Mesh):
                bpy.data.meshes.remove(data)
        raise
    context.view_layer.update()
    return heads


def _head_name(name: str) -> str:
    return "TR_Head_" + (re.sub(r"\s+", "_", name.strip()) or "speaker")[:40]


def _standings(context, cast: Cast, heads: dict[str, str]):
    """Each character's rig at rest, where it stands as the core sees it, and the camera's point: the
    scene's camera, else where Render's two-shot camera will stand."""
    scene = context.scene
    with living.at_rest(scene):
        rigs: dict[str, LivingRig] = {key: find_rig(bpy.data.objects[name]) for key, name in heads.items()}
        if scene.camera is not None:
            camera = np.array(scene.camera.matrix_world.translation)
        else:
            objects = [
                obj for name in heads.values() for obj in pipeline.head_objects(bpy.data.objects[name])
            ]
            facing = pipeline.group_facing(list(rigs.values()))
            centre, distance, _sensor, _size = render.camera_placement(scene, objects, facing, group=True)
            camera = np.array(centre) + facing[:, 2] * distance
    standings = {key: Standing(rig.pivot, rig.frame, rig.gaze_setup(None)[0]) for key, rig in rigs.items()}
    return rigs, standings, camera


# ---------------------------------------------------------------- keys, records, sounds


def _action_name(character, result: SceneResult, head: bpy.types.Object) -> str:
    """The character's action: its name and first words, short enough that its parts' actions (the name, a
    dot and the part's name) fit Blender's 63 bytes."""
    words = " ".join(
        word.text
        for line in result.speech.lines
        if line.speaker == character.role.key
        for word in line.utterance.words
    )
    longest = max((len(part.name.encode("utf-8")) for part in pipeline.head_objects(head)[1:]), default=0)
    room = max(63 - 1 - longest, 24)
    name = f"{OWNED_PREFIX}{character.role.name}: {words}"
    while len(name.encode("utf-8")) > room:
        name = name[:-1]
    return name.rstrip()


def character_text(result: SceneResult, key: str) -> str:
    """A character's lines as spoken, one a line (what its exports name as its text)."""
    return "\n".join(
        " ".join(word.text for word in line.utterance.words)
        for line in result.speech.lines
        if line.speaker == key
    )


def _keep_character_record(head: bpy.types.Object, result: SceneResult, character, start: int) -> None:
    """The character's own timeline and motion beside its keys: what its exports describe."""
    action = record_holder(head, pipeline.RECORD_PROPERTY)
    settings = {
        name: str(value) if isinstance(value, Path) else value
        for name, value in dataclasses.asdict(result.options).items()
    }
    role = character.role
    settings |= {
        "speaker": role.name,
        "voice": role.voice.variant,
        "voice_pitch": role.voice.pitch,
        "voice_rate": role.voice.rate,
        "emotion_strength": role.emotion_strength,
    }
    record = AnimationRecord(
        text=character_text(result, role.key),
        timeline=character.timeline,
        fps=character.tracks.fps,
        frame_start=start,
        frame_count=character.tracks.frame_count,
        settings=settings,
        key_fingerprint=keyframes.key_fingerprint(pipeline.head_objects(head)),
        warnings=result.warnings,
        head_and_eyes=character.tracks.head_and_eyes,
    )
    action[pipeline.RECORD_PROPERTY] = record_to_json(record)


def _write_sounds(speech, start: int, fps: float, folder: str, package: str | None):
    """Every piece of the scene's sound as a WAV, with the strip it becomes (named after its speaker and
    line, placed to the sample: a piece starting between frames gets that much silence first), and the
    whole scene's mix; written before the scene changes, so a folder that cannot be written changes
    nothing."""
    sounds = []
    for piece in speech.pieces:
        at = start + piece.start * fps
        first = math.floor(at + 1e-9)
        audio = _delayed(piece.audio, (at - first) / fps)
        wav = sequencer.write_speech_wav(piece.name, audio, folder, package)
        sounds.append((f"{OWNED_PREFIX}{piece.name}", wav, first, max(1, math.ceil(audio.duration * fps))))
    mix = speech.mix()
    mix_path = sequencer.write_speech_wav("scene", mix, folder, package) if mix is not None else None
    return sounds, mix_path


def _delayed(audio: Synthesis, seconds: float) -> Synthesis:
    pad = int(round(seconds * audio.sample_rate))
    if pad <= 0:
        return audio
    return dataclasses.replace(audio, samples=np.concatenate([np.zeros(pad, np.int16), audio.samples]))


def _forget_previous(scene: bpy.types.Scene, previous: ConversationRecord | None, keeping: set[str]) -> None:
    """What the last Generate made that this one does not replace: its strips, the single head's strip,
    and the keys of characters no longer cast (their heads stay, at rest)."""
    sequencer.remove_speech_strip(scene)
    if previous is None:
        return
    sequencer.remove_scene_strips(scene, previous.strips)
    for obj in previous.head_objects():
        if obj.name not in keeping:
            keyframes.remove_weight_tracks(pipeline.head_objects(obj))


def export_conversation_gltf(
    context: bpy.types.Context, filepath: str | Path
) -> list[gltf_export.GltfExport]:
    """A conversation as glTF: the whole scene in the chosen file, and each character in a file of its own
    beside it (scene_Ayşe.glb), each with the scene's speech WAV beside it."""
    record = conversation_record(context.scene)
    if record is None:
        raise HeadError("The scene has no conversation to export: generate one from a script with speakers.")
    path = Path(bpy.path.abspath(str(filepath))).with_suffix(".glb")
    heads = record.head_objects()
    written = [gltf_export.export_heads_gltf(context, heads, path)]
    for key, name in record.heads.items():
        if name in bpy.data.objects:
            speaker = "_".join(record.names.get(key, key).split())
            written.append(
                gltf_export.export_heads_gltf(
                    context, [bpy.data.objects[name]], path.with_name(f"{path.stem}_{speaker}.glb")
                )
            )
    return written
