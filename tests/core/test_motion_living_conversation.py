"""The living layers of a conversation: whom a character attends to, its nods while listening, its gaze on
the speaker's face and on whom it addresses."""

from __future__ import annotations

import numpy as np

from turkish_lipsync.core.base.rotations import direction, head_matrices
from turkish_lipsync.core.motion.living.conversation import (
    LISTENING,
    SPEAKING,
    Turn,
    attention_spans,
    back_channel_nods,
)
from turkish_lipsync.core.motion.living.measures import angle_between, nods
from turkish_lipsync.core.motion.living.parameters import living_parameters
from turkish_lipsync.core.motion.living.phrases import SpeechStructure
from turkish_lipsync.core.pipeline import LipSyncOptions
from turkish_lipsync.core.scene import cast_for, converse
from turkish_lipsync.core.scene.layout import default_standings, face_path, surroundings
from turkish_lipsync.core.text.script import read_script

TURNS = (Turn("ayşe", "ali", 0.2, 4.0), Turn("ali", "ayşe", 4.3, 9.0), Turn("ayşe", "camera", 9.3, 12.0))


def _at(spans, time):
    return next((a.mode, a.target) for a in spans if a.start <= time <= a.end)


def test_attention_follows_the_turns_and_goes_to_the_next_speaker_a_moment_early() -> None:
    ali = attention_spans("ali", TURNS, 13.0, anticipation=0.2)
    ayse = attention_spans("ayşe", TURNS, 13.0, anticipation=0.2)
    assert _at(ali, 2.0) == (LISTENING, "ayşe") and _at(ali, 6.0) == (SPEAKING, "ayşe")
    assert _at(ayse, 2.0) == (SPEAKING, "ali") and _at(ayse, 6.0) == (LISTENING, "ali")
    assert _at(ayse, 10.0) == (SPEAKING, "camera")
    assert _at(ali, 9.2) == (LISTENING, "ayşe")  # the next speaker, 0.1 s before she speaks
    assert _at(ayse, 4.15) == (LISTENING, "ali")  # between turns: on whom she spoke to
    covered = sum(a.end - a.start for a in ali)
    assert abs(covered - 13.0) < 1e-9


def test_listeners_nod_at_the_speakers_phrase_ends_and_never_over_their_own_line() -> None:
    phrases = tuple((start, start + 1.6) for start in np.arange(0.2, 60.0, 2.0))
    structure = SpeechStructure(60.0, (), phrases, (), None)
    turns = (Turn("ayşe", "ali", 0.2, 30.0), Turn("ali", "ayşe", 30.3, 44.0), Turn("ayşe", "ali", 44.3, 60.0))
    spans = attention_spans("ali", turns, 60.0, 0.2)
    times = np.arange(0, 60.0, 1 / 25)
    pitch = back_channel_nods(
        spans, structure, times, np.random.default_rng(3), living_parameters()["listening"]
    )
    found = nods(pitch, 25)
    assert 2 <= len(found) <= 14
    ends = np.array([end for _, end in phrases])
    assert all(np.min(np.abs(ends - t)) <= 0.5 for t in found)
    assert not any(30.0 <= t <= 44.2 for t in found)  # Ali speaks then
    assert pitch.min() < -3.0 and pitch.max() <= 0.0  # down, and back


def test_gaze_holds_the_speaker_while_listening_and_the_addressee_part_of_the_time_while_speaking() -> None:
    script = read_script(open("examples/conversation.txt", encoding="utf-8").read())
    cast = cast_for(script)
    scene = converse(script, cast, LipSyncOptions(fps=25, timing="table"))
    standings, camera = default_standings(cast.keys)
    # The others' faces where their heads turn them (a character looks at a face, not where it was).
    faces = {
        c.role.key: face_path(standings[c.role.key], c.tracks.head_and_eyes.head) for c in scene.characters
    }
    for character in scene.characters:
        motion = character.tracks.head_and_eyes
        times = np.arange(len(motion.head)) / character.tracks.fps
        rotations = head_matrices(motion.head)
        eye = standings[character.role.key].setup.eye_positions()[0]
        gaze = np.einsum("nij,nj->ni", rotations, direction(motion.left_eye[:, 0], motion.left_eye[:, 1]))
        points = surroundings(character.role.key, standings, camera, faces).points
        on = {SPEAKING: [], LISTENING: []}
        for line in scene.speech.lines:
            inside = (times >= line.first_phone) & (times <= line.last_phone)
            mine = line.speaker == character.role.key
            target = np.broadcast_to(points[line.addressee if mine else line.speaker], gaze.shape)
            off = angle_between(gaze[inside], target[inside] - rotations[inside] @ eye)
            on[SPEAKING if mine else LISTENING].append(off < 5.0)
        listening = np.concatenate(on[LISTENING]).mean()
        speaking = np.concatenate(on[SPEAKING]).mean()
        assert listening >= 0.6 and 0.2 <= speaking <= 0.7 and listening > speaking
