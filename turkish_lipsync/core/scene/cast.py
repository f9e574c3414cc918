"""The cast: who plays each speaker of a script, with which voice, how strongly their emotions show.

Every speaker gets a voice of their own: the script's or the user's choice, else an eSpeak NG variant of the
Turkish voice by gender (the script's GENDER, else a known given name, else whichever gender the cast has
fewest of), the n-th speaker of a gender the n-th variant and pitch and rate steps (conversation.toml), so
no two speakers sound alike. A head is the user's (a Blender object's name or a file) or "" for the default
head, which the Blender side gives each speaker in a tone of its own.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

from ..base.errors import LipSyncError
from ..base.model import Style, Utterance
from ..text.jsml import markup_error
from ..text.script import Script, ScriptSpeaker, speaker_key
from ..text.tables import turkish_lower
from .tables import Voices, conversation_table

GENDERS = ("female", "male")
PITCH_RANGE = (0.5, 2.0)
RATE_RANGE = (0.5, 2.0)


@dataclass(frozen=True)
class Voice:
    """A speaker's voice: an eSpeak NG variant of the Turkish voice, its pitch and rate (multipliers)."""

    variant: str
    pitch: float = 1.0
    rate: float = 1.0

    def style(self, style: Style, rate: float = 1.0) -> Style:
        """A stretch of markup spoken in this voice (the markup's own rates and pitches multiply with it),
        at the scene's rate too."""
        return replace(
            style, voice=self.variant, pitch=style.pitch * self.pitch, rate=style.rate * self.rate * rate
        )


@dataclass(frozen=True)
class Role:
    key: str  # the speaker's key in the script (speaker_key)
    name: str  # as the script writes it
    gender: str  # "female" or "male"
    voice: Voice
    head: str = ""  # the head that plays it: an object's name, a file, or "" for the default head
    emotion_strength: float = 1.0
    recording: Path | None = None  # a recording of this speaker's lines, a track of the whole scene


@dataclass(frozen=True)
class RoleChoice:
    """What the user chose for a speaker (a panel row, render.py's --cast and --voice); None: the cast's
    own choice."""

    head: str = ""
    gender: str | None = None
    variant: str | None = None
    pitch: float | None = None
    rate: float | None = None
    emotion_strength: float | None = None
    recording: Path | None = None


@dataclass(frozen=True)
class Cast:
    roles: tuple[Role, ...]

    def role(self, key: str) -> Role:
        return next(role for role in self.roles if role.key == key)

    @property
    def keys(self) -> tuple[str, ...]:
        return tuple(role.key for role in self.roles)


def known_variants() -> tuple[str, ...]:
    voices = conversation_table().voices
    return voices.female + voices.male


def cast_for(
    script: Script, choices: dict[str, RoleChoice] | None = None, emotion_strength: float = 1.0
) -> Cast:
    """A role for every speaker of the script, in the order they first speak; choices are by speaker name
    (any case)."""
    table = conversation_table()
    choices = {speaker_key(name): choice for name, choice in (choices or {}).items()}
    unknown = sorted(set(choices) - {speaker.key for speaker in script.speakers})
    if unknown:
        names = ", ".join(speaker.name for speaker in script.speakers)
        raise LipSyncError(
            f"The cast names {', '.join(unknown)}, who never speaks in the script; the speakers are {names}."
        )
    genders = _genders(script, choices, table.names)
    roles = []
    taken: dict[str, int] = dict.fromkeys(GENDERS, 0)
    for speaker in script.speakers:
        gender = genders[speaker.key]
        number = taken[gender]  # the n-th speaker of the gender takes the n-th voice and steps
        taken[gender] += 1
        choice = choices.get(speaker.key, RoleChoice())
        voice = _voice(script, speaker, choice, table.voices, gender, number)
        strength = emotion_strength if choice.emotion_strength is None else choice.emotion_strength
        if not 0.0 <= strength <= 1.0:
            raise LipSyncError(f"The emotion strength {strength:g} of {speaker.name} is outside 0..1.")
        roles.append(Role(speaker.key, speaker.name, gender, voice, choice.head, strength, choice.recording))
    return Cast(tuple(roles))


def _genders(script: Script, choices: dict[str, RoleChoice], names: dict[str, str]) -> dict[str, str]:
    """Each speaker's gender: the user's choice, the script's, a known given name's, else the gender the
    cast has fewest of."""
    genders: dict[str, str | None] = {}
    for speaker in script.speakers:
        choice = choices.get(speaker.key, RoleChoice())
        gender = choice.gender or speaker.gender or _gender_of_name(speaker.name, names)
        if gender is not None and gender not in GENDERS:
            raise LipSyncError(f"The gender {gender!r} of {speaker.name} is not one of {', '.join(GENDERS)}.")
        genders[speaker.key] = gender
    for key, gender in genders.items():  # the undecided take the gender the cast has fewest of
        if gender is None:
            counts = {g: sum(1 for other in genders.values() if other == g) for g in GENDERS}
            genders[key] = min(GENDERS, key=lambda g: counts[g])
    return genders


def _voice(
    script: Script, speaker: ScriptSpeaker, choice: RoleChoice, voices: Voices, gender: str, number: int
) -> Voice:
    """The speaker's voice: the chosen or written variant, pitch and rate, else the number-th of the
    gender's variants and steps (conversation.toml)."""
    variants = voices.of(gender)
    written = choice.variant or speaker.variant
    variant = _variant(written, variants, script, speaker) if written else variants[number % len(variants)]
    pitch = choice.pitch if choice.pitch is not None else voices.pitch_steps[number % len(voices.pitch_steps)]
    rate = choice.rate if choice.rate is not None else voices.rate_steps[number % len(voices.rate_steps)]
    for what, value, bounds in (("pitch", pitch, PITCH_RANGE), ("rate", rate, RATE_RANGE)):
        if not bounds[0] <= value <= bounds[1]:
            raise LipSyncError(
                f"The voice {what} {value:g} of {speaker.name} is outside {bounds[0]:g}..{bounds[1]:g}; "
                "choose a multiplier such as 0.9 or 1.1."
            )
    return Voice(variant, pitch, rate)


def _gender_of_name(name: str, names: dict[str, str]) -> str | None:
    first = turkish_lower(name.split()[0]) if name.split() else ""
    return names.get(first)


def _variant(written: str, variants: tuple[str, ...], script: Script, speaker) -> str:
    """A voice the script or the user asked for: a variant's name, or JSML's number (the n-th of the
    speaker's gender)."""
    written = written.strip().lower()
    if written.isdigit() and 1 <= int(written) <= len(variants):
        return variants[int(written) - 1]
    if written in known_variants():
        return written
    message = (
        f"{speaker.name}'s voice {written!r} is not one of the voices ({', '.join(known_variants())}) "
        f"or a number 1-{len(variants)}"
    )
    if speaker.variant == written:
        raise markup_error(script.source, speaker.offset, message)
    raise LipSyncError(message + ".")


def spoken_by(utterance: Utterance, role: Role, rate: float = 1.0) -> Utterance:
    """The utterance in the role's voice, at the scene's rate too."""
    words = tuple(replace(word, style=role.voice.style(word.style, rate)) for word in utterance.words)
    return replace(utterance, words=words)
