"""Names as a house reads them: rooms, accents, and no word said twice.

PLC identifiers are ASCII (``Stineni``, ``detskyPokoj``, ``OBYVAK_STROP``); the
words of a Czech program come back with their accents from the program's own
texts (T_ApiObject titles, GTSAP1 names, where the installer typed ``Obývák``)
and, failing that, from a short list of the words of a house. A name that says a
room (English or Czech, in any case, with or without accents) gives that room,
spelled as an area is: ``Kuchyňská linka`` is the *Linka* of the *Kuchyň*.

Home Assistant builds an entity's ID from its area, its device and its own name,
and its friendly name from its device and its own name: a word the device already
says is not said again by the entity (``Heating`` · ``Curve shift``), and a room
the area already says is not said again in the entity's ID.
"""

from collections.abc import Iterable, Mapping
import re
from typing import Final, NamedTuple
import unicodedata


def folded(text: str) -> str:
    """Text without accents and case: ``Okno ložnice`` → ``okno loznice``."""
    decomposed = unicodedata.normalize("NFKD", text)
    return "".join(c for c in decomposed if not unicodedata.combining(c)).casefold()


ROOMS: Final[tuple[tuple[re.Pattern[str], str], ...]] = tuple(
    (re.compile(rf"(?<!\w)(?:{pattern})(?!\w)"), room)
    for pattern, room in (
        (r"detsk\w* pokoj\w*", "Dětský pokoj"),
        (r"obyvaci pokoj\w*|obyvak\w*", "Obývák"),
        (r"kuchyn\w*", "Kuchyň"),
        (r"jidel\w*", "Jídelna"),
        (r"loznic\w*", "Ložnice"),
        (r"koupel\w*", "Koupelna"),
        (r"zachod\w*|toalet\w*|wc", "WC"),
        (r"chodb\w*", "Chodba"),
        (r"predsin\w*", "Předsíň"),
        (r"garaz\w*", "Garáž"),
        (r"pracovn\w*", "Pracovna"),
        (r"podkrov\w*", "Podkroví"),
        (r"sklep\w*", "Sklep"),
        (r"pradel\w*", "Prádelna"),
        (r"spiz\w*", "Spíž"),
        (r"teras\w*", "Terasa"),
        (r"zahrad\w*", "Zahrada"),
        (r"living ?rooms?|living|lounge", "Living room"),
        (r"kitchens?", "Kitchen"),
        (r"dining ?rooms?|dining", "Dining room"),
        (r"bed ?rooms?", "Bedroom"),
        (r"bath ?rooms?", "Bathroom"),
        (r"toilets?", "Toilet"),
        (r"hall ?ways?|halls?|corridors?", "Hall"),
        (r"garages?", "Garage"),
        (r"offices?", "Office"),
        (r"study", "Study"),
        (r"kids ?rooms?|kids|children'?s? rooms?|nursery", "Kids room"),
        (r"guest ?rooms?", "Guest room"),
        (r"attics?", "Attic"),
        (r"basements?|cellars?", "Basement"),
        (r"laundry", "Laundry"),
        (r"gardens?", "Garden"),
        (r"terraces?", "Terrace"),
    )
)
"""The rooms a name may say (in folded words), and each room's area name."""

HOUSE_WORDS: Final[Mapping[str, str]] = {
    folded(word): word
    for word in [
        "bazén",
        "brána",
        "čerpadlo",
        "dětská",
        "dětské",
        "dětský",
        "dveře",
        "elektřina",
        "garáž",
        "garážová",
        "garážové",
        "hlavní",
        "hostovský",
        "chlazení",
        "jídelna",
        "kuchyň",
        "kuchyňská",
        "kuchyňský",
        "ložnice",
        "měření",
        "místnost",
        "místnosti",
        "obývací",
        "obývák",
        "ohřev",
        "osvětlení",
        "podkroví",
        "prádelna",
        "předsíň",
        "přízemí",
        "šatna",
        "spíž",
        "společenská",
        "střešní",
        "stínění",
        "světla",
        "světel",
        "světlo",
        "tlačítko",
        "topení",
        "venkovní",
        "větrání",
        "vnitřní",
        "vstupní",
        "vytápění",
        "zádveří",
        "závlaha",
        "zavlažování",
        "zásuvka",
        "zásuvky",
        "žaluzie",
    ]
}
"""Words of a house whose ASCII spelling (a PLC identifier) lost its accents."""

_WORD: Final = re.compile(r"\w+")
_LINKS: Final = frozenset({"v", "ve", "na", "u", "do", "in", "of", "at", "the"})
"""Small words that lead to a room at a name's end (*Světlo v ložnici*)."""


def vocabulary(texts: Iterable[str]) -> dict[str, str]:
    """Return the accented words of a program's texts, by their folded spelling.

    The program's own spelling wins over :data:`HOUSE_WORDS`.
    """
    words = dict(HOUSE_WORDS)
    for text in texts:
        for word in _WORD.findall(text):
            if not word.isascii():
                words[folded(word)] = word.lower()
    return words


def spelled(text: str, words: Mapping[str, str]) -> str:
    """Return text with its ASCII words accented as ``words`` spell them.

    ``Detsky pokoj`` → ``Dětský pokoj``; a word's capital stays.
    """

    def accent(match: re.Match[str]) -> str:
        word = match.group()
        if not word.isascii() or (known := words.get(word.lower())) is None:
            return word
        return known[:1].upper() + known[1:] if word[:1].isupper() else known

    return _WORD.sub(accent, text)


class Room(NamedTuple):
    """The room a name says, and what the name says besides."""

    area: str
    rest: str


def room_of(name: str) -> Room | None:
    """Return the room a name says and the rest of the name (None: no room).

    ``Kuchyňská linka`` → (``Kuchyň``, ``Linka``); ``Ložnice`` → (``Ložnice``, ``""``).
    """
    words = name.split()
    folded_words = [folded(word) for word in words]
    text = " ".join(folded_words)
    for pattern, area in ROOMS:
        if (match := pattern.search(text)) is None:
            continue
        first = text[: match.start()].count(" ")
        last = first + match.group().count(" ")
        kept = words[:first] + words[last + 1 :]
        # Světlo v ložnici: the light, without the "in" that led to the room.
        if first == len(kept):
            while kept and folded(kept[-1]) in _LINKS:
                kept.pop()
        rest = " ".join(kept)
        return Room(area=area, rest=rest[:1].upper() + rest[1:])
    return None


def without_leading(name: str, *said: str | None) -> str:
    """Return a name without the words another name already said before it.

    ``Ventilation filter clogged`` on the device ``Ventilation`` is ``Filter
    clogged``; a name that starts where its device's name ends says those words
    once (``Plant status`` on *Heating plant* is ``Status``); a name that says
    nothing more, or only the first words of its device's (``Heating`` on
    *Heating plant*), is ``""``. Words compare without accents and case, whole
    words only.
    """
    words = name.split()
    others = [[folded(word) for word in other.split()] for other in said if other]
    stripped = True
    while stripped and words:
        stripped = False
        here = [folded(word) for word in words]
        for other in others:
            if size := _said_before(here, other):
                words, stripped = words[size:], True
                break
    if len(words) == len(name.split()):
        return name
    rest = " ".join(words)
    return rest[:1].upper() + rest[1:]


def _said_before(words: list[str], other: list[str]) -> int:
    """Return how many of the first words another name said (0: none).

    The whole other name at the start, or its last words (an overlap of one
    name's end and the next's start), or all of the words as its first.
    """
    if words[: len(other)] == other:
        return len(other)
    if len(words) <= len(other) and other[: len(words)] == words:
        return len(words)
    for size in range(min(len(other) - 1, len(words)), 0, -1):
        if other[-size:] == words[:size]:
            return size
    return 0
