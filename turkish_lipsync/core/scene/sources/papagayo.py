"""A Papagayo project with one voice per speaker (as the scene's own export writes it): each voice times that
speaker's lines, its sound the scene's."""

from __future__ import annotations

from pathlib import Path

from ...base.errors import LipSyncError
from ...base.model import Timeline
from ...speech import Synthesis
from ...speech.audio import read_audio, to_pcm16
from ...speech.cue_timing import timeline_from_cues
from ...speech.cues import CueSource
from ...speech.cues.papagayo_pgo import read_pgo_voices, rest_between, spoken_words
from ...text.script import speaker_key
from ..speech import SceneLine, SceneSpeech, SoundPiece, scene_utterance, split_timeline
from .base import SCENE_SOURCES, SceneRequest, SceneSource


@SCENE_SOURCES.register
class PapagayoProject(SceneSource):
    name = "papagayo project"
    given_as = "a cue file"
    priority = 20

    def claims(self, request: SceneRequest) -> bool:
        return request.cues is not None

    def speak(self, request: SceneRequest) -> SceneSpeech:
        path = Path(request.cues)
        voices = read_pgo_voices(path)
        chosen = _voices_of_speakers(path, voices, request)
        timelines: dict[int, Timeline] = {}
        warnings: list[str] = []
        duration = max(voice.duration_frames / voice.fps for voice in voices)
        for role in request.cast.roles:
            own = [index for index, line in enumerate(request.script.lines) if line.speaker == role.key]
            timeline, found = _voice_timeline(path, chosen[role.key], request, own, duration)
            warnings += [f"{role.name}: {w}" for w in found]
            duration = max(duration, timeline.duration)
            parts = split_timeline(timeline, [request.utterances[i] for i in own], duration)
            timelines.update(zip(own, parts, strict=True))
        addressees = request.addressees
        lines = tuple(
            SceneLine(index, line.speaker, addressees[index], timelines[index], request.utterances[index])
            for index, line in enumerate(request.script.lines)
        )
        pieces = ()
        sound = path.parent / voices[0].sound_path if voices[0].sound_path else None
        if sound is not None and sound.is_file():
            samples, rate = read_audio(sound)
            pieces = (
                SoundPiece("scene", None, 0.0, Synthesis(to_pcm16(samples), rate, (), (), "recording")),
            )
        elif voices[0].sound_path:
            warnings.append(
                f"{path} names the sound {voices[0].sound_path}, which is not there: the scene is silent."
            )
        return SceneSpeech(request.script, request.cast, lines, pieces, duration, "cues", tuple(warnings))


def _voices_of_speakers(path: Path, voices, request: SceneRequest) -> dict:
    """Each speaker's voice of the project: matched by name, else in order where the project has as many
    voices as the script speakers."""
    roles = request.cast.roles
    by_name = {speaker_key(voice.voice_name): voice for voice in voices}
    if all(role.key in by_name for role in roles):
        return {role.key: by_name[role.key] for role in roles}
    if len(voices) == len(roles):
        return {role.key: voice for role, voice in zip(roles, voices, strict=True)}
    names = ", ".join(voice.voice_name for voice in voices)
    raise LipSyncError(
        f"{path} has the voices {names}, which do not match the script's speakers "
        f"({', '.join(role.name for role in roles)}): name each voice after its speaker."
    )


def _voice_timeline(path: Path, voice, request: SceneRequest, own: list[int], duration: float):
    """(timeline, warnings) of one voice's cues over its speaker's lines spoken as one utterance."""
    whole = scene_utterance(request.script, request.cast, own, request.rate)
    words = spoken_words(voice)
    cues = rest_between(words)
    if not cues:
        raise LipSyncError(
            f"{path}: the voice {voice.voice_name} holds no phonemes; break its words down first"
        )
    source = CueSource(path, cues, duration, text=voice.text, sound_file=voice.sound_path, word_cues=words)
    return timeline_from_cues(whole, source)
