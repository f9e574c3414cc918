"""The settings of a recording's alignment to its text and of the judgement of how well it fits: one object.

Each value says what it does. How each was chosen, and what the values tried measured, is in the manual
(docs/developer/aligner-settings.md), with the command that measured it. A call takes its own settings
(`synthesize_timeline(..., recording=path, aligner=AlignerSettings(loose=1.6))`); the tuning and measuring
scripts of the lab pass them the same way (`--set NAME=VALUE`, core/base/settings.py).

Frames are the analysis's 10 ms frames; mismatches are natural-log units of the acoustic model's scaled
likelihoods (letter_warp.py: about 0.5 for a person reading the text, 2 and more for another text).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class AlignerSettings:
    """What the recording aligner and its judgement may be tuned by (see the module text)."""

    # -- the acoustic model
    second_hearing: bool = True
    """A take the shipped network fits loosely or hears as another text is heard again by the network that
    learnt many people's voices too, and the better fit kept (recording.align_recording)."""

    # -- the recording's speech
    least_speech_frames: int = 10
    """Under this many frames of speech in the WebRTC-based mask, Silero's detector decides what is speech
    (a person's short word may be all the mask missed)."""
    max_length_ratio: float = 4.0
    """A recording with this many times more or less speech than the synthetic rendition is refused ..."""
    length_slack: float = 3.0
    """... beyond this many seconds of slack (a word alone may be drawn out far slower than eSpeak says
    it)."""
    leading_silence_sure: float = 0.9
    """A run of detected speech starts where the word does, not at its first frames heard as silence this
    surely ..."""
    leading_quiet_db: float = 25.0
    """... and lying this far under the speaker (a gate or an edit opening on the room, a breath, handling
    noise)."""
    not_voice_frames: int = 150
    """A stretch in which Silero's detector, trained on people, hears no voice, holding this many frames
    that the WebRTC-based mask takes for speech (music, a tone, a machine before, between or after the
    lines; or a howl or a song) ..."""
    voice_reach_frames: int = 20
    """... and lying farther than this from any voice it hears for ..."""
    shortest_voice_frames: int = 30
    """... this long at least (a shorter run is a drum or a held note it takes for a voice), ..."""
    not_voice_edge_frames: int = 3_000
    """... within this of the take's start or end (an intro's or an outro's music, a jingle) ..."""
    suspect_mismatch: float = 8.0
    """... or of letters fitting worse than this ..."""
    suspect_frames: int = 8
    """... for this many frames within not_voice_frames (music between two lines), is heard as silence
    where the letters put in it fit it as another text's do (worse than `unmatched` on average): a howl
    or a song keeps them."""

    # -- the synthetic rendition
    chunk_letters: int = 3_000
    """The text is synthesised this many letters at a time (about 5 minutes of speech, cut at sentences)."""
    sentence_pause: float = 0.3
    """Seconds: a word after a pause this long may start a chunk."""
    padding_frames: int = 50
    """Silence added around the synthetic speech beyond the recording's own lead and tail."""

    # -- the DTW that finds the text in the recording as a whole
    heard_scale: float = 2.5
    """The DTW's features are the square roots of the posteriors times this (frames heard as different
    classes then lie 3.5 apart)."""
    silence_in_speech: float = 0.05
    """Where a voice is detected, silence's posterior is made this many times smaller for the DTW."""
    step_penalty: float = 2.0
    """Cost of a DTW step that stretches one signal: keeps the path near the diagonal where the distances
    do not decide."""
    pause_cost: float = 1.0
    """Per frame of a pause one signal makes and the other does not."""
    boundary_slack: int = 1
    """Frames either side of a synthetic word onset where a recorded pause may be held."""
    floor_pause_db: float = 10.0
    """A stretch this close to the noise floor ..."""
    floor_pause_frames: int = 15
    """... for this many frames is a pause (a voice in the background or a room's tail fills it)."""
    under_speech_pause_db: float = 15.0
    """Speech this far under the speaker's loud frames ..."""
    under_speech_pause_frames: int = 20
    """... for this many frames may be a pause ..."""
    far_under_hold_cost: float = 12.0
    """... held through at this cost a frame, which only a stretch matching nothing of the text is worth."""
    order_frames: int = 3_000
    """The text's order is tested on the first this many frames of a long take."""

    # -- placing each letter where the network hears it
    speech_edge_frames: int = 5
    """The letters' alignment trusts the detector's speech this far inside its runs."""
    speaker_silence_bias: float = -8.0
    """Added to silence's score well inside the speaker's speech: the network, unsure of a voice unlike any
    it learnt from, hears silence sooner than a wrong letter."""
    quiet_silence_bias: float = 3.0
    """Added to silence's score where a pause may hold quiet speech (a voice in the background, a room's
    tail)."""
    fading_db: float = 15.0
    """A sound dying away keeps no silence bias: from where the level falls this far under the speaker's
    loud frames ..."""
    rising_db: float = 3.0
    """... until it rises this much from the lowest it reached (the next sound's onset)."""
    break_frames: int = 200
    """A stretch of the recording this long with no speech is a break (a session's lines recorded in one
    take) ..."""
    break_pause_cost: float = 0.1
    """... where each frame of a pause between two words the text puts no pause between (no comma, no
    stop, no line break) costs this much more: the break lies where the text pauses, and the first words
    after it are not drawn before it into the dying sound of the line before."""
    hesitation_sounds: str = "aeıioöuümn"
    """A take still warned is aligned again with each pause between two words the text does not part (no
    comma, no stop) free to hold a hesitation said aloud, one of these letters ("ııı", "eee", "mmm"; the
    sound the word before ends on, or the vowel the next word begins with, only where a silence parts the
    hold from that word; "" for none) ..."""
    hesitation_frames: int = 30
    """... heard for at least this many frames of a run of frames / 0.6 (a word of such letters is no
    hesitation) ..."""
    hesitation_longest_frames: int = 200
    """... and at most this many in one pause (music or a long noise between two lines is none) ..."""
    hesitation_cost: float = 0.3
    """... at this cost a frame: the words around it are not drawn into it, and it is not judged. That
    alignment is kept where it has fewer warnings and holds at least one hesitation ..."""
    hesitation_words: int = 3
    """... and at most one for every this many words of the text (another text's sounds the alignment
    leaves to its pauses are many). A take that fits with no warning is aligned so too where the network
    hears a vowel for hesitation_frames inside a consonant of a word beside such a pause (a hesitation
    drawn into the next word), and kept where it then draws no warning and no word in further than the
    first did, and moves no word but those words and their neighbours."""

    # -- the judgement: a confidence per phrase, another text refused, warnings
    matched: float = 0.5
    """A phrase fitting this well has confidence 1 ..."""
    unmatched: float = 2.0
    """... and this badly, 0."""
    unmatched_word: float = 2.2
    """A word fitting worse than this ..."""
    shortened: float = 0.7
    """... given less than this share of the recording's pace is not in the recording ..."""
    lost_word: float = 3.2
    """... nor is one fitting this much worse than the take as a whole does."""
    word_prior_frames: int = 10
    """A short word's mismatch leans toward the take's by this many frames (a person says "a", "ve", "bu" in
    a breath, and the network hears little of them)."""
    other_text: float = 1.6
    """A take fitting worse than this ..."""
    other_text_order_ratio: float = 0.9
    """... whose sounds fit it in their order little better than reversed (this ratio or more) reads another
    text and is refused ..."""
    plainly_other_text: float = 2.5
    """... and so does one fitting worse than this, whatever its order ..."""
    words_heard: float = 0.8
    """... unless a quarter of its words fit closer than this (a list of foreign syllables spelt roughly):
    such a take is judged by how loosely it fits."""
    loose: float = 1.45
    """A take whose mismatch plus order_weight times its order ratio's excess over own_text_order_ratio
    passes this fits its text only loosely, and is warned."""
    own_text_order_ratio: float = 0.7
    """The order ratio of a take of its own text (the looseness counts from here)."""
    order_weight: float = 2.0
    """How much the order ratio counts in the looseness against the mismatch."""
    list_items: int = 4
    """A text of this many phrases or more, none longer than two words, is a list (a phrase ends where the
    text pauses, or where the recording pauses for list_pause: a list read item by item, written with no
    commas) ..."""
    list_loose: float = 2.05
    """... and is loose past this instead of `loose`: each item is found on its own between pauses."""
    list_pause: float = 0.3
    """Seconds of pause in the recording between two words that end a phrase (see list_items)."""
    short_loose: float = 2.6
    """A take or a text with less speech than refusal_evidence_frames is never refused, and warned as loose
    only past this mismatch ..."""
    refusal_evidence_frames: int = 100
    """... (a word or two said alone is too little to tell another text from a voice heard poorly)."""
    stretched: float = 1.7
    """A word stretched this much beyond the recording's pace ..."""
    stretched_mismatch: float = 1.3
    """... and fitting this badly has company: words the text lacks were said next to it."""
    extra_speech_frames: int = 30
    """Loud speech this long that the letters' alignment leaves to a pause between two words ..."""
    loud_under_speech_db: float = 15.0
    """... (within this of the speaker's loud frames: not a voice in the background, not a room's tail) is
    speech the text lacks."""
    most_warnings: int = 10
    """A take with more places of doubt gets the first ones and a count of the rest."""


DEFAULT_ALIGNER = AlignerSettings()
