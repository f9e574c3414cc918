"""Written forms a Turkish reader expands: dates, times, money, phone numbers, fractions, ranges, Roman
numerals, degrees and e-mail or web addresses.

Each reader looks at the composed text of one run at a token's start and returns the spoken words, each
at the source index of the character it reads, and where the form ends. Suffixes and units after a form
are added by the caller (normalize.py), so "09:00'da" and "120 km/sa" share that logic with plain numbers.
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cache

from .numbers import (
    THOUSANDS,
    Digits,
    Words,
    cardinal,
    decimal,
    digit_names,
    fraction,
    locative,
    mixed_number,
    ordinal_words,
    value_words,
)
from .tables import VOWELS, fold_letter, text_tables, turkish_lower


@dataclass(frozen=True)
class Reading:
    words: Words
    end: int  # index into the run's text just after the form
    takes_unit: bool = False  # a number or range that a unit may follow: "10-20 km"


_DASHES = "-–"
_LETTER_AFTER = r"(?![^\W\d_])"
_NUMBER = rf"(?:{THOUSANDS}(?:,[0-9]+)?|[0-9]+(?:,[0-9]+)?)"
_DATE = re.compile(
    r"(?P<day>[0-9]{1,2})(?P<separator>[./-])(?P<month>[0-9]{1,2})(?P=separator)(?P<year>[0-9]{4})(?![0-9])"
    r"|(?P<iso_year>[0-9]{4})-(?P<iso_month>[0-9]{2})-(?P<iso_day>[0-9]{2})(?![0-9])"
)
_DAY_MONTH = re.compile(r"(?P<day>[0-9]{1,2})/(?P<month>[0-9]{2})(?![0-9/])")
_TIME = re.compile(
    r"(?P<hour>[01]?[0-9]|2[0-3]|24(?=[:.]00))(?P<separator>[:.])(?P<minute>[0-5][0-9])(?![0-9]|[:.,][0-9])"
)
_PHONE = re.compile(
    r"(?:\+90[ -]?|0[ -]?)\(?[0-9]{3}\)?[ -]?[0-9]{3}[ -]?[0-9]{2}[ -]?[0-9]{2}(?![0-9])"
    r"|\+90[ -]?[0-9]{3}[ -]?[0-9]{3}[ -]?[0-9]{4}(?![0-9])"
)
_AMOUNT = (
    rf"(?P<integer>{THOUSANDS}|[0-9]+)(?:,(?P<cents>[0-9]{{1,2}})|\.(?P<point_cents>[0-9]{{2}}))?(?![0-9])"
)
_RATIO = re.compile(rf"1:(?P<denominator>{THOUSANDS}|[0-9]{{3,}})(?![0-9:])")
_MIXED = re.compile(r"(?P<whole>[0-9]+) (?P<numerator>[0-9]+)/(?P<denominator>[0-9]+)(?![0-9/])")
_FRACTION = re.compile(rf"(?P<numerator>[0-9]+)/(?P<denominator>{THOUSANDS}|[0-9]+)(?![0-9/]|[.,][0-9])")
_VULGAR = re.compile(r"(?P<whole>[0-9]+)?(?P<vulgar>[\u00bc-\u00be\u2150-\u215e])")
_VULGAR_SIGNS = re.compile("[\u00bc-\u00be\u2150-\u215e]")
_DIGITS = re.compile("[0-9]*")
# What may follow the first digits of a date, time, fraction, range, degree, decimal or fixed form.
_SEPARATORS_IN_FORMS = frozenset("./:-–,°")
_RANGE = re.compile(
    rf"(?P<first>{_NUMBER})[{_DASHES}](?P<second>{_NUMBER})(?P<ordinal>\.(?=[^\S\n]+[^\W\d_]))?"
    rf"(?![0-9]|[{_DASHES}][0-9]|[.,/:][0-9])"
)
_TIMES = re.compile(
    rf"(?P<first>{_NUMBER})[^\S\n]?(?P<sign>[x×])[^\S\n]?(?P<second>{_NUMBER})(?![0-9])"
)  # 1920x1080
_PERCENT = re.compile(
    rf"%[^\S\n]?(?P<minus>[-−])?(?P<first>[0-9]+\.[0-9]{{1,2}}(?![0-9])|{_NUMBER})(?:[{_DASHES}]%?(?P<second>{_NUMBER}))?(?![0-9])"
)
_DEGREES = re.compile(
    r"(?P<degrees>[0-9]+(?:[.,][0-9]+)?)°(?:[^\S\n]?(?P<minutes>[0-9]+)['′]"
    r"(?:[^\S\n]?(?P<seconds>[0-9]+(?:[.,][0-9]+)?)(?:\"|″|''))?)?[^\S\n]?(?P<direction>[KGDB])"
    + _LETTER_AFTER
)
# A map position: latitude and longitude as decimals with at least four places (39.9334, 32.8597).
_COORDINATES = re.compile(
    r"(?P<latitude>-?[0-9]{1,2}\.[0-9]{4,}),[^\S\n]*(?P<longitude>-?[0-9]{1,3}\.[0-9]{4,})(?![0-9])"
)
_ROMAN = re.compile(r"(?P<roman>[IVXLCDM]+)(?P<dot>\.)?(?=[^\S\n]+(?P<next>[^\W\d_]+))")
_ROMAN_VALUES = {"I": 1, "V": 5, "X": 10, "L": 50, "C": 100, "D": 500, "M": 1000}
_EMAIL = re.compile(r"[A-Za-z0-9][A-Za-z0-9._+-]*@[A-Za-z0-9-]+(?:\.[A-Za-z0-9-]+)+")
_URL = re.compile(r"(?:https?://|www\.)[^\s<>\"]+")
_ADDRESS_PART = re.compile(r"[^\W\d_]+|[0-9]+|.")
_NUMBER_BEFORE = re.compile(r"(?:\b[Nn]o|\b[Nn]u|\b[Nn]umara)[.:]?[^\S\n]*$")
_TIME_WORD_BEFORE = re.compile(r"\b(?:[Ss]aat|SAAT)[^\W\d_]*[^\S\n]+$")
_WORD_BEFORE = re.compile(r"([^\W\d_]+)[^\S\n]*$")
_SENTENCE_BEFORE = re.compile(r"(?:^|[.!?…:\n])[\s\"'“”«»(]*$")


def _roman_value(numeral: str) -> int | None:
    """The value of a Roman numeral written canonically (XIX, not IXX or IIII), else None."""
    total = 0
    for index, letter in enumerate(numeral):
        value = _ROMAN_VALUES[letter]
        following = _ROMAN_VALUES[numeral[index + 1]] if index + 1 < len(numeral) else 0
        total += -value if value < following else value
    return total if total > 0 and _to_roman(total) == numeral else None


def _to_roman(value: int) -> str:
    numeral = []
    for number, letters in (
        (1000, "M"), (900, "CM"), (500, "D"), (400, "CD"), (100, "C"), (90, "XC"),
        (50, "L"), (40, "XL"), (10, "X"), (9, "IX"), (5, "V"), (4, "IV"), (1, "I"),
    ):  # fmt: skip
        count, value = divmod(value, number)
        numeral.append(letters * count)
    return "".join(numeral)


@cache
def _bare_domain() -> re.Pattern[str]:
    """A lowercase web address without "www." or a scheme: ornek.com.tr, ornek.com/rapor."""
    domains = "|".join(sorted(text_tables().top_level_domains, key=len, reverse=True))
    return re.compile(rf"[a-z0-9-]+(?:\.[a-z0-9-]+)*\.(?:{domains})(?![\w.]|\.[a-z0-9])(?:/[^\s<>\"]*)?")


@cache
def _money_patterns() -> tuple[re.Pattern[str], re.Pattern[str]]:
    """An amount and its currency (1.250,50 ₺, 100 TL), and a sign before its amount ($4.99)."""
    signs = "|".join(re.escape(key) for key in sorted(text_tables().currencies, key=len, reverse=True))
    return (
        re.compile(rf"{_AMOUNT}[^\S\n]?(?P<currency>{signs}){_LETTER_AFTER}"),
        re.compile(rf"(?P<currency>{signs})[^\S\n]?{_AMOUNT}"),
    )


class WrittenForms:
    """The readers for one run's composed text; `offsets` maps each character to its source index."""

    def __init__(self, text: str, offsets: Sequence[int]) -> None:
        self.text = text
        self.offsets = offsets
        self.tables = text_tables()

    # ------------------------------------------------------------ helpers

    def at(self, start: int, end: int) -> list[int]:
        return list(self.offsets[start:end])

    def digits(self, match: re.Match[str], group: str) -> Digits:
        return match.group(group), self.at(match.start(group), match.end(group))

    def group_words(self, match: re.Match[str], group: str, reader: Callable = cardinal) -> Words:
        return reader(match.group(group), self.at(match.start(group), match.end(group)))

    def spoken(self, word: str, index: int) -> tuple[str, int]:
        return (word, self.offsets[index])

    def word_before(self, start: int) -> str | None:
        match = _WORD_BEFORE.search(self.text, max(0, start - 40), start)
        return match.group(1) if match else None

    def sentence_starts_at(self, start: int) -> bool:
        return _SENTENCE_BEFORE.search(self.text, max(0, start - 10), start) is not None

    # ------------------------------------------------------------ entry points

    def after_digit(self, start: int) -> Reading | None:
        """A form that starts with a digit. Most numbers are plain ("2024 yılında"): after digits and a
        space or a letter only a phone number, an amount, a mixed fraction or a product can go on."""
        following = self.text[_DIGITS.match(self.text, start).end() :][:1]
        if following in _SEPARATORS_IN_FORMS or _VULGAR_SIGNS.match(following):
            readers = self.digit_readers
        elif following.isspace() or not following:
            readers = (self.phone, self.money, self.mixed, self.times)
        else:
            readers = (self.money, self.times)
        return self.first_reading(readers, start)

    @property
    def digit_readers(self) -> tuple[Callable[[int], Reading | None], ...]:
        return (
            self.fixed,
            self.coordinates,
            self.phone,
            self.date_range,
            self.date,
            self.time_range,
            self.time,
            self.degrees,
            self.money,
            self.ratio,
            self.mixed,
            self.vulgar,
            self.day_month,
            self.fraction,
            self.range,
            self.times,
        )

    def after_symbol(self, start: int) -> Reading | None:
        """A form that starts with a sign: +90 ..., -12.3456, %10-20, $5, ½."""
        sign = self.text[start]
        if sign not in "+-%" and sign not in self.tables.currencies and not _VULGAR_SIGNS.match(sign):
            return None
        return self.first_reading(
            (self.coordinates, self.phone, self.percent, self.money, self.vulgar), start
        )

    @staticmethod
    def first_reading(readers: Sequence[Callable[[int], Reading | None]], start: int) -> Reading | None:
        for reader in readers:
            reading = reader(start)
            if reading is not None:
                return reading
        return None

    def after_letter(self, start: int) -> Reading | None:
        """A form that starts with a letter: Roman numerals, e-mail or web addresses (½ is a letter to re)."""
        return self.first_reading((self.address, self.roman, self.vulgar), start)

    # ------------------------------------------------------------ numbers

    def fixed(self, start: int) -> Reading | None:
        for written, said in self.tables.fixed_expressions.items():
            end = start + len(written)
            if self.text.startswith(written, start) and not self.text[end : end + 1].isalnum():
                return Reading([self.spoken(said, start)], end)
        return None

    def coordinates(self, start: int) -> Reading | None:
        """39.9334, 32.8597 enlem otuz dokuz virgül dokuz üç üç dört, boylam otuz iki virgül ..."""
        match = _COORDINATES.match(self.text, start)
        if (
            not match
            or abs(float(match.group("latitude"))) > 90
            or abs(float(match.group("longitude"))) > 180
        ):
            return None
        words: Words = []
        for group in ("latitude", "longitude"):
            begin = match.start(group)
            words.append(self.spoken(self.tables.words[group], begin))
            if self.text[begin] == "-":
                words.append(self.spoken(self.tables.words["minus"], begin))
                begin += 1
            words += decimal(self.text[begin : match.end(group)], self.at(begin, match.end(group)))
        return Reading(words, match.end())

    def phone(self, start: int) -> Reading | None:
        match = _PHONE.match(self.text, start)
        if not match:
            return None
        words = [self.spoken(self.tables.words["plus"], start)] if self.text[start] == "+" else []
        for index in range(match.start(), match.end()):
            if self.text[index].isdigit():
                words.extend(digit_names(self.text[index], [self.offsets[index]]))
        return Reading(words, match.end())

    def _date_words(self, match: re.Match[str]) -> Words | None:
        prefix = "iso_" if match.group("iso_year") else ""
        day, month = int(match.group(prefix + "day")), int(match.group(prefix + "month"))
        if not (1 <= day <= 31 and 1 <= month <= 12):
            return None
        month_start = match.start(prefix + "month")
        return (
            self.group_words(match, prefix + "day", value_words)
            + [self.spoken(self.tables.months[month - 1], month_start)]
            + self.group_words(match, prefix + "year")
        )

    def date(self, start: int) -> Reading | None:
        match = _DATE.match(self.text, start)
        words = match and self._date_words(match)
        return Reading(words, match.end()) if words else None

    def date_range(self, start: int) -> Reading | None:
        first = _DATE.match(self.text, start)
        if not first or self.text[first.end() : first.end() + 1] not in tuple(_DASHES):
            return None
        second = _DATE.match(self.text, first.end() + 1)
        words, other = first and self._date_words(first), second and self._date_words(second)
        if not words or not other:
            return None
        return Reading(words + [self.spoken(self.tables.words["range"], first.end())] + other, second.end())

    def day_month(self, start: int) -> Reading | None:
        """15/03: a day and a month (the month written with two digits, and no fraction: 1/10 is one)."""
        match = _DAY_MONTH.match(self.text, start)
        if not match:
            return None
        day, month = int(match.group("day")), int(match.group("month"))
        if not (1 <= day <= 31 and 1 <= month <= 12) or not (match.group("month")[0] == "0" or day > month):
            return None
        words = self.group_words(match, "day", value_words)
        return Reading(
            words + [self.spoken(self.tables.months[month - 1], match.start("month"))], match.end()
        )

    def _time_words(self, match: re.Match[str]) -> Words:
        """09:30 dokuz otuz, 09:00 dokuz, 10:05 on sıfır beş, 00:15 sıfır sıfır on beş."""
        hour = match.group("hour")
        words = self.group_words(match, "hour", cardinal if hour == "00" else value_words)
        minute = match.group("minute")
        if minute != "00":
            words += self.group_words(match, "minute", cardinal if minute[0] != "0" else digit_names)
        return words

    def _is_time(self, match: re.Match[str] | None, start: int) -> bool:
        """A colon always makes a time; a dot (14.30) only before a suffix (14.30'da) or after "saat"."""
        if not match:
            return False
        if match.group("separator") == ":":
            return True
        following = self.text[match.end() : match.end() + 1]
        return (
            following != ""
            and following in "'’"
            or bool(_TIME_WORD_BEFORE.search(self.text, max(0, start - 20), start))
        )

    def time(self, start: int) -> Reading | None:
        match = _TIME.match(self.text, start)
        if not self._is_time(match, start):
            return None
        return Reading(self._time_words(match), match.end())

    def time_range(self, start: int) -> Reading | None:
        """10:00-12:00 on ile on iki; 14.30-15.30 too (two times with a dash are a range of times)."""
        first = _TIME.match(self.text, start)
        if not first or self.text[first.end() : first.end() + 1] not in tuple(_DASHES):
            return None
        second = _TIME.match(self.text, first.end() + 1)
        if not second or first.group("separator") != second.group("separator"):
            return None
        words = self._time_words(first) + [self.spoken(self.tables.words["range"], first.end())]
        return Reading(words + self._time_words(second), second.end())

    def degrees(self, start: int) -> Reading | None:
        """39°56'12"K otuz dokuz derece elli altı dakika on iki saniye kuzey."""
        match = _DEGREES.match(self.text, start)
        if not match:
            return None
        words = self.group_words(match, "degrees", self.number)
        words.append(self.spoken(self.tables.words["degree"], match.end("degrees")))
        for group, name in (("minutes", "minute"), ("seconds", "second")):
            if match.group(group):
                words += self.group_words(match, group, self.number)
                words.append(self.spoken(self.tables.words[name], match.end(group)))
        direction = self.tables.directions[match.group("direction")]
        return Reading(words + [self.spoken(direction, match.start("direction"))], match.end())

    @staticmethod
    def number(text: str, positions: Sequence[int]) -> Words:
        words = decimal(text, positions)
        return words if words is not None else cardinal(text, positions)

    def money(self, start: int) -> Reading | None:
        """1.250,50 ₺ bin iki yüz elli lira elli kuruş; $4.99 dört dolar doksan dokuz sent."""
        amount_first, sign_first = _money_patterns()
        match = amount_first.match(self.text, start)
        if not match:
            match = sign_first.match(self.text, start)
            if not match or match.group("currency")[0].isalpha():
                return None
        currency = self.tables.currencies[match.group("currency")]
        at_sign = match.start("currency")
        words = self.group_words(match, "integer")
        cents_group = (
            "cents" if match.group("cents") else "point_cents" if match.group("point_cents") else None
        )
        cents = match.group(cents_group) if cents_group else ""
        if int(match.group("integer").replace(".", "")) or not int(cents or "0"):
            words.append(self.spoken(currency.name, at_sign))
        else:
            words = []
        if cents and int(cents):  # 9,5 € is dokuz avro elli sent: one digit is tens of cents
            positions = self.at(match.start(cents_group), match.end(cents_group))
            words += value_words(cents.ljust(2, "0"), (positions * 2)[:2])
            words.append(self.spoken(currency.subunit, at_sign))
        return Reading(words, match.end())

    def ratio(self, start: int) -> Reading | None:
        """1:1000 binde bir (a map scale)."""
        match = _RATIO.match(self.text, start)
        if not match:
            return None
        words = locative(self.group_words(match, "denominator"))
        return Reading(words + [self.spoken(self.tables.digits[1], start)], match.end())

    def fraction(self, start: int) -> Reading | None:
        match = _FRACTION.match(self.text, start)
        if not match or int(match.group("denominator").replace(".", "")) == 0:
            return None
        numerator, denominator = (
            int(match.group("numerator")),
            int(match.group("denominator").replace(".", "")),
        )
        # No: 5/7 (an address) and 5/2 (an article and its paragraph) are read with "bölü"; fractions are
        # smaller than one.
        if numerator >= denominator or _NUMBER_BEFORE.search(self.text, max(0, start - 12), start):
            slash = match.start("denominator") - 1
            words = self.group_words(match, "numerator") + [self.spoken(self.tables.words["fraction"], slash)]
            return Reading(words + self.group_words(match, "denominator"), match.end())
        words = fraction(self.digits(match, "numerator"), self.digits(match, "denominator"))
        return Reading(words, match.end(), takes_unit=True)

    def mixed(self, start: int) -> Reading | None:
        match = _MIXED.match(self.text, start)
        if not match or not 0 < int(match.group("numerator")) < int(match.group("denominator")):
            return None
        words = mixed_number(
            self.group_words(match, "whole"),
            self.digits(match, "numerator"),
            self.digits(match, "denominator"),
        )
        return Reading(words, match.end(), takes_unit=True)

    def vulgar(self, start: int) -> Reading | None:
        """½ yarım, 2½ iki buçuk, ¾ dörtte üç."""
        match = _VULGAR.match(self.text, start)
        if not match:
            return None
        numerator, _, denominator = unicodedata.normalize("NFKC", match.group("vulgar")).partition("\u2044")
        if not numerator.isdigit() or not denominator.isdigit():
            return None
        at_sign = self.offsets[match.start("vulgar")]  # every word of ½ sits on the sign
        parts = ((numerator, [at_sign] * len(numerator)), (denominator, [at_sign] * len(denominator)))
        if match.group("whole"):
            words = mixed_number(self.group_words(match, "whole"), *parts)
        else:
            words = fraction(*parts)
        return Reading(words, match.end(), takes_unit=True)

    def range(self, start: int) -> Reading | None:
        """3-5 kişi üç beş; 2020-2025 iki bin yirmi ile iki bin yirmi beş; 3-5. maddeler üçüncü ile beşinci.
        Small numbers side by side are said side by side (so are scores, 3-1); years, thousands, ordinals
        and days before a month take "ile"."""
        match = _RANGE.match(self.text, start)
        if not match or match.group("second")[0] == "0" and len(match.group("second")) > 1:
            return None  # 2024-0153 is a code, read group by group
        first = self.group_words(match, "first", self.number)
        second = self.group_words(match, "second", self.number)
        values = [match.group(name) for name in ("first", "second")]
        following = self.word_before_next(match.end())
        joined = (
            match.group("ordinal") is not None
            or any("." in value or int(value.split(",")[0]) >= 1000 for value in values)
            or following in self.tables.months
        )
        if match.group("ordinal"):
            first, second = ordinal_words(first), ordinal_words(second)
        dash = match.end("first")
        middle = [self.spoken(self.tables.words["range"], dash)] if joined else []
        return Reading(first + middle + second, match.end(), takes_unit=not match.group("ordinal"))

    def times(self, start: int) -> Reading | None:
        """1920x1080 bin dokuz yüz yirmi çarpı bin seksen; 3 × 4."""
        match = _TIMES.match(self.text, start)
        if not match:
            return None
        sign = self.spoken(self.tables.words["times"], match.start("sign"))
        words = self.group_words(match, "first", self.number) + [sign]
        return Reading(words + self.group_words(match, "second", self.number), match.end(), takes_unit=True)

    def word_before_next(self, end: int) -> str | None:
        """The next word after `end`, lowercased (for "1-5 Haziran")."""
        match = re.compile(r"[^\S\n]*([^\W\d_]+)").match(self.text, end)
        return turkish_lower(match.group(1)) if match else None

    def percent(self, start: int) -> Reading | None:
        """%18,5 yüzde on sekiz virgül beş; %10-20 yüzde on ile yirmi; %-3 yüzde eksi üç."""
        match = _PERCENT.match(self.text, start)
        if not match:
            return None
        words = [self.spoken(self.tables.words["percent"], start)]
        if match.group("minus"):  # %-3: yüzde eksi üç
            words.append(self.spoken(self.tables.words["minus"], match.start("minus")))
        words += self.group_words(match, "first", self.number)
        if match.group("second"):
            words.append(self.spoken(self.tables.words["range"], match.end("first")))
            if self.text[match.start("second") - 1] == "%":
                words.append(self.spoken(self.tables.words["percent"], match.start("second") - 1))
            words += self.group_words(match, "second", self.number)
        return Reading(words, match.end())

    # ------------------------------------------------------------ letters

    def roman(self, start: int) -> Reading | None:
        """XX. yüzyıl yirminci yüzyıl, II. Abdülhamit ikinci Abdülhamit, Sultan V. Mehmet; not the initial
        in "Mehmet V. Delibaş", a lone "I", "VIP", or an acronym such as "CD." or "MI"."""
        match = _ROMAN.match(self.text, start)
        if not match:
            return None
        numeral, following = match.group("roman"), match.group("next")
        value = _roman_value(numeral)
        if value is None or value >= 100 or numeral == "L":
            return None
        if not match.group("dot"):  # XXI yüzyıl: only before a word that counts in ordinals
            if len(numeral) < 2 or turkish_lower(following) not in ("yüzyıl", "yüzyılda", "yüzyılın", "asır"):
                return None
        elif following[0].isupper():
            before = self.word_before(start)
            names_before = before is not None and before[0].isupper() and not self.sentence_starts_at(start)
            if names_before and turkish_lower(before) not in self.tables.regnal_titles:
                return None  # an initial between names
            if before is None and not self.sentence_starts_at(start):
                return None
        words = ordinal_words(cardinal(str(value), [self.offsets[start]] * len(str(value))))
        return Reading(words, match.end())

    def address(self, start: int) -> Reading | None:
        """ali.veli@ornek.com.tr ali nokta veli et ornek nokta com nokta te re; https://www.x.gov.tr/harita
        without the scheme and "www"; a query (?x=1) is not read."""
        match = (
            _EMAIL.match(self.text, start)
            or _URL.match(self.text, start)
            or _bare_domain().match(self.text, start)
        )
        if not match:
            return None
        text = match.group().rstrip(".,;:!?)")
        if "@" not in text and "/" not in text and not text.startswith("www.") and "." not in text:
            return None
        end = start + len(text)
        body_start = start
        scheme = re.match(r"(?:https?://)?(?:www\.)?", text)
        body_start += scheme.end()
        body_end = start + len(re.split(r"[?#]", text, maxsplit=1)[0])
        words: Words = []
        for part in _ADDRESS_PART.finditer(self.text, body_start, body_end):
            words.extend(self.address_part(part.group(), part.start()))
        return Reading(words, end) if words else None

    def address_part(self, part: str, start: int) -> Words:
        tables = self.tables
        if part[0] in "0123456789":
            return cardinal(part, self.at(start, start + len(part)))
        if part.isalpha():  # a word as written, letter by letter; a part without vowels spelled (tr, pdf)
            # Addresses are ASCII: their I is i. Letters are folded to Turkish ones (w -> v).
            letters = [
                (letter, self.offsets[start + index])
                for index, char in enumerate(part)
                for letter in fold_letter(char.lower() if char.isascii() else char)
            ]
            if len(part) > 1 and any(letter in VOWELS for letter, _ in letters):
                return [("".join(letter for letter, _ in letters), tuple(offset for _, offset in letters))]
            names = tables.letter_names
            spelled: Words = []
            for index, char in enumerate(part):  # x is "iks", not the letters of "ks"
                lower = char.lower() if char.isascii() else turkish_lower(char)
                folded = [lower] if lower in names else list(fold_letter(char))
                spelled += [(names.get(letter, letter), self.offsets[start + index]) for letter in folded]
            return spelled
        said = tables.address_words.get(part)
        return [(said, self.offsets[start])] if said else []
