"""Where a recording speaks: WebRTC's voice activity detector, checked against the room's noise floor.

The WebRTC detector (the `webrtcvad-wheels` package: Google's detector from WebRTC, in C, wheels for
every platform Blender runs on, no model files) tells voice from stationary room noise; a frame also
has to rise above the recording's own noise floor, so hiss it half-accepts does not count. Then runs
too short to be a syllable (clicks, pops) are dropped, and so is a weak run before or after the
speech or alone between pauses (a breath, a chair): speech is where the loud frames are.
"""

from __future__ import annotations

import numpy as np

from ..base.errors import AudioError
from .audio import to_pcm16
from .features import ANALYSIS_RATE, HOP

# The loud frames are brought to this level (dB full scale) for the detector, which has absolute thresholds:
# a quiet take is still speech (tuned on the tuning sentences: -8 to -13 dB align alike, -20 dB worse).
DETECTOR_LEVEL_DB = -10.0
AGGRESSIVENESS = 3  # WebRTC's strictest mode: least noise taken for speech
ABOVE_NOISE_DB = 6.0  # a speech frame is at least this much louder than the noise floor
BELOW_SPEECH_DB = 45.0  # ... and no more than this much quieter than the loud speech frames
SHORTEST_RUN = 5  # frames (50 ms): shorter runs are clicks
BRIDGED_GAP = 8  # frames (80 ms): shorter gaps are stop closures inside speech, not pauses
ISOLATION = 30  # frames (300 ms) of silence around a run that makes it isolated
VOICING = 0.5  # normalised autocorrelation at the pitch period above which a hop is voiced
VOICED_IN_SPEECH = 3  # hops: a run with fewer voiced ones (a breath, a chair, a click) is not speech
VOICING_STRIDE = 4  # hops: the voicing of every fourth hop is tested first
WEAK_RUN_DB = 20.0  # an isolated run whose peak stays this far below the loud frames is not speech


def frame_levels(samples: np.ndarray) -> np.ndarray:
    """Level in dB of each 10 ms hop of 16 kHz samples."""
    count = samples.size // HOP
    blocks = samples[: count * HOP].reshape(count, HOP)  # a view: a long take is not copied
    return 10 * np.log10(np.einsum("ij,ij->i", blocks, blocks, dtype=np.float64) / HOP + 1e-12)


def speech_frames(samples: np.ndarray, frames: int) -> np.ndarray:
    """True for each of `frames` analysis frames (10 ms hops of 16 kHz samples) that holds speech."""
    levels = frame_levels(samples)
    if levels.size == 0:
        return np.zeros(frames, bool)
    floor = np.percentile(levels, 10)
    loud = np.percentile(levels, 95)
    # Frame i's analysis window is centred 120 samples after hop i's start: close enough for pauses.
    speech = (
        (levels > floor + ABOVE_NOISE_DB)
        & (levels > loud - BELOW_SPEECH_DB)
        & _webrtc(samples, levels.size, 10 ** ((DETECTOR_LEVEL_DB - loud) / 20))
    )
    speech = _drop_short_runs(_bridge_gaps(speech))
    speech = _drop_isolated_weak_runs(speech, levels, loud)
    speech = _drop_unvoiced_runs(samples, speech)
    return np.pad(speech, (0, max(0, frames - speech.size)))[:frames]


def above_floor(samples: np.ndarray, frames: int) -> np.ndarray:
    """dB by which each hop rises above the recording's noise floor (its quietest tenth of hops)."""
    levels = np.convolve(frame_levels(samples), np.ones(3) / 3, "same")
    if levels.size == 0:
        return np.zeros(frames)
    above = levels - np.percentile(levels, 10)
    return np.pad(above, (0, max(0, frames - above.size)), mode="edge")[:frames]


def under_speech(samples: np.ndarray, frames: int) -> np.ndarray:
    """dB by which each hop (its level over 30 ms) lies under the recording's loud frames (95th percentile).

    Relative to the speaker's own level, not the noise floor: a voice in the background or a room's
    tail rises far above the floor of a quiet take, but stays well under the speaker's voice.
    """
    levels = np.convolve(frame_levels(samples), np.ones(3) / 3, "same")
    if levels.size == 0:
        return np.zeros(frames)
    under = np.percentile(levels, 95) - levels
    return np.pad(under, (0, max(0, frames - under.size)), mode="edge")[:frames]


def clean_speech_frames(samples: np.ndarray, frames: int) -> np.ndarray:
    """speech_frames for a signal with no noise (the synthetic rendition), by its levels alone.

    Without noise, speech is where the level comes within BELOW_SPEECH_DB of the loud frames; the
    gaps are bridged and the clicks dropped as for a recording. On the tuning sentences this differs
    from speech_frames in 0-2 frames of 330-500, at a small part of its cost.
    """
    levels = frame_levels(samples)
    if levels.size == 0:
        return np.zeros(frames, bool)
    speech = _drop_short_runs(_bridge_gaps(levels > np.percentile(levels, 95) - BELOW_SPEECH_DB))
    return np.pad(speech, (0, max(0, frames - speech.size)))[:frames]


def voiced_frames(samples: np.ndarray, candidates: np.ndarray) -> np.ndarray:
    """True where a candidate 10 ms hop is periodic at a voice's pitch (60-400 Hz): vowels, not breaths.

    Worked out at 8 kHz (the pitch needs no more), only for the hops the other tests left as speech.
    """
    rate, hop = ANALYSIS_RATE // 2, HOP // 2
    halved = 0.5 * (samples[0 : samples.size - 1 : 2] + samples[1::2])
    shortest, longest = rate // 400, rate // 60
    width = 2 * longest
    size = 1 << int(np.ceil(np.log2(width + longest)))
    overlap = (width - np.arange(shortest, longest)) / width  # long lags are not penalised for shorter sums
    halved = np.pad(halved, (0, width))
    voiced = np.zeros(candidates.size, bool)
    wanted = np.flatnonzero(candidates)
    for begin in range(0, wanted.size, 4096):
        hops = wanted[begin : begin + 4096]
        rows = halved[hops[:, None] * hop + np.arange(width)[None, :]]
        rows = rows - rows.mean(axis=1, keepdims=True)
        correlation = np.fft.irfft(np.abs(np.fft.rfft(rows, size, axis=1)) ** 2, size, axis=1)
        peak = (correlation[:, shortest:longest] / overlap).max(axis=1)
        voiced[hops] = peak > VOICING * (correlation[:, 0] + 1e-12)
    return voiced


def _webrtc(samples: np.ndarray, count: int, gain: float) -> np.ndarray:
    """WebRTC's verdict per hop, on the samples brought to a speaking level (it has absolute thresholds)."""
    try:
        import webrtcvad
    except ImportError:
        raise AudioError(
            "aligning a recording needs the Python package webrtcvad-wheels "
            "(`pip install webrtcvad-wheels`); reinstall the extension, which bundles it"
        ) from None
    detector = webrtcvad.Vad(AGGRESSIVENESS)
    speech = np.zeros(count, bool)
    step = 2 * HOP  # bytes of one hop of 16-bit PCM
    for begin in range(0, count, 1 << 14):  # 16-bit PCM made a block of hops at a time
        stop = min(begin + (1 << 14), count)
        pcm = to_pcm16(samples[begin * HOP : stop * HOP] * gain).astype("<i2").tobytes()
        speech[begin:stop] = [
            detector.is_speech(pcm[index * step : (index + 1) * step], ANALYSIS_RATE)
            for index in range(stop - begin)
        ]
    return speech


def runs(mask: np.ndarray) -> np.ndarray:
    """(start, stop) frame pairs of the True runs of a mask."""
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    return np.stack((np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)), axis=1)


def long_runs(mask: np.ndarray, shortest: int) -> np.ndarray:
    """The frames of the mask's True runs that last at least `shortest` frames."""
    found = np.zeros(mask.size, bool)
    for start, stop in runs(mask):
        if stop - start >= shortest:
            found[start:stop] = True
    return found


def _bridge_gaps(mask: np.ndarray) -> np.ndarray:
    mask = mask.copy()
    spans = runs(mask)
    for (_, stop), (start, _) in zip(spans[:-1], spans[1:], strict=True):
        if start - stop < BRIDGED_GAP:
            mask[stop:start] = True
    return mask


def _drop_short_runs(mask: np.ndarray) -> np.ndarray:
    return long_runs(mask, SHORTEST_RUN)


def _drop_isolated_weak_runs(mask: np.ndarray, levels: np.ndarray, loud: float) -> np.ndarray:
    """Weak runs before the first strong one, after the last, or alone between pauses are not speech."""
    mask = mask.copy()
    spans = runs(mask)
    weak = np.array([levels[start:stop].max() < loud - WEAK_RUN_DB for start, stop in spans], bool)
    if weak.all():
        return mask
    strong = np.flatnonzero(~weak)
    for number, (start, stop) in enumerate(spans):
        if not weak[number]:
            continue
        gap_before = start - spans[number - 1][1] if number else np.inf
        gap_after = spans[number + 1][0] - stop if number + 1 < len(spans) else np.inf
        outside = number < strong[0] or number > strong[-1]
        if outside or min(gap_before, gap_after) >= ISOLATION:
            mask[start:stop] = False
    return mask


def _drop_unvoiced_runs(samples: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """The mask without its runs of fewer than VOICED_IN_SPEECH voiced hops.

    Every VOICING_STRIDE-th hop is tested first: a run of speech has its voiced hops by then; only the
    runs left short of them have all their hops tested (the same result at a fraction of the cost).
    """
    mask = mask.copy()
    spans = runs(mask)
    sparse = np.zeros(mask.size, bool)
    sparse[::VOICING_STRIDE] = True
    voiced = voiced_frames(samples, mask & sparse)
    undecided = np.zeros(mask.size, bool)
    for start, stop in spans:
        if voiced[start:stop].sum() < VOICED_IN_SPEECH:
            undecided[start:stop] = True
    voiced |= voiced_frames(samples, undecided & ~sparse)
    for start, stop in spans:
        if voiced[start:stop].sum() < VOICED_IN_SPEECH:
            mask[start:stop] = False
    return mask
