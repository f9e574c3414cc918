"""The core's one entry point: Turkish text in, the utterance, its speech, timeline and weight tracks out.

`lip_sync(source, options)` is what the command line, the Blender pipeline and scripts/render.py all call;
every option and its choices are defined here once (the panel's enum items are built from these choices).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

from .base.choices import Choice, identifiers
from .base.errors import LipSyncError
from .base.model import Timeline, Utterance, WeightTracks
from .motion import motion_choices, weight_tracks
from .motion.living import GazeSetup, LivingOptions, living_tracks
from .speech.aligner_settings import DEFAULT_ALIGNER, AlignerSettings
from .speech.recognition.settings import DEFAULT_RECOGNISER, RecogniserSettings
from .speech.sources import SpeechRequest, speak
from .speech.timeline import check_timing_follows
from .text.utterance import unspoken_warning

TIMING_CHOICES = (
    Choice("phone", "Phone", "Key every phone where the speech engine speaks it (most accurate)"),
    Choice("word", "Word", "The thesis's method: word starts from the engine, letters by mean durations"),
    Choice("table", "Table", "Mean letter durations only (thesis Table 5.4), no speech engine, no audio"),
)
MOTION_CHOICES = motion_choices()
INTERPOLATION_CHOICES = (
    Choice("AUTO", "Automatic", "What the motion model asks for"),
    Choice("LINEAR", "Linear", "Straight lines between keys"),
    Choice("BEZIER", "Bézier", "Smooth curves between keys"),
    Choice("CONSTANT", "Constant", "Hold each key until the next (stepped)"),
)
RATE_RANGE = (0.25, 4.0)
FPS_RANGE = (1.0, 240.0)
AMOUNT_RANGE = (0.0, 2.0)
# The living layers each motion model has when they are not chosen: the thesis had none.
LIVING_BY_DEFAULT = {"natural": True, "thesis": False}
LIVING_LAYERS = ("gaze", "blinks", "head_motion", "expression")


@dataclass(frozen=True)
class LipSyncOptions:
    """Everything that decides the motion a text gets, checked when made."""

    timing: str = "phone"
    motion: str = "natural"
    interpolation: str = "AUTO"
    rate: float = 1.0  # multiplier of every word's speaking rate
    emotion_strength: float = 1.0  # 0..1, scales the markup's emotion weights
    fps: float = 25.0
    recording: Path | None = None  # a recording of the text to align to instead of the synthetic voice
    engine: str = "espeak"
    # A Rhubarb/Papagayo/Moho cue file timing the visemes instead of an engine (speech/cue_timing.py);
    # the recording is then its audio as it is, not aligned.
    cues: Path | None = None
    # The living layers (motion/living): each on, off, or None for the motion model's default (on for the
    # natural model, off for the thesis's), with an amount (1 the model's own, 0..2) and one seed.
    gaze: bool | None = None
    gaze_amount: float = 1.0
    blinks: bool | None = None
    blink_amount: float = 1.0  # scales the blink rate
    head_motion: bool | None = None
    head_amount: float = 1.0
    expression: bool | None = None  # brow raises on accents and emphasis, emotions that breathe
    expression_amount: float = 1.0
    seed: int = 0
    gaze_setup: GazeSetup = dataclasses.field(default_factory=GazeSetup)
    aligner: AlignerSettings = DEFAULT_ALIGNER  # how a recording is aligned to its text
    recogniser: RecogniserSettings = DEFAULT_RECOGNISER  # how a recording alone is heard

    @classmethod
    def from_attributes(cls, source: object, **given) -> LipSyncOptions:
        """Options from any object naming them (the panel's settings, parsed command-line arguments)."""
        named = {
            field.name: getattr(source, field.name)
            for field in dataclasses.fields(cls)
            if field.name not in given and hasattr(source, field.name)
        }
        return cls(**named, **given)

    def __post_init__(self) -> None:
        for name, choices in (
            ("timing", TIMING_CHOICES),
            ("motion", MOTION_CHOICES),
            ("interpolation", INTERPOLATION_CHOICES),
        ):
            value = getattr(self, name)
            if value not in identifiers(choices):
                raise LipSyncError(f"Unknown {name} {value!r}; use one of {', '.join(identifiers(choices))}.")
        _require_range("speaking rate", self.rate, RATE_RANGE, "a multiplier such as 0.8 or 1.2")
        _require_range("emotion strength", self.emotion_strength, (0.0, 1.0), "a share such as 0.5")
        _require_range("frame rate", self.fps, FPS_RANGE, "frames per second such as 25 or 29.97")
        for name in ("gaze_amount", "blink_amount", "head_amount", "expression_amount"):
            _require_range(
                name.replace("_", " "), getattr(self, name), AMOUNT_RANGE, "1 for the usual amount"
            )
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise LipSyncError(
                f"The seed {self.seed!r} must be a whole number of at least 0, such as 0 or 7."
            )
        if not (0.05 <= self.gaze_setup.target_distance <= 1e4):
            raise LipSyncError(
                f"The gaze target is {self.gaze_setup.target_distance:g} m from the eyes; it must be 0.05 m "
                "to 10 km away (move the camera or the target object)."
            )
        if self.cues is not None:
            object.__setattr__(self, "cues", Path(self.cues))
        if self.recording is not None:
            object.__setattr__(self, "recording", Path(self.recording))
            # With a cue file the recording is only its sound, whatever the timing says.
            check_timing_follows(self.timing, self.cues is None)

    def living(self) -> LivingOptions:
        """The living layers' amounts for this motion model (0 where a layer is off)."""
        default = LIVING_BY_DEFAULT.get(self.motion, True)

        def amount(on: bool | None, value: float) -> float:
            return value if (default if on is None else on) else 0.0

        return LivingOptions(
            gaze=amount(self.gaze, self.gaze_amount),
            blinks=amount(self.blinks, self.blink_amount),
            head=amount(self.head_motion, self.head_amount),
            expression=amount(self.expression, self.expression_amount),
            seed=self.seed,
            setup=self.gaze_setup,
        )


def _require_range(name: str, value: float, bounds: tuple[float, float], example: str) -> None:
    low, high = bounds
    if not (isinstance(value, int | float) and math.isfinite(value) and low <= value <= high):
        raise LipSyncError(f"The {name} {value!r} is outside {low:g}..{high:g}; choose {example}.")


@dataclass(frozen=True, eq=False)
class LipSyncResult:
    """What lip_sync made, and what the user must be told about it."""

    options: LipSyncOptions
    utterance: Utterance
    synthesis: object  # speech.Synthesis, None for table timing
    timeline: Timeline
    tracks: WeightTracks
    warnings: tuple[str, ...]


def speech_request(source: str, options: LipSyncOptions) -> SpeechRequest:
    """What the timing sources are asked for the source text with these options."""
    return SpeechRequest(
        text=source,
        timing=options.timing,
        rate=options.rate,
        recording=options.recording,
        cues=options.cues,
        engine=options.engine,
        fps=options.fps,
        aligner=options.aligner,
        recogniser=options.recogniser,
    )


def lip_sync(source: str, options: LipSyncOptions | None = None) -> LipSyncResult:
    """Read the source as a Turkish speaker would, speak it (or align the recording), time it, move it."""
    options = options or LipSyncOptions()
    utterance, speech = speak(speech_request(source, options))
    tracks = weight_tracks(
        speech.timeline, options.fps, mode=options.motion, emotion_strength=options.emotion_strength
    )
    synthesis = speech.synthesis
    tracks = living_tracks(
        tracks,
        speech.timeline,
        options.living(),
        getattr(synthesis, "samples", None),
        getattr(synthesis, "sample_rate", 0),
    )
    if options.interpolation != "AUTO":
        tracks = dataclasses.replace(tracks, interpolation=options.interpolation)
    return LipSyncResult(
        options=options,
        utterance=utterance,
        synthesis=speech.synthesis,
        timeline=speech.timeline,
        tracks=tracks,
        warnings=unspoken_warning(utterance) + speech.warnings,
    )
