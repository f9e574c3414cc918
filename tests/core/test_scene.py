"""A scene from a script: the cast's voices, the lines laid out with conversational gaps, each character's
mouth only in its own lines, and the layers of listening and addressing."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from lab.kit.voices import cast_reading
from turkish_lipsync.core.base.errors import LipSyncError, MarkupError
from turkish_lipsync.core.base.model import Hesitation, Timeline, viseme_key_name
from turkish_lipsync.core.motion.living.prosody import measure_prosody
from turkish_lipsync.core.pipeline import LipSyncOptions
from turkish_lipsync.core.scene import RoleChoice, cast_for, converse
from turkish_lipsync.core.scene.sources.spoken import line_starts
from turkish_lipsync.core.scene.speech import split_timeline
from turkish_lipsync.core.scene.tables import conversation_table
from turkish_lipsync.core.speech.timing import table_timeline
from turkish_lipsync.core.text.script import read_script
from turkish_lipsync.core.text.utterance import build_utterance

SCRIPT = """AYŞE (to ALİ): Merhaba Ali, nasılsın? Bugün seni çok yorgun gördüm.
ALİ: İyiyim, sağ ol. Dün gece geç yattım, o yüzden biraz yorgunum.
AYŞE: <SURPRISED>Neden</SURPRISED> bu kadar geç yattın?
ALİ: Yeni bir kitap okuyordum, bırakamadım. Çok güzel bir roman, sana da veririm.
"""


def test_the_cast_gives_every_speaker_a_voice_of_their_own() -> None:
    script = read_script("AYŞE: Merhaba.\nALİ: Selam.\nZEYNEP: Günaydın.\nKAAN: İyi günler.")
    cast = cast_for(script)
    genders = {role.name: role.gender for role in cast.roles}
    assert genders == {"Ayşe": "female", "Ali": "male", "Zeynep": "female", "Kaan": "male"}  # Kaan: fewest
    voices = [role.voice for role in cast.roles]
    assert len(set(voices)) == 4
    assert cast.role("ayşe").voice.variant in conversation_table().voices.female
    chosen = cast_for(script, {"Ali": RoleChoice(head="Kafa", variant="m7", pitch=0.8)})
    assert chosen.role("ali").voice.variant == "m7" and chosen.role("ali").voice.pitch == 0.8
    assert chosen.role("ali").head == "Kafa"


def test_the_cast_refuses_what_it_cannot_play() -> None:
    script = read_script("AYŞE: Merhaba.\nALİ: Selam.")
    with pytest.raises(LipSyncError, match="never speaks"):
        cast_for(script, {"Veli": RoleChoice()})
    with pytest.raises(MarkupError, match="'robot'"):
        cast_for(read_script('<VOICE NAME="A" VARIANT="robot">Merhaba.</VOICE>'))
    with pytest.raises(LipSyncError, match="pitch 3"):
        cast_for(script, {"Ayşe": RoleChoice(pitch=3.0)})


def test_lines_follow_each_other_with_conversational_gaps_breaks_and_overlaps() -> None:
    script = read_script(
        "AYŞE: Bir.\nALİ: İki.\nAYŞE: Üç.\nAYŞE: Dört.\n"
        'ALİ (overlapping): Beş.\n<BREAK TIME="2s"/>\nAYŞE: Altı.'
    )
    firsts, lasts = [0.1] * 6, [1.1] * 6
    turns = conversation_table().turns
    starts = line_starts(script, firsts, lasts, np.random.default_rng(0), turns)
    first_phones = [s + 0.1 for s in starts]
    last_phones = [s + 1.1 for s in starts]
    gaps = [first_phones[i] - last_phones[i - 1] for i in range(1, 6)]
    assert all(turns.gap_min <= gap <= turns.gap_max for gap in gaps[:2])
    assert gaps[2] == pytest.approx(turns.same_speaker_gap)
    assert gaps[3] == pytest.approx(-turns.overlap)
    assert first_phones[5] - max(last_phones[:5]) == pytest.approx(2.0)
    many = [
        line_starts(
            read_script("AYŞE: Bir.\nALİ: İki."), [0.0, 0.0], [1.0, 1.0], np.random.default_rng(s), turns
        )[1]
        - 1.0
        for s in range(200)
    ]
    assert 0.15 <= float(np.median(many)) <= 0.3  # about 200 ms between turns (Stivers et al. 2009)


@pytest.fixture(scope="module")
def scene():
    script = read_script(SCRIPT)
    return converse(script, cast_for(script), LipSyncOptions(fps=25))


def test_each_mouth_moves_only_in_its_own_lines(scene) -> None:
    lines = scene.speech.lines
    assert [line.speaker for line in lines] == ["ayşe", "ali", "ayşe", "ali"]
    for before, after in zip(lines, lines[1:], strict=False):
        assert 0.1 <= after.first_phone - before.last_phone <= 0.6
    for character in scene.characters:
        tracks = character.tracks
        frames = np.arange(tracks.frame_count)
        names, weights = tracks.sample(frames)
        jaw = weights[:, names.index(viseme_key_name("a"))] + weights[:, names.index(viseme_key_name("e"))]
        times = frames / tracks.fps
        own = np.zeros(frames.size, bool)
        others = np.zeros(frames.size, bool)
        for line in lines:
            inside = (times >= line.first_phone) & (times <= line.last_phone)
            (own if line.speaker == character.role.key else others)[inside] = True
        assert jaw[own].max() > 0.5
        assert jaw[others & ~own].max() < 0.02


def test_speakers_sound_different(scene) -> None:
    pitch = {}
    for character in scene.characters:
        prosody = measure_prosody(character.voice.samples, character.voice.sample_rate)
        pitch[character.role.gender] = np.nanmedian(prosody.f0)
    assert pitch["female"] > 1.4 * pitch["male"]


def test_listeners_look_at_the_speaker_and_speakers_at_whom_they_address(scene) -> None:
    for character in scene.characters:
        attention = character.tracks.extra["attention"]
        for line in scene.speech.lines:
            middle = (line.first_phone + line.last_phone) / 2
            mode, target = next((m, t) for s, e, m, t in attention if s <= middle <= e)
            if line.speaker == character.role.key:
                assert (mode, target) == ("speaking", line.addressee)
            else:
                assert (mode, target) == ("listening", line.speaker)


def test_a_single_speaker_text_is_not_a_scene() -> None:
    assert read_script("Merhaba, benim adım Erdem.") is None


@pytest.mark.parametrize("kind", ["scene", "speakers"])
def test_a_recording_of_the_scene_or_of_each_speaker_times_every_line(tmp_path, scene, kind) -> None:
    """The truth is the synthesised scene itself: each line where the gaps put it."""
    from turkish_lipsync.core.scene import scene_speech
    from turkish_lipsync.core.scene.speech import SceneSources
    from turkish_lipsync.core.speech import write_wav

    truth = scene.speech
    if kind == "scene":
        sources = SceneSources(scene_recording=write_wav(tmp_path / "scene.wav", truth.mix()))
    else:
        tracks = {
            r.key: write_wav(tmp_path / f"{r.key}.wav", truth.voice_of(r.key)) for r in truth.cast.roles
        }
        sources = SceneSources(speaker_recordings=tracks)
    aligned = scene_speech(truth.script, truth.cast, LipSyncOptions(fps=25), sources)
    for line, true in zip(aligned.lines, truth.lines, strict=True):
        assert abs(line.first_phone - true.first_phone) < 0.05
        assert {p.word_index for p in line.timeline.phones} == {p.word_index for p in true.timeline.phones}
    assert len(aligned.pieces) == (1 if kind == "scene" else 2)


def test_an_overlapping_line_in_one_recording_of_the_scene_starts_where_it_is_said(tmp_path) -> None:
    """The line said over the other's last word: the acoustic model hears the other voice as its first word,
    so that word is placed back from the second by its own length at the speaker's pace."""
    from turkish_lipsync.core.scene import scene_speech
    from turkish_lipsync.core.scene.speech import SceneSources
    from turkish_lipsync.core.speech import write_wav

    script = read_script(
        "AYŞE: Geçen hafta yeni bir işe başladım, ilk gün bana pasta bile getirdiler.\n"
        "ALİ (overlapping): Pasta mı?\n"
        "AYŞE: Evet, çikolatalı bir pasta. Çok şaşırdım ama çok da sevindim.\n"
        "ALİ: Ne hoş. Peki, bu akşam boş musun?"
    )
    cast = cast_for(script)
    for reading in ({}, {"rate": 1.12, "pitch": 0.9}):
        choices = cast_reading(cast, reading)
        truth = converse(script, cast_for(script, choices), LipSyncOptions(fps=25)).speech
        take = write_wav(tmp_path / "scene.wav", truth.mix())
        found = scene_speech(script, cast, LipSyncOptions(fps=25), SceneSources(scene_recording=take))
        errors = [abs(a.first_phone - b.first_phone) for a, b in zip(found.lines, truth.lines, strict=True)]
        assert max(errors) < 0.05, (reading, errors)


def test_an_overlapping_line_that_moves_with_its_stretch_took_the_other_voice_for_its_first_word() -> None:
    """A line heard where it is said begins there from any stretch; one that begins 0.1 s earlier when the
    stretch does (the other voice heard as its first word) is not taken as it is."""
    from types import SimpleNamespace

    from turkish_lipsync.core.scene.sources.scene_recording import _moves_with

    def heard_at(begins_of):
        return lambda start: (SimpleNamespace(phones=[SimpleNamespace(start=begins_of(start))]), ())

    latching = heard_at(lambda start: start + 0.037)  # always just after the stretch's start
    said = heard_at(lambda start: 37.465)  # where the line is said, whatever the stretch
    assert _moves_with(latching, 37.428, 37.465)
    assert not _moves_with(said, 37.428, 37.465)
    assert not _moves_with(latching, 0.0, 0.037)  # a stretch from the take's start cannot begin earlier


def test_a_hesitation_said_aloud_goes_to_the_line_it_is_said_within() -> None:
    """One take of the scene, split into its lines: an "ııı" inside Ali's line is his; one in the gap
    between two lines is no one's (the take does not say whose)."""
    first, second = build_utterance("Merhaba Ali."), build_utterance("İyiyim, sağ ol.")
    ayse = table_timeline(first)
    ali = table_timeline(second).shifted(
        ayse.duration + 1.0, ayse.duration + 1.0 + table_timeline(second).duration
    )
    ali_pause = (ali.phones[5].end, ali.phones[6].start)  # the comma after "İyiyim"
    inside = Hesitation(ali_pause[0] + 0.01, ali_pause[1] - 0.01, "ı", "I")
    between = Hesitation(ayse.duration + 0.2, ayse.duration + 0.8, "e", "e")
    whole = dataclasses.replace(Timeline.joined([ayse, ali], ali.duration), hesitations=(between, inside))
    lines = split_timeline(whole, [first, second], whole.duration)
    assert lines[0].hesitations == () and lines[1].hesitations == (inside,)
    assert [p.start for p in lines[1].phones] == [p.start for p in ali.phones]
