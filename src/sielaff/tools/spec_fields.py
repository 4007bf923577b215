"""What a spec says, checked: its numbers, its 17 fields and range cards, and the text
of a spec written back (``sielaff synth --write-best``).

Shared by the readers of the spec's tables (:mod:`sielaff.tools.spec` for the deck and
the file, :mod:`sielaff.tools.spec_scene` for ``[scene]``, :mod:`sielaff.tools.spec_sweep`
for ``[sweep]``; the commands read their own ``[synthesis]``, ``[tolerance]`` and
``[motor]``).  The spec's format is in :mod:`sielaff.tools.spec`.  Every error is a
:class:`PunchError`: one line naming the file and the key.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from decimal import Decimal

from sielaff.tools.errors import EXIT_DECK as EXIT_SPEC

__all__ = ["FOUR_BAR", "MAX_DIGITS", "MAX_EXPONENT", "OTHER_TABLES", "PunchError",
           "kind_names", "linkage_kind", "spec_dict",
           "spec_number", "spec_text", "spec_values", "spec_whole"]

LINKS = ("crank", "coupler", "rocker")
#: (section, key, sub-key or None) -> listing name.
SPEC_NAMES: dict[tuple[str, str, str | None], str] = {
    ("weights", "crank", None): "W2",
    ("weights", "coupler", None): "W3",
    ("weights", "rocker", None): "W4",
    ("inertia", "crank", None): "ZI2",
    ("inertia", "coupler", None): "ZI3",
    ("inertia", "rocker", None): "ZI4",
    ("lengths", "frame", None): "R1",
    ("lengths", "crank", None): "R2",
    ("lengths", "coupler", None): "R3",
    ("lengths", "rocker", None): "R4",
    ("mass_centres", "crank", "angle"): "ADEL2",
    ("mass_centres", "coupler", "angle"): "ADEL3",
    ("mass_centres", "rocker", "angle"): "ADEL4",
    ("mass_centres", "crank", "distance"): "RG2",
    ("mass_centres", "coupler", "distance"): "RG3",
    ("mass_centres", "rocker", "distance"): "RG4",
    ("drive", "speed", None): "TH2D",
}
RANGE_KEYS = ("start", "step", "stop")
#: The tables a spec may hold besides the mechanism's: each is read by the command that
#: owns it (so one spec serves several commands); any other table is refused.
OTHER_TABLES = ("linkage", "scene", "sweep", "motor", "synthesis", "tolerance")

#: The four-bar's ``[linkage] kind`` (the default: a spec without ``[linkage]``).
FOUR_BAR = "four-bar"
#: The commands that take a linkage of every kind (the others take a four-bar only so far).
KIND_COMMANDS = ("table", "check", "plot", "simulate", "sweep", "tolerance", "report")


def kind_names() -> dict[str, dict[tuple[str, str, str | None], str]]:
    """Each ``[linkage] kind`` a spec may name (the engine's models of a kind), with where
    its fields are given."""
    from sielaff.engine.analysis import MODELS

    out = {FOUR_BAR: SPEC_NAMES}
    for model in MODELS:
        kind = getattr(model.mechanism, "KIND", None)
        if kind is not None:
            out[kind] = model.mechanism.SPEC_NAMES  # type: ignore[union-attr]
    return out


def linkage_kind(spec: dict, path: str = "<spec>") -> str:
    """The spec's ``[linkage] kind`` ("four-bar" without one); one line naming the key if
    it is not a kind sielaff knows."""
    table = _table(f"{path}: [linkage]", spec.get("linkage", {}))
    _unknown(f"{path}: [linkage]", table, ("kind",))
    return _name(f"{path}: [linkage] kind", table.get("kind", FOUR_BAR), tuple(kind_names()))


@dataclass(frozen=True)
class Key:
    """One key of a spec's table as its reader declares it: ``sielaff help spec`` and
    docs/spec.md are made from these, and the reader refuses any key not declared.

    ``kind``: the kind of quantity (:data:`sielaff.quantities.KINDS`, for its unit in
    either unit system), ``"name"``, ``"bool"``, ``"integer"``, ``"list"`` or
    ``"table"``; ``default``: as written in a spec, or ``""`` (required or none);
    ``bounds``: the values it takes, in words."""

    name: str
    kind: str
    default: str
    bounds: str
    meaning: str


def key_names(keys: tuple[Key, ...]) -> tuple[str, ...]:
    return tuple(k.name for k in keys)

#: The cards, as listing names (card 7 on: the range cards).
CARDS = (("W2", "W3", "W4"), ("ZI2", "ZI3", "ZI4"), ("R1", "R2", "R3", "R4"),
         ("ADEL2", "ADEL3", "ADEL4"), ("RG2", "RG3", "RG4"), ("TH2D",))


class PunchError(Exception):
    """A spec that cannot be punched; ``str(err)`` is one line."""

    def __init__(self, message: str, status: int = EXIT_SPEC) -> None:
        super().__init__(message)
        self.status = status


# --------------------------------------------------------------------------
# The spec
# --------------------------------------------------------------------------


#: Every number a spec gives is bounded before any arithmetic: finite, at most
#: :data:`MAX_DIGITS` significant digits (the decimal module's default precision, so no
#: step rounds one silently), and 0 or of magnitude from 1E-99 to below 1E99 (the IBM
#: 1410's range, as for a deck's fields).
MAX_DIGITS = 28
MAX_EXPONENT = 98


def _shown(d: Decimal) -> str:
    text = str(d)
    return text if len(text) <= 40 else f"{text[:20]}...({len(text)} characters)"


def spec_number(where: str, value) -> Decimal:
    """``value`` (an int or a Decimal from the TOML) as a Decimal, checked as
    :data:`MAX_DIGITS` and :data:`MAX_EXPONENT` say; PunchError naming ``where`` if not.
    Only integer operations on the digits are used here, so nothing can overflow."""
    if isinstance(value, bool) or not isinstance(value, int | Decimal):
        raise PunchError(f"{where} = {value!r}: not a number")
    d = Decimal(value)
    if not d.is_finite():
        raise PunchError(f"{where} = {d}: {d} is not a finite number")
    if not d:
        return Decimal(0) if d.is_signed() else d
    sign, digits, exponent = d.as_tuple()
    zeros = len(digits) - len(bytes(digits).rstrip(b"\0"))
    significant = len(digits) - zeros
    adjusted = d.adjusted()
    if not -MAX_EXPONENT - 1 <= adjusted <= MAX_EXPONENT:
        raise PunchError(f"{where} = {_shown(d)}: out of range (a spec number is 0 or of "
                         "magnitude from 1E-99 to below 1E99)")
    if significant > MAX_DIGITS:
        raise PunchError(f"{where} = {_shown(d)}: {significant} significant digits; a spec "
                         f"number has at most {MAX_DIGITS} (a double holds about 17)")
    return d


_number = spec_number


def spec_whole(where: str, key: str, value, lo: int, hi: int, even: bool = False) -> int:
    """``value`` as a whole number from ``lo`` to ``hi`` (and even, if ``even``: a count
    of crank angles); PunchError naming ``where`` and ``key`` if not."""
    if not (isinstance(value, int) and not isinstance(value, bool) and lo <= value <= hi) \
            or (even and value % 2):
        raise PunchError(f"{where} {key} = {value!r}: a whole number from {lo} to {hi}"
                         + (", even" if even else ""))
    return value


def _table(where: str, value) -> dict:
    if not isinstance(value, dict):
        raise PunchError(f"{where}: expected a table, got {value!r}")
    return value


def _name(where: str, value, names, say: str | None = None):
    """A spec's name (a unit system, a branch, a link, a kind): ``value`` if it is one of
    ``names`` (strings, or the link numbers a link may also be), else one line naming
    ``where`` and what it may be (``say``, or the names).  The one reader of names: a
    list, a table or a boolean where a name stands is refused, never looked up."""
    if isinstance(value, bool) or not isinstance(value, str | int) or value not in names:
        words = [f'"{n}"' for n in names if isinstance(n, str)]
        choices = say or (", ".join(words[:-1]) + " or " + words[-1] if len(words) > 1
                          else "".join(words))
        raise PunchError(f"{where} = {value!r}: {choices}")
    return value


def _unknown(where: str, table: dict, known) -> None:
    extra = [k for k in table if k not in known]
    if extra:
        raise PunchError(f"{where}: unknown key {extra[0]!r} (expected: {', '.join(known)})")


def spec_values(spec: dict, path: str = "<spec>", names: dict | None = None
                ) -> tuple[dict[str, Decimal], list[tuple[Decimal, Decimal, Decimal]], str | None]:
    """The listing's values (or those of ``names``: another kind's fields, as
    :func:`kind_names` gives them), the range cards and the sequence prefix (None: blank).

    Checks the spec's shape only (every key present, numbers, no unknown keys).
    """
    names = SPEC_NAMES if names is None else names
    sections: dict[str, list[str]] = {}
    for section, key, _ in names:
        keys = sections.setdefault(section, [])
        if key not in keys:
            keys.append(key)
    _unknown(path, spec, [*sections, "range", "deck", *OTHER_TABLES])
    values: dict[str, Decimal] = {}
    for section, keys in sections.items():
        if section not in spec:
            raise PunchError(f"{path}: missing [{section}] ({', '.join(keys)})")
        table = _table(f"{path}: [{section}]", spec[section])
        _unknown(f"{path}: [{section}]", table, keys)
        for key in keys:
            if key not in table:
                raise PunchError(f"{path}: [{section}] has no {key}")
    for (section, key, sub), name in names.items():
        item = spec[section][key]
        where = f"{path}: [{section}] {key}"
        if sub is not None:
            subs = [s for (t, k, s) in names if (t, k) == (section, key)]
            item = _table(where, item)
            _unknown(where, item, subs)
            if sub not in item:
                inline = ", ".join(f"{s} = ..." for s in subs)
                raise PunchError(f"{where} has no {sub} (write {key} = {{ {inline} }})")
            item, where = item[sub], f"{where}.{sub}"
        values[name] = _number(where, item)
    ranges = spec.get("range")
    if not ranges:
        raise PunchError(f"{path}: no [[range]] (start, step, stop in degrees)")
    if not isinstance(ranges, list):
        raise PunchError(f"{path}: write the range as [[range]], one table per range card")
    cards = []
    for n, r in enumerate(ranges, 1):
        where = f"{path}: [[range]] {n}"
        r = _table(where, r)
        _unknown(where, r, RANGE_KEYS)
        for key in RANGE_KEYS:
            if key not in r:
                raise PunchError(f"{where} has no {key}")
        cards.append(tuple(_number(f"{where} {k}", r[k]) for k in RANGE_KEYS))
    deck = _table(f"{path}: [deck]", spec.get("deck", {}))
    _unknown(f"{path}: [deck]", deck, ("sequence",))
    prefix = deck.get("sequence", "SIEL")
    if prefix is False:
        prefix = None
    elif not (isinstance(prefix, str) and re.fullmatch(r"[A-Z0-9]{0,4}", prefix)):
        raise PunchError(f"{path}: [deck] sequence = {prefix!r}: up to 4 capital letters or "
                         "digits, or false")
    return values, cards, prefix


def _where(path: str, name: str, names: dict | None = None) -> str:
    for (section, key, sub), n in (SPEC_NAMES if names is None else names).items():
        if n == name:
            return f"{path}: [{section}] {key}{'.' + sub if sub else ''}"
    return f"{path}: {name}"



def _float(where: str, value) -> float:
    """A spec's number as a float; a NaN, an infinity or a magnitude past the scene's
    bound is one line naming ``where``."""
    from sielaff.engine.values import LIMIT

    x = float(_number(where, value))
    if not abs(x) <= LIMIT:
        raise PunchError(f"{where} = {value!r}: not a finite value within {LIMIT:g}")
    return x



def spec_dict(values: dict[str, Decimal], ranges: list[tuple[Decimal, Decimal, Decimal]],
              base: dict | None = None) -> dict:
    """A spec (parsed form) with the 17 listing ``values`` and the range cards, keeping
    every other table of ``base`` (its [scene], [deck], [sweep])."""
    spec = {k: v for k, v in (base or {}).items()
            if k not in {s for s, _, _ in SPEC_NAMES} | {"range"}}
    for (section, key, sub), name in SPEC_NAMES.items():
        table = spec.setdefault(section, {})
        if sub is None:
            table[key] = values[name]
        else:
            table.setdefault(key, {})[sub] = values[name]
    spec["range"] = [dict(zip(RANGE_KEYS, r)) for r in ranges]
    return spec


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, Decimal)):
        text = str(v)
        return text if isinstance(v, int) or "." in text or "E" in text else text + ".0"
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(f"cannot write {v!r} in a spec")


def spec_text(spec: dict, header: str = "") -> str:
    """TOML text for a parsed spec (the inverse of :func:`read_spec`, comments aside)."""
    lines = [f"# {h}" for h in header.splitlines()]

    def table(name: str, body: dict) -> None:
        lines.append(f"\n[{name}]")  # sub-tables inline; lists of tables as [[name.key]]
        lines.extend(f"{k} = {_toml_value(v)}" for k, v in body.items() if not _is_tables(v))
        for k, v in body.items():
            if _is_tables(v):
                for item in v:
                    lines.append(f"\n[[{name}.{k}]]")
                    lines.extend(f"{kk} = {_toml_value(vv)}" for kk, vv in item.items())

    for name, body in spec.items():
        if isinstance(body, dict):
            table(name, body)
        elif _is_tables(body):
            for item in body:
                lines.append(f"\n[[{name}]]")
                lines.extend(f"{k} = {_toml_value(v)}" for k, v in item.items())
        else:
            lines.insert(len(header.splitlines()), f"{name} = {_toml_value(body)}")
    return "\n".join(lines).lstrip("\n") + "\n"


def _is_tables(v) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)
