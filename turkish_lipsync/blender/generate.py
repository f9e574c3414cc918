"""Generate: a text spoken and every character keyed on it, one head or a script's cast, the speech in the
sequencer and the frame range fitted.

One path for one head and many: the core's scene (core/scene: perform) gives a Character per speaker, a
text with no speakers being a cast of one; each character is keyed alike (its living motion, its keys or
face rig, its record), and the scene's sound placed. What differs is only where the heads come from (the
chosen head; or each speaker's, cast by conversation.py) and how the sound is laid out (one strip of the
speech; or a strip per line and the scene's mix). Everything that can fail for bad input runs before
Blender data changes: the speech, its motion and its WAVs (a conversation's default heads are made after
the speech, and removed again if one fails). Functions take and return names, never keep Blender
references.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass
from pathlib import Path

import bpy
import numpy as np

from ..core.base.errors import HeadError
from ..core.base.model import OWNED_PREFIX, Timeline, Utterance, WeightTracks
from ..core.interchange.animation_record import AnimationRecord, record_to_json
from ..core.motion.frames import shown_frame_count
from ..core.pipeline import LipSyncOptions, lip_sync, speech_request
from ..core.scene import Character, RoleChoice, SceneResult, cast_for, scene_motion, scene_speech, solo_scene
from ..core.scene.speech import SceneSources
from ..core.speech import Synthesis
from ..core.speech.sources import timing_source_for
from ..core.text.script import read_script
from . import character, conversation, face_rig, keyframes, living, pipeline, sequencer
from .living_rig import LivingRig
from .scene_record import (
    ConversationRecord,
    conversation_record,
    forget_conversation_record,
    keep_conversation_record,
)


@dataclass(frozen=True, eq=False)
class GenerateResult:
    """What Generate did (names only, safe across undo) and the scene it keyed."""

    heads: dict[str, str]  # the speaker's name ("" for a text with no speakers) -> the head object's name
    action_names: tuple[str, ...]
    strip_names: tuple[str, ...]
    wav_path: str | None  # the scene's whole sound
    frame_start: int
    frame_end: int
    fps: float
    scene: SceneResult
    warnings: tuple[str, ...] = ()

    @property
    def duration(self) -> float:
        return self.scene.speech.duration

    @property
    def timeline(self) -> Timeline:
        """The one head's timeline; a conversation's every line on the scene's timeline."""
        return self.scene.characters[0].timeline if self.scene.solo else self.scene.speech.scene_timeline()

    @property
    def tracks(self) -> WeightTracks:
        """The first character's weight tracks (the one head's)."""
        return self.scene.characters[0].tracks

    @property
    def strip_name(self) -> str | None:
        return self.strip_names[0] if self.strip_names else None

    @property
    def phone_count(self) -> int:
        return len(self.timeline.phones)

    @property
    def timing(self) -> str:
        return self.timeline.timing


@dataclass(frozen=True, eq=False)
class _Cast:
    """The spoken and moved scene with what keys it: each speaker's head, living rig and face rig (by
    speaker key), and the WAVs already written: (strip name, WAV, first frame, frames) per piece and the
    whole sound."""

    scene: SceneResult
    heads: dict[str, str]
    rigs: dict[str, LivingRig | None]
    faces: dict[str, face_rig.FaceRig | None]
    sounds: list[tuple[str, Path, int, int]]
    mix_path: Path | None
    warnings: tuple[str, ...] = ()


def _quiet(_fraction: float, _message: str) -> None:
    pass


def generate(
    context: bpy.types.Context,
    source: str,
    options: LipSyncOptions | None = None,
    *,
    head: bpy.types.Object | None = None,
    choices: dict[str, RoleChoice] | None = None,
    sources: SceneSources | None = None,
    audio_folder: str = "",
    start_frame: int | None = None,
    package: str | None = None,
    progress: pipeline.Progress | None = None,
    gaze_target: str = "",
) -> GenerateResult:
    """Speak the source: a text with no speakers on `head` (its TR_* keys or face rig, its head and eyes
    turned, the TR_speech strip); a script with speakers by its cast (choices: what the user chose per
    speaker, by name; sources: recordings or a cue file of the scene), every character keyed, a strip per
    line. Then the frame range. options are the core's; their frame rate is replaced by the scene's and a
    head's gaze set-up by its eyes and the target (gaze_target names an object; else the camera)."""
    progress = progress or _quiet
    scene = context.scene
    fps = sequencer.scene_fps(scene)
    start = scene.frame_start if start_frame is None else int(start_frame)
    options = dataclasses.replace(options or LipSyncOptions(), fps=fps)
    script = read_script(source) if source.strip() else None
    if script is None:
        cast = _solo(
            context, head, source, options, gaze_target, (start, fps, audio_folder, package), progress
        )
    else:
        cast = _conversation(
            context, script, choices or {}, options, sources, (start, fps, audio_folder, package), progress
        )
    # From here on Blender data changes; nothing below raises LipSyncError for bad input.
    progress(0.55, "Keying the characters")
    previous = conversation_record(scene)
    _forget_previous(scene, previous, set(cast.heads.values()), cast.scene.solo)
    actions, warnings = _key_characters(context, cast, source, start)
    progress(0.85, "Placing the speech in the sequencer")
    strips = _place_sound(scene, cast, start)
    frame_count = shown_frame_count(cast.scene.speech.duration, fps)
    warnings += sequencer.fit_frame_range(scene, start, frame_count)
    if not cast.scene.solo:
        _keep_cast_record(scene, cast, strips, fps)
    progress(1.0, "Animation generated")
    roles = {role.key: role.name for role in cast.scene.speech.cast.roles}
    return GenerateResult(
        heads={roles[key]: name for key, name in cast.heads.items()},
        action_names=tuple(actions),
        strip_names=strips,
        wav_path=str(cast.mix_path) if cast.mix_path else None,
        frame_start=start,
        frame_end=start + frame_count - 1,
        fps=fps,
        scene=cast.scene,
        warnings=tuple(dict.fromkeys((*cast.scene.warnings, *cast.warnings, *warnings))),
    )


def _solo(context, head, source: str, options: LipSyncOptions, gaze_target: str, where, progress) -> _Cast:
    """One head speaking a text: its rig set up for the gaze, the text spoken and moved, its WAV written."""
    start, fps, audio_folder, package = where
    if head is None:
        raise HeadError(
            "The text has no speakers, so one head speaks it: choose the head in the Lip Sync panel and "
            "build its shape keys first."
        )
    objects = pipeline.head_objects(head)
    character.check_can_speak(head, objects)
    rig, target_warning = None, ""
    if options.living().any:  # the eyes, the head's pivot and the target matter only to the living layers
        rig, target = living.rig_and_target(context, head, objects, gaze_target)
        setup, target_warning = rig.gaze_setup(target)
        options = dataclasses.replace(options, gaze_setup=setup)
    face = character.face_rig_for(context, head, rig)  # the head's face rig, if it has one
    rig = face_rig.hand_eyes_to_rig(rig, face) if rig is not None else None
    progress(0.05, timing_source_for(speech_request(source, options)).working)
    spoken = lip_sync(source, options)
    scene = solo_scene(spoken)
    wav_path = None
    if spoken.synthesis is not None:
        progress(0.45, "Saving the speech audio")
        name = action_name_for(spoken.utterance)
        wav_path = sequencer.write_speech_wav(name, spoken.synthesis, audio_folder, package)
    warned = (target_warning,) if target_warning and options.living().gaze > 0 else ()
    key = scene.characters[0].role.key
    return _Cast(scene, {key: head.name}, {key: rig}, {key: face}, [], wav_path, warned)


def _conversation(context, script, choices, options, sources, where, progress) -> _Cast:
    """A script spoken by its cast: the lines and their WAVs first, then each speaker's head (made where
    the cast names none: Blender data changes from here) and where it stands, then every character moved."""
    start, fps, audio_folder, package = where
    cast = cast_for(script, choices, options.emotion_strength)
    progress(0.05, f"Speaking {len(script.lines)} lines of {len(cast.roles)} speakers")
    speech = scene_speech(script, cast, options, sources)
    progress(0.3, "Saving the lines' audio")
    sounds, mix_path = _write_sounds(speech, start, fps, audio_folder, package)
    progress(0.35, "Casting the heads")
    heads = conversation.cast_heads(context, cast)
    rigs, standings, camera = conversation.standings(context, cast, heads)
    progress(0.45, "Moving every character")
    scene = scene_motion(speech, options, standings, camera)
    faces = {
        key: character.face_rig_for(context, bpy.data.objects[name], rigs[key]) for key, name in heads.items()
    }
    return _Cast(scene, heads, dict(rigs), faces, sounds, mix_path)


def _key_characters(context, cast: _Cast, source: str, start: int) -> tuple[list[str], list[str]]:
    """Every character keyed: its living motion (the head and eyes first: their keying reads the rest pose,
    which the scene evaluates at once while the shape keys are not yet animated), its keys or face rig,
    and its record. Returns the actions written and the warnings."""
    actions: list[str] = []
    warnings: list[str] = []
    for number, played in enumerate(cast.scene.characters):
        key = played.role.key
        head = bpy.data.objects[cast.heads[key]]
        moved = living.key_living_motion(context, cast.rigs[key], played.tracks, start, clear=number == 0)
        name = _action_name(played, cast.scene, head)
        keyed = character.key_speech(
            head, pipeline.head_objects(head), played.tracks, start, name, cast.faces[key]
        )
        actions += keyed.action_names
        text = source if cast.scene.solo else character_text(cast.scene, key)
        _keep_record(head, cast.scene, played, start, text)
        warnings += [*moved.warnings, *keyed.warnings, *pipeline.own_keys_held_warning(head)]
    return actions, warnings


def _place_sound(scene: bpy.types.Scene, cast: _Cast, start: int) -> tuple[str, ...]:
    """The speech in the sequencer: one head's TR_speech strip; a conversation's strip per piece of its
    sound, on the lowest channel free for each, and its mix as the scene's speech. Returns the strips."""
    if cast.scene.solo:
        if cast.mix_path is None:
            sequencer.remove_speech_strip(scene)
            scene.pop(sequencer.SPEECH_PATH_PROPERTY, None)
            return ()
        strip = sequencer.place_speech_strip(scene, cast.mix_path, start, cast.scene.speech.duration)
        return (strip,) if strip else ()
    if cast.mix_path is None:
        scene.pop(sequencer.SPEECH_PATH_PROPERTY, None)
    return sequencer.place_scene_strips(scene, cast.sounds, cast.mix_path)


def _forget_previous(scene, previous: ConversationRecord | None, keeping: set[str], solo: bool) -> None:
    """What the last Generate made that this one does not replace: a conversation's strips and record
    (its characters keep their keys, as any other head does, unless this is a conversation that no longer
    casts them: they rest), and one head's speech strip."""
    if solo:
        if previous is not None:
            sequencer.remove_scene_strips(scene, previous.strips)
            forget_conversation_record(scene)
        return
    sequencer.remove_speech_strip(scene)
    if previous is None:
        return
    sequencer.remove_scene_strips(scene, previous.strips)
    for obj in previous.head_objects():
        if obj.name not in keeping:
            keyframes.remove_weight_tracks(pipeline.head_objects(obj))


def _keep_cast_record(scene: bpy.types.Scene, cast: _Cast, strips: tuple[str, ...], fps: float) -> None:
    roles = cast.scene.speech.cast.roles
    keep_conversation_record(
        scene,
        ConversationRecord(
            heads=dict(cast.heads),
            names={role.key: role.name for role in roles},
            strips=strips,
            fps=fps,
            duration=cast.scene.speech.duration,
        ),
    )


# ---------------------------------------------------------------- names, records, sounds


def action_name_for(utterance: Utterance) -> str:
    """One head's action, named after its words (Blender names hold at most 63 bytes)."""
    words = " ".join(word.text for word in utterance.words)
    name = OWNED_PREFIX + re.sub(r"\s+", " ", words).strip()
    while len(name.encode("utf-8")) > 60:
        name = name[:-1]
    return name


def _action_name(played: Character, scene: SceneResult, head: bpy.types.Object) -> str:
    """A character's action: one head's after its words; a speaker's after its name and first words,
    short enough that its parts' actions (the name, a dot and the part's name) fit Blender's 63 bytes."""
    if scene.solo:
        return action_name_for(scene.speech.lines[0].utterance)
    words = " ".join(
        word.text
        for line in scene.speech.lines
        if line.speaker == played.role.key
        for word in line.utterance.words
    )
    longest = max((len(part.name.encode("utf-8")) for part in pipeline.head_objects(head)[1:]), default=0)
    room = max(63 - 1 - longest, 24)
    name = f"{OWNED_PREFIX}{played.role.name}: {words}"
    while len(name.encode("utf-8")) > room:
        name = name[:-1]
    return name.rstrip()


def character_text(scene: SceneResult, key: str) -> str:
    """A character's lines as spoken, one a line (what its exports name as its text)."""
    return "\n".join(
        " ".join(word.text for word in line.utterance.words)
        for line in scene.speech.lines
        if line.speaker == key
    )


def _keep_record(
    head: bpy.types.Object, scene: SceneResult, played: Character, start: int, text: str
) -> None:
    """The character's own timeline and motion beside its keys, with the settings it was made with: what
    its exports describe."""
    action = character.record_holder(head, pipeline.RECORD_PROPERTY)
    if action is None:
        return
    settings = {
        name: str(value) if isinstance(value, Path) else value
        for name, value in dataclasses.asdict(scene.options).items()
    }
    role = played.role
    if role.name:  # a speaker of a script: its voice too
        settings |= {
            "speaker": role.name,
            "voice": role.voice.variant,
            "voice_pitch": role.voice.pitch,
            "voice_rate": role.voice.rate,
            "emotion_strength": role.emotion_strength,
        }
    record = AnimationRecord(
        text=text,
        timeline=played.timeline,
        fps=played.tracks.fps,
        frame_start=start,
        frame_count=played.tracks.frame_count,
        settings=settings,
        key_fingerprint=keyframes.key_fingerprint(pipeline.head_objects(head)),
        warnings=scene.warnings,
        head_and_eyes=played.tracks.head_and_eyes,
    )
    action[pipeline.RECORD_PROPERTY] = record_to_json(record)


def _write_sounds(speech, start: int, fps: float, folder: str, package: str | None):
    """Every piece of a scene's sound as a WAV, with the strip it becomes (named after its speaker and
    line, placed to the sample: a piece starting between frames gets that much silence first), and the
    whole scene's mix."""
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
