"""Numbers as Turkish words: cardinals, ordinals, decimals and fractions.

Each word is returned with the source index of the digit it reads, so the letters of "yirmi" sit on the
"2" of "2024" (lists of (word, index); a word may hold spaces, as "dörtte üç").
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from .suffixes import ordinal, spoken_suffix
from .tables import text_tables

# (spoken word or words, source index of all its letters, or one index per letter for a word as written)
Words = list[tuple[str, int | tuple[int, ...]]]

# An integer with "." between thousands (Turkish style), or plain digits.
THOUSANDS = r"[0-9]{1,3}(?:\.[0-9]{3})+"
INTEGER = rf"(?:{THOUSANDS}|[0-9]+)"
_DECIMAL_COMMA = re.compile(rf"(?P<integer>{INTEGER})(?:,(?P<fraction>[0-9]+))?")
# One "." that is no thousands separator is a decimal point (3.5, 3.14; 3.500 is three thousand five hundred).
_DECIMAL_POINT = re.compile(r"(?P<integer>[0-9]+)\.(?P<fraction>[0-9]{1,2}|[0-9]{4,})")
_SEPARATOR_WORDS = {".": "decimal_point", ",": "decimal_comma", "/": "fraction"}


def digit_names(digits: str, positions: Sequence[int]) -> Words:
    """Each digit by its name: phone numbers, 007."""
    names = text_tables().digits
    return [(names[int(digit)], position) for digit, position in zip(digits, positions, strict=True)]


def _hundreds(digits: str, positions: Sequence[int]) -> Words:
    """Words of a number below 1000 (given as up to three digits), each with its digit's position."""
    tables = text_tables()
    words: Words = []
    places = [None] * (3 - len(digits)) + list(positions)
    hundreds, tens, ones = (int(digit) for digit in digits.rjust(3, "0"))
    if hundreds:
        if hundreds > 1:
            words.append((tables.digits[hundreds], places[0]))
        words.append((tables.hundred, places[0]))
    if tens:
        words.append((tables.tens[tens], places[1]))
    if ones:
        words.append((tables.digits[ones], places[2]))
    return words


def cardinal(digits: str, positions: Sequence[int]) -> Words:
    """A whole number written as digits (a "." between thousands is skipped): 1.250 -> bin iki yüz elli."""
    if "." in digits:
        kept = [index for index, char in enumerate(digits) if char != "."]
        return cardinal(digits.replace(".", ""), [positions[index] for index in kept])
    tables = text_tables()
    if len(digits) > 1 and digits[0] == "0" or len(digits) > 3 * len(tables.scales):
        # Leading zeros (007) and numbers beyond the largest scale are read digit by digit.
        return digit_names(digits, positions)
    if int(digits) == 0:
        return [(tables.digits[0], positions[0])]
    words: Words = []
    group_count = (len(digits) + 2) // 3
    first = len(digits) - 3 * (group_count - 1)
    starts = [0] + [first + 3 * n for n in range(group_count - 1)]
    for number, (begin, end) in enumerate(zip(starts, starts[1:] + [len(digits)], strict=True)):
        group, places = digits[begin:end], positions[begin:end]
        scale = tables.scales[group_count - 1 - number]
        value = int(group)
        if not value:
            continue
        if scale == tables.scales[1] and value == 1:
            words.append((scale, places[-1]))  # 1000 is "bin", not "bir bin"
            continue
        significant = group.lstrip("0")
        words.extend(_hundreds(significant, places[len(group) - len(significant) :]))
        if scale:
            words.append((scale, places[-1]))
    return words


def value_words(digits: str, positions: Sequence[int]) -> Words:
    """A number by its value, leading zeros ignored: the 03 of a date is "üç"."""
    significant = digits.lstrip("0") or "0"
    return cardinal(significant, positions[len(digits) - len(significant) :])


def decimal_digits(digits: str, positions: Sequence[int]) -> Words:
    """The digits after a decimal separator: up to two as a number after their leading zeros (3,05 ->
    sıfır beş; 3,14 -> on dört), longer ones digit by digit (39,9334 -> dokuz üç üç dört)."""
    if len(digits) > 2:
        return digit_names(digits, positions)
    significant = digits.lstrip("0")
    zeros = len(digits) - len(significant)
    words = digit_names(digits[:zeros], positions[:zeros])
    if significant:
        words.extend(cardinal(significant, positions[zeros:]))
    return words


def decimal(number: str, positions: Sequence[int]) -> Words | None:
    """3,5 / 1.250,75 / 3.14 as words (a decimal point is read "virgül", as Turkish says decimals);
    None when the text is no plain or decimal number."""
    tables = text_tables()
    match = _DECIMAL_COMMA.fullmatch(number) or _DECIMAL_POINT.fullmatch(number)
    if not match:
        return None
    integer, fraction = match.group("integer"), match.group("fraction")
    words = cardinal(integer, positions[: len(integer)])
    if fraction is not None:
        words.append((tables.words["decimal_comma"], positions[len(integer)]))
        words.extend(decimal_digits(fraction, positions[len(integer) + 1 :]))
    return words


def number_words(number: str, positions: Sequence[int]) -> Words:
    """Any run of digits and separators: a number or decimal, else the groups one by one with their
    separators spoken (192.168.1.1, 1.2.3)."""
    words = decimal(number, positions)
    if words is not None:
        return words
    tables = text_tables()
    words = []
    start = 0
    for part in re.split(r"([.,:/])", number):
        if part in _SEPARATOR_WORDS:
            words.append((tables.words[_SEPARATOR_WORDS[part]], positions[start]))
        elif part and part != ":":
            words.extend(cardinal(part, positions[start : start + len(part)]))
        start += len(part)
    return words


def ordinal_words(words: Words) -> Words:
    """A number's words with the last one made ordinal: yirmi bir -> yirmi birinci."""
    last, offset = words[-1]
    return [*words[:-1], (ordinal(last), offset)]


def locative(words: Words) -> Words:
    """A number's words with the last in the locative: dört -> dörtte, altı -> altıda."""
    last, offset = words[-1]
    letters = spoken_suffix([(letter, offset) for letter in last], [("d", offset), ("e", offset)])
    return [*words[:-1], ("".join(letter for letter, _ in letters), offset)]


Digits = tuple[str, Sequence[int]]  # digits as written and the source index of each


def fraction(numerator: Digits, denominator: Digits) -> Words:
    """1/2 yarım, 1/4 çeyrek, otherwise the denominator in the locative and the numerator: 3/4 dörtte üç."""
    tables = text_tables()
    value = (int(numerator[0]), int(denominator[0].replace(".", "")))
    if value == (1, 2):
        return [(tables.words["half"], numerator[1][0])]
    if value == (1, 4):
        return [(tables.words["quarter"], numerator[1][0])]
    return locative(cardinal(*denominator)) + value_words(*numerator)


def mixed_number(whole: Words, numerator: Digits, denominator: Digits) -> Words:
    """2 1/2 iki buçuk; 3 3/4 üç tam dörtte üç."""
    tables = text_tables()
    if (int(numerator[0]), int(denominator[0])) == (1, 2):
        return whole + [(tables.words["and_a_half"], numerator[1][0])]
    return whole + [(tables.words["whole"], numerator[1][0])] + fraction(numerator, denominator)
