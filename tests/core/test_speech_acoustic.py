"""The acoustic model's forced alignment: where each letter of a known text lies."""

import numpy as np
import pytest

from turkish_lipsync.core.base.errors import DataError
from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.acoustic.features import (
    BANDS,
    SHORT_OWN_WEIGHT,
    frames_of,
    levelled,
    log_bands,
    long_quiet,
    own_level_weight,
    recogniser_features,
    sounding_frames,
)
from turkish_lipsync.core.speech.acoustic.forced import (
    POSTERIOR_FLOOR,
    PRIOR_WEIGHT,
    ForcedAlignment,
    _transitions,
    force_align,
    letter_model,
    text_units,
)
from turkish_lipsync.core.speech.acoustic.labels import CLASS_INDEX, CLASSES
from turkish_lipsync.core.speech.acoustic.network import PEOPLE_WEIGHTS_FILE, WEIGHTS_FILE, load_network
from turkish_lipsync.core.speech.audio import resample
from turkish_lipsync.core.speech.features import ANALYSIS_RATE, HOP, WINDOW, frame_count
from turkish_lipsync.core.speech.letter_warp import _hesitation_drawn_in, spoken_hesitations
from turkish_lipsync.core.text.utterance import build_utterance, read_aloud


def posteriors_of(labels: list[int]) -> np.ndarray:
    """Log posteriors that hear exactly the given class in each frame (and a little of everything)."""
    heard = np.full((len(labels), len(CLASSES)), 0.01 / len(CLASSES))
    heard[np.arange(len(labels)), labels] += 0.99
    return np.log(heard)


def test_text_units_are_the_letters_that_are_sounds_in_order():
    units = text_units(build_utterance("Ağaç, bal."))
    assert [CLASSES[c] for c in units.classes] == list("aaçbal")  # ğ is no sound of its own
    assert units.word_starts.tolist() == [True, False, False, True, False, False]


def test_each_letter_is_found_where_it_is_heard_and_pauses_are_skipped_or_taken():
    silence, a, b, e = (CLASS_INDEX[name] for name in "_abe")
    # "ab e" heard as: silence, a a a, b b, a pause, e e e e, silence
    frames = [silence] * 3 + [a] * 3 + [b] * 2 + [silence] * 4 + [e] * 4 + [silence] * 2
    units = np.array([a, b, e])
    model = letter_model(units, np.array([True, False, True]), np.ones(len(CLASSES), np.int64))
    found = force_align(posteriors_of(frames), np.full(len(CLASSES), 1 / len(CLASSES)), model)
    assert found.starts.tolist() == [3, 6, 12]
    assert found.stops.tolist() == [6, 8, 16]
    # The same words run together: the pause before "e" is skipped.
    joined = [silence] * 2 + [a] * 3 + [b] * 2 + [e] * 4
    found = force_align(posteriors_of(joined), np.full(len(CLASSES), 1 / len(CLASSES)), model)
    assert found.starts.tolist() == [2, 5, 7]


def hesitating(held: str, frames: int, second: str = "du") -> np.ndarray:
    """ "ba" and a second word of two letters heard with `frames` of a held sound between the words:
    mostly `held`, a little u."""
    silence, a, b, u = (CLASS_INDEX[name] for name in "_abu")
    first, then = (CLASS_INDEX[name] for name in second)
    heard = np.full((33 + frames, len(CLASSES)), 1e-4)
    for start, stop, name in ((0, 3, silence), (3, 6, b), (6, 10, a), (10, 13, silence)):
        heard[start:stop, name] = 1.0
    heard[13 : 13 + frames, CLASS_INDEX[held]], heard[13 : 13 + frames, u] = 0.7, 0.3
    for start, stop, name in ((0, 3, silence), (3, 6, first), (6, 10, then), (10, 20, silence)):
        heard[13 + frames + start : 13 + frames + stop, name] = 1.0
    return np.log(heard / heard.sum(axis=1, keepdims=True))


@pytest.mark.parametrize(
    ("held", "frames", "hesitation"),
    [("ı", 30, True), ("ı", 10, False), ("a", 30, False), ("u", 30, True)],
)
def test_a_hesitation_said_aloud_between_two_words_draws_neither_into_it(held, frames, hesitation):
    """An "ııı" held for 300 ms between "ba" and "du" is a pause: "du" starts after it, not in it. Held
    for 100 ms it is no hesitation; an "a", the sound "ba" ends on, is never one (a drawn-out vowel, a
    room's tail). A "uuu" is one: the d parts it from the u of "du" ("eee gelmeden")."""
    units = np.array([CLASS_INDEX[name] for name in "badu"])
    starts, shortest = np.array([True, False, True, False]), np.ones(len(CLASSES), np.int64)
    model = letter_model(units, starts, shortest, marked=np.zeros(4, bool))  # "ba du": no comma
    priors = np.full(len(CLASSES), 1 / len(CLASSES))
    sounds = np.array([CLASS_INDEX[name] for name in "aeıioöuümn"])
    log_posteriors = hesitating(held, frames)
    plain = force_align(log_posteriors, priors, model)
    found = force_align(log_posteriors, priors, model, None, None, None, sounds, 0.3, 15)
    d = 13 + frames + 3
    if held != "a":
        assert plain.starts[2] < d - 2  # without hesitations, the d is drawn into the held sound
    if hesitation:
        assert found.starts.tolist() == [3, 6, d, d + 3]
        held_sound = found.frame_hesitations == CLASS_INDEX[held]  # which sound: the mouth shapes it
        assert held_sound[13 : 13 + frames].all() and np.count_nonzero(found.frame_hesitations >= 0) == frames
        # "ba, du": a list's items, or words the text parts with a comma, hold no hesitation.
        listed = letter_model(units, starts, shortest, marked=starts)
        assert (
            force_align(
                log_posteriors, priors, listed, None, None, None, sounds, 0.3, 15
            ).frame_hesitations.max()
            == -1
        )
    else:
        assert found.frame_hesitations.max() == -1
        assert found.starts.tolist() == plain.starts.tolist()


def test_the_vowel_a_word_begins_with_held_before_it_is_that_words():
    """ "ba ud" with 300 ms of "uuu" before "ud": its own u drawn out, no hesitation (nothing parts
    the two)."""
    units = np.array([CLASS_INDEX[name] for name in "baud"])
    starts, shortest = np.array([True, False, True, False]), np.ones(len(CLASSES), np.int64)
    model = letter_model(units, starts, shortest, marked=np.zeros(4, bool))
    priors = np.full(len(CLASSES), 1 / len(CLASSES))
    sounds = np.array([CLASS_INDEX[name] for name in "aeıioöuümn"])
    found = force_align(hesitating("u", 30, "ud"), priors, model, None, None, None, sounds, 0.3, 15)
    assert found.frame_hesitations.max() == -1
    assert found.starts[2] < 13 + 30 - 10  # the u of "ud" holds the drawn-out sound


def test_a_hesitation_is_one_span_through_a_few_quiet_frames_not_through_a_word():
    """Frames of a fit: "ııı" 40 frames, 5 quiet, 30 more "ııı" (one hesitation), a word, "mmm" 35 (another,
    shaped as closed lips), 20 quiet frames, "mmm" 30 (a third: 0.2 s of quiet parts them)."""
    ı, m = CLASS_INDEX["ı"], CLASS_INDEX["m"]
    pieces = [(ı, -1, 40), (-1, -1, 5), (ı, -1, 30), (-1, 0, 25), (m, -1, 35), (-1, -1, 20), (m, -1, 30)]
    sounds = np.concatenate([np.full(n, sound) for sound, _, n in pieces])
    words = np.concatenate([np.full(n, word) for _, word, n in pieces])
    found = spoken_hesitations(sounds, words)
    assert [(h.sound, h.viseme) for h in found] == [("ı", "I"), ("m", "me"), ("m", "me")]
    assert [round(h.end - h.start, 3) for h in found] == [0.75, 0.35, 0.3]
    assert found[1].start == pytest.approx(found[0].end + 0.25)


@pytest.mark.parametrize("text", ["A. O e", "A\nO e"])
def test_a_break_lies_where_the_text_pauses_not_inside_its_sentence(text):
    """Two sentences 1.5 s apart ("a. o e", or "a" and "o e" on two lines): the o may be heard in the a's
    dying tail or where a sound between o and e starts after the break. Alike to the network (the tail a
    little more o-like), a pause the text does not mark costs its frames in a break: the break goes
    before the o."""
    silence, a, o, e = (CLASS_INDEX[name] for name in "_aoe")
    heard = np.full((160, len(CLASSES)), 1e-4)
    heard[0:3, a] = 1.0
    heard[3:5, o], heard[3:5, silence] = 0.55, 0.45  # the tail of the a
    heard[5:155, silence] = 1.0  # the break
    heard[155:157, o], heard[155:157, e] = 0.5, 0.5  # an o or an e
    heard[157:160, e] = 1.0
    log_posteriors = np.log(heard / heard.sum(axis=1, keepdims=True))
    units = text_units(read_aloud(build_utterance(text)))
    assert units.marked.tolist() == [False, True, False]
    model = letter_model(units.classes, units.word_starts, np.ones(len(CLASSES), np.int64), units.marked)
    priors = np.full(len(CLASSES), 1 / len(CLASSES))
    assert force_align(log_posteriors, priors, model).starts.tolist()[1] == 3  # no cost: the o in the tail
    cost = np.zeros(160)
    cost[5:155] = 0.1
    assert force_align(log_posteriors, priors, model, break_cost=cost).starts.tolist()[:2] == [0, 155]


def test_a_line_break_is_spoken_as_a_space_and_read_aloud_as_a_commas_pause():
    lines = build_utterance("Merhaba Ali\nnasılsın\r\n  bugün")
    assert [word.line_start for word in lines.words] == [False, False, True, True]
    assert all(word.pause_before == 0 for word in lines.words)  # the voice reads on as across a space
    read = read_aloud(lines)
    comma = build_utterance("Merhaba Ali, nasılsın, bugün")
    assert [word.pause_before for word in read.words] == [word.pause_before for word in comma.words]
    assert [word.ending for word in read.words] == [word.ending for word in comma.words]
    assert text_units(read).marked.tolist() == text_units(comma).marked.tolist()
    assert not build_utterance("\nMerhaba").words[0].line_start  # a text's first word begins no line
    # After a stop the word keeps its stop's pause; a blank line is a paragraph's pause, not a line.
    assert (
        read_aloud(build_utterance("A.\nO")).words[1].pause_before
        == build_utterance("A. O").words[1].pause_before
    )
    paragraph = read_aloud(build_utterance("A\n\nO")).words[1]
    assert (
        not paragraph.line_start
        and paragraph.pause_before == build_utterance("<PARA>A</PARA> O").words[1].pause_before
    )


def test_every_letter_lasts_at_least_its_shortest_duration():
    silence, a, b = (CLASS_INDEX[name] for name in "_ab")
    frames = [silence] * 2 + [a] * 6 + [silence] * 2  # the b is not heard at all
    shortest = np.full(len(CLASSES), 3)
    model = letter_model(np.array([a, b]), np.array([True, False]), shortest)
    found = force_align(posteriors_of(frames), np.full(len(CLASSES), 1 / len(CLASSES)), model)
    assert (found.stops - found.starts >= 3).all()


def test_a_band_too_narrow_for_any_path_is_an_error():
    a, b = CLASS_INDEX["a"], CLASS_INDEX["b"]
    model = letter_model(np.array([a, b]), np.array([True, True]), np.ones(len(CLASSES), np.int64))
    frames = 6
    band = (np.zeros(frames, np.int64), np.ones(frames, np.int64))  # never past the leading silence
    with pytest.raises(ValueError, match="no path"):
        force_align(posteriors_of([a] * frames), np.full(len(CLASSES), 1 / len(CLASSES)), model, band)


def test_a_band_that_moves_back_is_an_error():
    a, b = CLASS_INDEX["a"], CLASS_INDEX["b"]
    model = letter_model(np.array([a, b]), np.array([True, True]), np.ones(len(CLASSES), np.int64))
    low = np.array([0, 1, 0, 1, 2, 3])
    band = (low, np.full(6, len(model.classes)))
    with pytest.raises(ValueError, match="moves back"):
        force_align(posteriors_of([a] * 6), np.full(len(CLASSES), 1 / len(CLASSES)), model, band)


def dense_path(scores: np.ndarray, model, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """Each frame's state on the best path: every state of every frame scored, -inf outside the band,
    ties kept as force_align keeps them (stay, then the state before, then two before)."""
    frames, states = len(scores), len(model.classes)
    stay, enter, jump = _transitions(model)
    outside = (np.arange(states)[None, :] < low[:, None]) | (np.arange(states)[None, :] >= high[:, None])
    emitted = np.where(outside, -np.inf, scores[:, model.classes])
    value = np.full(states, -np.inf)
    value[0] = 0.0
    value[1] = 0.0 if model.skippable[0] else -np.inf
    value = value + emitted[0]
    moves = np.zeros((frames, states), np.int8)
    for frame in range(1, frames):
        before = np.concatenate(([-np.inf, -np.inf], value))
        options = np.stack((before[2:] + stay, before[1:-1] + enter, before[:-2] + jump))
        choice = np.where(options[1] > options[0], 1, 0)
        choice = np.where(options[2] > np.maximum(options[0], options[1]), 2, choice)
        moves[frame] = choice
        value = options.max(axis=0) + emitted[frame]
    state = states - 1 if value[-1] >= value[-2] else states - 2
    path = np.empty(frames, np.int64)
    for frame in range(frames - 1, -1, -1):
        path[frame] = state
        state -= moves[frame, state]
    return path


def test_a_moving_band_finds_the_path_every_state_scored_finds():
    rng = np.random.default_rng(11)
    classes = rng.integers(1, len(CLASSES), 40)
    starts = rng.random(40) < 0.3
    starts[0] = True
    model = letter_model(classes, starts, rng.integers(1, 4, len(CLASSES)))
    frames, states = 160, len(model.classes)
    scores = np.log(rng.dirichlet(np.ones(len(CLASSES)), frames))
    middle = np.linspace(0, states, frames)  # a band that climbs through the states, as a DTW path's does
    low = np.clip(np.floor(middle - 4).astype(np.int64), 0, states - 1)
    high = np.clip(np.ceil(middle + 4).astype(np.int64), 1, states)
    low[0], high[-1] = 0, states
    uniform = np.full(len(CLASSES), 1 / len(CLASSES))
    found = force_align(scores, uniform, model, (low, high))
    scored = np.maximum(scores, np.log(POSTERIOR_FLOOR)) - PRIOR_WEIGHT * np.log(uniform)[None, :]
    assert np.array_equal(found.frame_letters, model.letter_of_state[dense_path(scored, model, low, high)])


def test_letters_of_speech_are_found_near_where_they_were_spoken():
    utterance = build_utterance("Bugün hava çok güzel, parka gidip biraz yürüyelim.")
    speech = synthesize_timeline(utterance)
    synthesis = speech.synthesis
    samples = resample(synthesis.samples.astype(np.float32) / 32768, synthesis.sample_rate, ANALYSIS_RATE)
    network = load_network()
    units = text_units(utterance)
    shortest = np.maximum(1, np.round(network.shortest * 0.5)).astype(np.int64)
    found = force_align(
        network.log_posteriors(recogniser_features(samples)),
        network.priors,
        letter_model(units.classes, units.word_starts, shortest),
    )
    truth = {phone.letter_index: phone.start for phone in speech.timeline.phones}
    onsets = [
        (found.starts[n] * 0.01, truth[letter]) for n, letter in enumerate(units.letters) if letter in truth
    ]
    error = np.abs(np.array(onsets)[:, 0] - np.array(onsets)[:, 1])
    assert np.median(error) < 0.02 and np.percentile(error, 90) < 0.05


def spoken_samples(text: str) -> np.ndarray:
    synthesis = synthesize_timeline(build_utterance(text)).synthesis
    return resample(synthesis.samples.astype(np.float32) / 32768, synthesis.sample_rate, ANALYSIS_RATE)


def test_a_take_with_speech_enough_is_levelled_on_itself_alone():
    samples = spoken_samples("Bugün hava çok güzel, parka gidip biraz yürüyelim.")
    assert np.array_equal(recogniser_features(samples), recogniser_features(samples, whole_take_level=True))


def test_a_long_break_in_the_recording_is_left_out_of_its_speech_level():
    """A stretch of room at least LONG_QUIET_FRAMES long (two sentences 20 s apart) is levelled as if cut
    out of the take; a shorter pause is counted as before."""
    rng = np.random.default_rng(8)
    first = spoken_samples("Bugün hava çok güzel.")
    second = spoken_samples("Parka gidip biraz yürüyelim.")
    room = 10 ** (-50 / 20) * np.abs(first).max()

    def take(seconds):
        pause = rng.normal(0, room, int(seconds * ANALYSIS_RATE))
        return np.concatenate((first + rng.normal(0, room, first.size), pause, second))

    short, long = log_bands(take(1.0)), log_bands(take(20.0))
    assert not long_quiet(_loudness(short)).any()
    kept = ~long_quiet(_loudness(long))
    assert 2000 <= np.count_nonzero(~kept) <= 2100  # the break and the quiet either side of it
    np.testing.assert_array_equal(levelled(long)[kept], levelled(long[kept]))


def _loudness(decibels):
    return 10.0 * np.log10(np.sum(10.0 ** (decibels / 10.0), axis=1) + 1e-10)


def test_a_syllable_alone_keeps_its_vowel_colour():
    """Levelled on itself alone, a take of one syllable is levelled on its vowel, and "bi" and "ba" look
    alike where their vowels are; levelled partly on people's long-term spectrum, they stay apart."""

    def vowel_bands(text: str, whole_take_level: bool) -> np.ndarray:
        features = recogniser_features(spoken_samples(text), whole_take_level)
        loud = features[:, BANDS] > -0.5  # within 5 dB of the take's speech level
        return features[loud, :BANDS].mean(axis=0)

    apart = np.linalg.norm(vowel_bands("bi", False) - vowel_bands("ba", False))
    alike = np.linalg.norm(vowel_bands("bi", True) - vowel_bands("ba", True))
    assert apart > 2 * alike


def test_digital_silence_at_either_end_is_not_the_takes_sound():
    """Zeros and one-step dither at a take's end are left out from the first frame whose window holds
    sound, where they last longer than the silence the network learnt around speech; a shorter run is
    kept, the quietest room noise is sound, and a take of nothing but digital silence is heard whole."""
    room = np.random.default_rng(3).normal(0, 1e-3, 16000)  # -60 dBFS
    dither = np.random.default_rng(4).integers(-1, 2, 3000) / 32768
    take = np.concatenate((np.zeros(16000), dither, room, np.zeros(8000)))
    frames = frame_count(take.size)
    first, stop = sounding_frames(take, frames)
    sound_starts = 16000 + 3000
    assert (first, stop) == (-(-(sound_starts - WINDOW + 1) // HOP), frames)  # 0.5 s after: kept
    assert np.array_equal(frames_of(take, first, stop, frames), take[first * HOP :])
    padded = np.concatenate((take, np.zeros(32000)))
    assert sounding_frames(padded, frame_count(padded.size))[1] == (sound_starts + 16000 - 1) // HOP + 1
    assert sounding_frames(room, frame_count(room.size)) == (0, frame_count(room.size))
    assert sounding_frames(np.zeros(1000), 7) == (0, 7)


def test_the_own_spectrum_counts_more_the_more_speech_a_take_holds():
    level = 0.0
    weights = [
        own_level_weight(np.r_[np.zeros(frames), np.full(400, -80.0)], level) for frames in (10, 100, 200)
    ]
    assert weights == [SHORT_OWN_WEIGHT, (1 + SHORT_OWN_WEIGHT) / 2, 1.0]


def _shipped_layers() -> dict[str, np.ndarray]:
    with np.load(WEIGHTS_FILE) as shipped:
        return {
            key.removeprefix("weight/"): shipped[key] for key in shipped.files if key.startswith("weight/")
        }


def _weights_file(path, layers: dict[str, np.ndarray]):
    """A weights file with the shipped network's statistics and these layers."""
    with np.load(WEIGHTS_FILE) as shipped:
        kept = {key: shipped[key] for key in shipped.files if not key.startswith("weight/")}
    np.savez(path, **kept, **{f"weight/{name}": value for name, value in layers.items()})
    return path


def test_weights_of_another_width_run_as_trained(tmp_path):
    """A network grown by channels that nothing reads (lab/train/many_voices.py --channels starts so)
    hears as the network it was grown from: the runtime takes the width the weights have."""
    grown = {}
    for name, value in _shipped_layers().items():
        wider = [size + 32 if axis < 2 and size == 128 else size for axis, size in enumerate(value.shape)]
        grown[name] = np.zeros(wider, np.float32)
        grown[name][tuple(slice(0, size) for size in value.shape)] = value
    features = recogniser_features(spoken_samples("Bir baba, mavi bir kapı."))
    np.testing.assert_allclose(
        load_network(_weights_file(tmp_path / "grown.npz", grown)).log_posteriors(features),
        load_network().log_posteriors(features),
        atol=1e-4,
    )


def test_the_people_network_is_the_shipped_one_grown():
    """The second hearing's network (lab/train/many_voices.py --keep-start) holds the shipped network's
    weights unchanged, and its shipped channels hear nothing grown: retraining the shipped network means
    growing the people's network from it again."""
    shipped = _shipped_layers()
    with np.load(PEOPLE_WEIGHTS_FILE) as people:
        for name, value in shipped.items():
            grown = people[f"weight/{name}"]
            assert grown.shape[0] >= value.shape[0] and grown.ndim == value.ndim
            np.testing.assert_array_equal(grown[tuple(slice(0, size) for size in value.shape)], value)
            if name.startswith("blocks.") and value.ndim == 3:
                assert not grown[: value.shape[0], value.shape[1] :].any(), name
    assert (
        load_network(PEOPLE_WEIGHTS_FILE).layers["first.weight"].shape[1] > shipped["first.weight"].shape[0]
    )


def test_weights_that_do_not_fit_the_layout_are_refused_with_their_layer(tmp_path):
    layers = _shipped_layers()
    layers["blocks.2.dilated.weight"] = layers["blocks.2.dilated.weight"][:, :64]
    with pytest.raises(DataError, match=r"do not fit its network \(blocks\.2\.dilated\.weight\)"):
        load_network(_weights_file(tmp_path / "broken.npz", layers))


def test_a_hesitation_heard_with_a_few_other_frames_in_it_is_held_at_its_own_scores():
    """ "ba eee de", the "eee" heard with a b-like frame every sixth (as the network hears eSpeak NG's and
    people's): a pause holds it and "de" starts after it. A grey-scale opening (the least score over 0.3
    s) priced every frame of it at a b frame's, under the e of "de", and the d was drawn to its start."""
    silence, a, b, d, e = (CLASS_INDEX[name] for name in "_abde")
    frames = 60
    heard = np.full((33 + frames, len(CLASSES)), 1e-4)
    for start, stop, name in ((0, 3, silence), (3, 6, b), (6, 10, a), (10, 13, silence)):
        heard[start:stop, name] = 1.0
    heard[13 : 13 + frames, e] = 1.0
    heard[13 : 13 + frames : 6, e], heard[13 : 13 + frames : 6, b] = 0.2, 0.8
    for start, stop, name in ((0, 3, silence), (3, 5, d), (5, 10, e), (10, 20, silence)):
        heard[13 + frames + start : 13 + frames + stop, name] = 1.0
    heard[13 + frames + 3 : 13 + frames + 5, e] = 0.3  # the d heard faintly, as a voiced stop often is
    log_posteriors = np.log(heard / heard.sum(axis=1, keepdims=True))
    units = np.array([CLASS_INDEX[name] for name in "bade"])
    starts, shortest = np.array([True, False, True, False]), np.ones(len(CLASSES), np.int64)
    model = letter_model(units, starts, shortest, marked=np.zeros(4, bool))
    priors = np.full(len(CLASSES), 1 / len(CLASSES))
    sounds = np.array([CLASS_INDEX[name] for name in "aeıioöuümn"])
    found = force_align(log_posteriors, priors, model, None, None, None, sounds, 0.3, 30)
    assert found.starts[2] == 13 + frames + 3
    assert np.count_nonzero(found.frame_hesitations == e) >= frames - 5


def test_each_word_a_hesitation_seems_drawn_into_is_told():
    """ "bal demek gerek" with an "eee" drawn into the e inside "demek" (40 frames) and one into the e
    inside "gerek" (35): both words are told, so that a second alignment may move both (it was the
    longest alone, and a second alignment that put the other word right too was not kept)."""
    utterance = build_utterance("bal demek gerek")
    units = text_units(utterance)
    lengths = np.full(len(units.classes), 5)
    lengths[4], lengths[9] = 40, 35  # the first e of "demek", of "gerek"
    stops = np.cumsum(lengths)
    starts = stops - lengths
    frames = int(stops[-1])
    frame_letters = np.repeat(np.arange(len(lengths)), lengths)
    found = ForcedAlignment(starts, stops, frame_letters, np.zeros(frames), np.full(frames, -1))
    word_of_letter = np.array([utterance.letters[letter].word_index for letter in units.letters])
    silence = np.full((frames, len(CLASSES)), -10.0)
    silence[:, CLASS_INDEX["_"]] = 0.0
    drawn_in = _hesitation_drawn_in(units, found, silence, word_of_letter, len(utterance.words))
    assert drawn_in.tolist() == [5, 40, 35]


def _hesitation_before_a_word_of_its_sound(parting: int) -> np.ndarray:
    """Log posteriors of "ba eee ede": "ba", 60 frames of e, `parting` frames of silence, "ede"."""
    silence, a, b, d, e = (CLASS_INDEX[name] for name in "_abde")
    frames = 60
    heard = np.full((13 + frames + parting + 20, len(CLASSES)), 1e-4)
    for start, stop, name in ((0, 3, silence), (3, 6, b), (6, 10, a), (10, 13, silence)):
        heard[start:stop, name] = 1.0
    heard[13 : 13 + frames, e] = 1.0
    heard[13 + frames : 13 + frames + parting, silence] = 1.0
    word = 13 + frames + parting
    for start, stop, name in ((0, 5, e), (5, 8, d), (8, 13, e), (13, 20, silence)):
        heard[word + start : word + stop, name] = 1.0
    return np.log(heard / heard.sum(axis=1, keepdims=True))


@pytest.mark.parametrize("parting", [0, 8])
def test_a_hesitation_of_the_next_words_first_vowel_is_held_only_where_a_silence_parts_them(parting):
    """ "ba eee, ede": where a silence parts the "eee" from the word, the pause holds it and the word
    starts after the silence ("eee, eğlenceliydi"); where none does, it is the word's own first vowel
    drawn out ("eeede"), and the word starts where it does."""
    log_posteriors = _hesitation_before_a_word_of_its_sound(parting)
    units = np.array([CLASS_INDEX[name] for name in "baede"])
    starts, shortest = np.array([True, False, True, False, False]), np.ones(len(CLASSES), np.int64)
    model = letter_model(units, starts, shortest, marked=np.zeros(5, bool))
    priors = np.full(len(CLASSES), 1 / len(CLASSES))
    sounds = np.array([CLASS_INDEX[name] for name in "aeıioöuümn"])
    found = force_align(log_posteriors, priors, model, None, None, None, sounds, 0.3, 30)
    assert found.starts[2] == (13 + 60 + parting if parting else 13)
    assert np.count_nonzero(found.frame_hesitations >= 0) == (60 if parting else 0)


@pytest.mark.parametrize("parting", [0, 8])
def test_a_words_first_vowel_holding_a_hesitation_parted_from_it_is_told(parting):
    """The path draws "ba eee, ede"'s hesitation into the first e of "ede": told as drawn in where a
    silence parts it from the rest of the vowel inside the letter, not where the vowel is one (a drawn-out
    vowel is the word's own)."""
    log_posteriors = _hesitation_before_a_word_of_its_sound(parting)
    utterance = build_utterance("ba ede")
    units = text_units(utterance)
    lengths = np.array([3, 4, 3 + 60 + parting + 5, 3, 5])
    stops = 3 + np.cumsum(lengths)
    starts = stops - lengths
    frame_letters = np.full(len(log_posteriors), -1)
    for letter, (start, stop) in enumerate(zip(starts, stops, strict=True)):
        frame_letters[start:stop] = letter
    found = ForcedAlignment(
        starts, stops, frame_letters, np.zeros(len(frame_letters)), np.full(len(frame_letters), -1)
    )
    word_of_letter = np.array([utterance.letters[letter].word_index for letter in units.letters])
    drawn_in = _hesitation_drawn_in(units, found, log_posteriors, word_of_letter, len(utterance.words))
    assert drawn_in.tolist() == [0, 60 if parting else 0]


def test_a_hesitation_heard_nearly_as_a_vowel_inside_a_consonant_is_told():
    """ "im parator": the "eee" drawn into the p, heard as e on most frames and as b on every sixth
    (within a nat of the e): each of its frames counts, the b-like ones too, and both words beside the
    join are told (the m and the p at it may share a hold between them)."""
    utterance = build_utterance("im parator")
    units = text_units(utterance)
    lengths = np.array([5, 5, 60, 5, 5, 5, 5, 5, 5])
    stops = np.cumsum(lengths)
    starts = stops - lengths
    heard = np.full((int(stops[-1]), len(CLASSES)), -10.0)
    heard[np.arange(len(heard)), units.classes[np.repeat(np.arange(len(lengths)), lengths)]] = 0.0
    p = slice(int(starts[2]), int(stops[2]))
    heard[p, CLASS_INDEX["p"]] = -10.0
    heard[p, CLASS_INDEX["e"]] = 0.0
    heard[p][::6, CLASS_INDEX["b"]] = 0.5
    frame_letters = np.repeat(np.arange(len(lengths)), lengths)
    found = ForcedAlignment(starts, stops, frame_letters, np.zeros(len(heard)), np.full(len(heard), -1))
    word_of_letter = np.array([utterance.letters[letter].word_index for letter in units.letters])
    assert _hesitation_drawn_in(units, found, heard, word_of_letter, 2).tolist() == [60, 60]


@pytest.mark.parametrize("pause", [0, 10])
def test_a_words_last_vowel_held_long_before_the_paths_pause_is_told(pause):
    """ "gün işe gel": the path put the i and ş of "işe" at an "eee"'s start and held its e through the
    "eee" (50 frames), then paused before "gel" (the word's own sounds were heard later): told where the
    path pauses right after the held vowel, not where the next word follows it at once (a drawn-out
    vowel)."""
    utterance = build_utterance("gün işe gel")
    units = text_units(utterance)
    lengths = np.array([5, 5, 5, 2, 4, 50, 5, 5, 5])
    gaps = np.zeros(len(lengths), np.int64)
    gaps[6] = pause  # before "gel"
    starts = np.cumsum(lengths + gaps) - lengths
    stops = starts + lengths
    frame_letters = np.full(int(stops[-1]), -1)
    for letter, (start, stop) in enumerate(zip(starts, stops, strict=True)):
        frame_letters[start:stop] = letter
    heard = np.full((len(frame_letters), len(CLASSES)), -10.0)
    spoken = frame_letters >= 0
    heard[np.flatnonzero(spoken), units.classes[frame_letters[spoken]]] = 0.0
    heard[~spoken, CLASS_INDEX["_"]] = 0.0
    found = ForcedAlignment(starts, stops, frame_letters, np.zeros(len(heard)), np.full(len(heard), -1))
    word_of_letter = np.array([utterance.letters[letter].word_index for letter in units.letters])
    drawn_in = _hesitation_drawn_in(units, found, heard, word_of_letter, 3)
    assert drawn_in[1] == (50 if pause else 0)
