"""A scene from a text: one head speaking it, or several characters from one script, each speaking its
lines and listening to the others.

`perform(source, options)` is the one entry for both: a text with no speakers is a cast of one (the head
speaks it all: `lip_sync`, with the living layers of one face to the camera), a script with speakers a
conversation. Either way the result is a SceneResult: the scene's speech and a Character per speaker
(its timeline, weight tracks and voice), which the command line, the exports and the Blender layer take
alike. `converse(script, cast, options)` is the conversation's part: the script's lines
spoken in each speaker's voice (or found in recordings) on one timeline (speech.py), then for every
character its own weight tracks (its mouth moves only in its lines) with the living layers of a
conversation (core/motion/living/conversation.py: whom it looks at, its head turned toward them, nods while
listening, blinks at the conversation's pauses), a faint echo of the emotion of the line it hears.

Why a stage of its own, between pipeline and interchange: it builds on the pipeline's options and on every
stage below (text for the script, speech for the voices, motion for the layers), and the exports and the
command line above it write and print what it makes; nothing below needs to know that several characters
exist.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..base.model import EMOTIONS, Timeline, WeightTracks, emotion_key_name, emotion_release_key_name
from ..motion import weight_tracks
from ..motion.frames import sparse_track
from ..motion.living.conversation import Turn, conversation_living_tracks
from ..motion.living.parameters import living_parameters
from ..pipeline import LipSyncOptions, LipSyncResult, lip_sync
from ..speech import Synthesis
from ..text.script import CAMERA, Script, read_script
from .cast import Cast, Role, RoleChoice, Voice, cast_for
from .layout import Standing, default_standings, face_path, surroundings
from .speech import SceneLine, SceneSources, SceneSpeech, SoundPiece, speak_scene, with_faint_emotions


@dataclass(frozen=True, eq=False)
class Character:
    """One character's part of the scene: its role, its own lines' timeline and its motion."""

    role: Role
    timeline: Timeline  # its own lines on the scene's timeline
    tracks: WeightTracks  # its mouth, emotions and living layers over the whole scene
    voice: Synthesis | None  # its voice alone on the scene's timeline


@dataclass(frozen=True, eq=False)
class SceneResult:
    options: LipSyncOptions
    speech: SceneSpeech
    characters: tuple[Character, ...]
    warnings: tuple[str, ...]

    def character(self, key: str) -> Character:
        return next(c for c in self.characters if c.role.key == key)

    @property
    def solo(self) -> bool:
        """Whether this is one head speaking a text with no speakers (a cast of one)."""
        return self.speech.script is None

    def sound(self) -> Synthesis | None:
        """Everything the scene says on its timeline (a cast of one: its speech as it is; None without
        audio)."""
        return self.characters[0].voice if self.solo else self.speech.mix()


# The one role of a text with no speakers: the head speaks it in the default voice.
SOLO_ROLE = Role(key="", name="", gender="", voice=Voice(""))


def perform(
    source: str,
    options: LipSyncOptions | None = None,
    *,
    cast: Cast | None = None,
    sources: SceneSources | None = None,
    standings: dict[str, Standing] | None = None,
    camera: np.ndarray | None = None,
) -> SceneResult:
    """The source spoken and every character moved: a script with speakers as a conversation (the cast by
    default from the script; sources by default the options' recording or cue file, as the whole scene's),
    any other text by one head (a cast of one: the options' recording or cue file is its own)."""
    options = options or LipSyncOptions()
    script = read_script(source) if source.strip() else None
    if script is None:
        return solo_scene(lip_sync(source, options))
    cast = cast or cast_for(script, emotion_strength=options.emotion_strength)
    return converse(script, cast, options, sources=sources, standings=standings, camera=camera)


def solo_scene(result: LipSyncResult) -> SceneResult:
    """One head's lip sync as a scene of one character: its one line said to the camera."""
    timeline, synthesis = result.timeline, result.synthesis
    line = SceneLine(0, SOLO_ROLE.key, CAMERA, timeline, result.utterance)
    pieces = () if synthesis is None else (SoundPiece("speech", SOLO_ROLE.key, 0.0, synthesis, 0),)
    speech = SceneSpeech(
        None, Cast((SOLO_ROLE,)), (line,), pieces, timeline.duration, timeline.timing, result.warnings
    )
    character = Character(SOLO_ROLE, timeline, result.tracks, synthesis)
    return SceneResult(result.options, speech, (character,), result.warnings)


def listener_tracks(
    own: Timeline, heard: list[Timeline], share: float, options: LipSyncOptions, strength: float
) -> WeightTracks:
    """A character's weight tracks: its own lines, and the emotions of the lines it hears at `share` of
    their weight on its upper face only (their mouth part released at once: a listener's mouth rests)."""
    tracks = weight_tracks(own, options.fps, mode=options.motion, emotion_strength=strength)
    echoed = with_faint_emotions(own, heard, share)
    if options.motion != "natural" or echoed is own:
        return tracks
    full = weight_tracks(echoed, options.fps, mode=options.motion, emotion_strength=strength)
    frames = np.arange(tracks.frame_count, dtype=np.float64)

    def values(source: WeightTracks, name: str) -> np.ndarray:
        track = source.track(name)
        return np.zeros(frames.size) if track is None else np.interp(frames, track.frames, track.values)

    changed = {}
    for emotion in EMOTIONS:
        name, release = emotion_key_name(emotion), emotion_release_key_name(emotion)
        faint = values(full, name) - values(tracks, name)
        if np.abs(faint).max(initial=0.0) < 1e-6:
            continue
        changed[name] = sparse_track(name, frames, values(full, name))
        changed[release] = sparse_track(release, frames, values(tracks, release) + faint)
    kept = tuple(track for track in tracks.tracks if track.name not in changed)
    return dataclasses.replace(tracks, tracks=kept + tuple(changed.values()))


def turns_of(speech: SceneSpeech) -> tuple[Turn, ...]:
    return tuple(
        Turn(line.speaker, line.addressee, line.first_phone, line.last_phone) for line in speech.lines
    )


def converse(
    script: Script,
    cast: Cast,
    options: LipSyncOptions | None = None,
    *,
    sources: SceneSources | None = None,
    standings: dict[str, Standing] | None = None,
    camera: np.ndarray | None = None,
) -> SceneResult:
    """Speak the script with the cast and move every character (standings: where each stands, by speaker
    key; the core's own arc and camera where not given)."""
    options = options or LipSyncOptions()
    return scene_motion(scene_speech(script, cast, options, sources), options, standings, camera)


def scene_speech(
    script: Script, cast: Cast, options: LipSyncOptions, sources: SceneSources | None = None
) -> SceneSpeech:
    """The scene's lines spoken (or found in recordings) with the options' timing, rate and engine; a
    recording or cue file of the options is the whole scene's."""
    sources = sources or SceneSources(scene_recording=options.recording, cues=options.cues)
    return speak_scene(
        script,
        cast,
        timing=options.timing,
        rate=options.rate,
        engine=options.engine,
        sources=sources,
        seed=options.seed,
        aligner=options.aligner,
    )


def scene_motion(
    speech: SceneSpeech,
    options: LipSyncOptions,
    standings: dict[str, Standing] | None = None,
    camera: np.ndarray | None = None,
) -> SceneResult:
    """Every character's tracks over the scene: its own lines' mouth, the faint emotions of what it hears,
    and the living layers of the conversation (see the module's text)."""
    cast = speech.cast
    if standings is None or camera is None:
        standings, camera = default_standings(cast.keys)
    # Twice: each character looks at the others' faces where they are; the second time where their heads
    # have turned them (a face 0.5 m away moves 5 degrees as its head turns toward whom it speaks to).
    characters = _characters(speech, options, standings, camera, None)
    faces = {
        c.role.key: face_path(standings[c.role.key], c.tracks.head_and_eyes.head)
        for c in characters
        if c.tracks.head_and_eyes is not None
    }
    if faces:
        characters = _characters(speech, options, standings, camera, faces)
    return SceneResult(options, speech, tuple(characters), speech.warnings)


def _characters(speech: SceneSpeech, options, standings, camera, faces) -> list[Character]:
    turns = turns_of(speech)
    mix = speech.mix()
    heard_voice = (mix.samples, mix.sample_rate) if mix is not None else None
    scene_timeline = speech.scene_timeline()
    share = living_parameters()["listening"]["emotion_share"]
    characters = []
    for number, role in enumerate(speech.cast.roles, start=1):
        own = speech.speaker_timeline(role.key)
        heard = [line.timeline for line in speech.lines if line.speaker != role.key]
        tracks = listener_tracks(own, heard, share, options, role.emotion_strength)
        living = dataclasses.replace(options.living(), setup=standings[role.key].setup, character=number)
        voice = speech.voice_of(role.key)
        tracks = conversation_living_tracks(
            tracks,
            own,
            living,
            role.key,
            turns,
            surroundings(role.key, standings, camera, faces),
            (voice.samples, voice.sample_rate) if voice is not None else None,
            heard_voice,
            scene_timeline,
        )
        if options.interpolation != "AUTO":
            tracks = dataclasses.replace(tracks, interpolation=options.interpolation)
        characters.append(Character(role, own, tracks, voice))
    return characters


__all__ = [
    "Cast",
    "Character",
    "Role",
    "RoleChoice",
    "SceneLine",
    "SceneResult",
    "SceneSources",
    "SceneSpeech",
    "SoundPiece",
    "Standing",
    "cast_for",
    "converse",
    "perform",
    "read_script",
    "scene_motion",
    "scene_speech",
]
