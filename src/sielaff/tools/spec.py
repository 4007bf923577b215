"""``sielaff punch SPEC.toml [-o DECK]``: punch a card deck from a readable spec.

The spec is a TOML file that names every value and gives it in the
report's units; ``punch`` turns it into the 80-column ``4F8.4`` deck the
1966 program reads (``decks/example.toml`` punches ``decks/example.dat``)::

    # The report's example problem (page 19).

    [weights]           # lb                        -> card 1: W2 W3 W4
    crank = 3.0
    coupler = 8.0
    rocker = 6.0

    [inertia]           # in-lb-sec^2, about G       -> card 2: ZI2 ZI3 ZI4
    crank = 0.0         # (never used: the crank turns at constant speed)
    coupler = 0.5
    rocker = 0.4

    [lengths]           # in                        -> card 3: R1 R2 R3 R4
    frame = 12.0        # O2 to O4
    crank = 4.0         # O2 to A
    coupler = 16.0      # A to B
    rocker = 12.0       # O4 to B

    [mass_centres]      # distance in, from the link's base pin (O2, A, O4);
                        # angle deg, + or - from the link's line
                        #                    -> card 4: ADEL2-4, card 5: RG2-4
    crank = { distance = 2.0, angle = 0.0 }
    coupler = { distance = 8.0, angle = -15.0 }
    rocker = { distance = 6.0, angle = 15.0 }

    [drive]
    speed = 50.0        # rad/sec, constant         -> card 6: TH2D

    [[range]]           # degrees, one card each    -> THZERO DELTA THMAX
    start = 10.0
    step = 10.0
    stop = 360.0

    [deck]              # optional
    sequence = "SIEL"   # columns 73-80: this prefix (at most 4 letters or
                        # digits; "" for none), then 10, 20, ... ; false: blank

Every key above is required except ``[deck]``; more ``[[range]]`` tables
punch more range cards.  Unknown keys are refused (they are typos).

Values are read as exact decimals and punched exactly: right-justified in
their 8-column field, with a decimal point (``    12.0``, ``     -.5``), or,
when only that fits, as 8 digits whose last 4 are the fraction
(``12345678`` = 1234.5678).  A value that cannot be punched exactly in an
F8.4 field is refused, never rounded: too many digits (0.333333333), out of
range (123456.78, 1E8), or so small that its digits do not fit (1E-9).  So
are a mechanism that is not a crank-rocker (the 1966 program would stop at
statement 52) and a range the 1966 loop would never leave (step <= 0 with
start <= stop).

Errors are :class:`PunchError` with a one-line message and the exit status
(2, or 3 for a mechanism that is not a crank-rocker).
"""

from __future__ import annotations

import os
import re
import tomllib
from decimal import Decimal
from typing import TYPE_CHECKING

from sielaff.emulator.cards import Deck, Range, read_field_decimal
from sielaff.mechanism import FIELD_NAMES, Mechanism, crank_rocker_failure

if TYPE_CHECKING:
    from sielaff.engine.scene import Scene

__all__ = ["PunchError", "punch_deck", "punch_field", "punch_file", "spec_deck", "spec_number",
           "spec_values"]

from sielaff.tools.errors import EXIT_DECK as EXIT_SPEC  # noqa: E402
from sielaff.tools.errors import EXIT_NOT_CRANK_ROCKER  # noqa: E402

WIDTH = 8

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

#: The cards, as listing names (card 7 on: the range cards).
CARDS = (("W2", "W3", "W4"), ("ZI2", "ZI3", "ZI4"), ("R1", "R2", "R3", "R4"),
         ("ADEL2", "ADEL3", "ADEL4"), ("RG2", "RG3", "RG4"), ("TH2D",))


class PunchError(Exception):
    """A spec that cannot be punched; ``str(err)`` is one line."""

    def __init__(self, message: str, status: int = EXIT_SPEC) -> None:
        super().__init__(message)
        self.status = status


# --------------------------------------------------------------------------
# One field
# --------------------------------------------------------------------------


def _fixed(a: Decimal) -> tuple[str, str]:
    """Integer and fraction digits of ``a`` >= 0, without trailing fraction zeros."""
    text = f"{a.normalize():f}" if a else "0"
    whole, _, frac = text.partition(".")
    return whole, frac.rstrip("0")


def punch_field(value: Decimal | int | str) -> str:
    """``value`` as an 8-column F8.4 field that reads back exactly; ValueError(reason) if none."""
    v = Decimal(value)
    if not v.is_finite():
        raise ValueError(f"{value} is not a finite number")
    if v == 0:
        return "0.0".rjust(WIDTH)
    sign = "-" if v < 0 else ""
    whole, frac = _fixed(abs(v))
    candidates = []
    if whole == "0":
        candidates += [f"{sign}0.{frac}", f"{sign}.{frac}"]
    else:
        candidates += [f"{sign}{whole}.{frac or '0'}", f"{sign}{whole}.{frac}"]
    if len(frac) <= 4:  # no point: the last 4 digits are the fraction
        candidates.append(sign + (whole + frac.ljust(4, "0")).lstrip("0"))
    for text in candidates:
        if len(text) <= WIDTH:
            field = text.rjust(WIDTH)
            assert read_field_decimal(field) == v, (field, v)
            return field
    shown = f"{sign}{whole}.{frac}" if frac else f"{sign}{whole}"
    if len(sign + whole) > WIDTH - 1:
        most = "9" * (WIDTH - 1 - len(sign))
        raise ValueError(f"out of range: {shown} has {len(whole)} digits before the point; "
                         f"an F8.4 field holds at most {sign}{most}.")
    room = WIDTH - len(sign) - (len(whole) if whole != "0" else 0) - 1  # fraction digits
    rounded = abs(v).quantize(Decimal(1).scaleb(-room)) if room >= 0 else None
    if not rounded:
        raise ValueError(f"too small: {shown} needs {len(shown)} columns and would punch as 0 "
                         f"in 8 (the smallest F8.4 value is .{'0' * (WIDTH - 2)}1)")
    raise ValueError(f"too many digits: {shown} needs {len(shown)} columns, an F8.4 field has "
                     f"{WIDTH}; punching it would lose precision (round it, e.g. to "
                     f"{sign}{rounded.normalize():f})")


# --------------------------------------------------------------------------
# The spec
# --------------------------------------------------------------------------


#: Every number a spec gives is bounded before any arithmetic: finite, at most
#: :data:`MAX_DIGITS` significant digits (the decimal module's default precision, so no
#: step rounds one silently), and 0 or of magnitude from 1E-99 to below 1E99 (the IBM
#: 1410's range, as for a deck's fields).
MAX_DIGITS = 28
MAX_EXPONENT = 98
#: A spec file is read up to this many bytes; a longer one (or /dev/zero) is refused.
MAX_SPEC_BYTES = 1 << 20


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


def _table(where: str, value) -> dict:
    if not isinstance(value, dict):
        raise PunchError(f"{where}: expected a table, got {value!r}")
    return value


def _unknown(where: str, table: dict, known) -> None:
    extra = [k for k in table if k not in known]
    if extra:
        raise PunchError(f"{where}: unknown key {extra[0]!r} (expected: {', '.join(known)})")


def spec_values(spec: dict, path: str = "<spec>"
                ) -> tuple[dict[str, Decimal], list[tuple[Decimal, Decimal, Decimal]], str | None]:
    """The listing's values, the range cards and the sequence prefix (None: blank).

    Checks the spec's shape only (every key present, numbers, no unknown keys).
    """
    sections: dict[str, list[str]] = {}
    for section, key, _ in SPEC_NAMES:
        keys = sections.setdefault(section, [])
        if key not in keys:
            keys.append(key)
    _unknown(path, spec, [*sections, "range", "deck", "scene", "sweep", "motor"])
    values: dict[str, Decimal] = {}
    for section, keys in sections.items():
        if section not in spec:
            raise PunchError(f"{path}: missing [{section}] ({', '.join(keys)})")
        table = _table(f"{path}: [{section}]", spec[section])
        _unknown(f"{path}: [{section}]", table, keys)
        for key in keys:
            if key not in table:
                raise PunchError(f"{path}: [{section}] has no {key}")
    for (section, key, sub), name in SPEC_NAMES.items():
        item = spec[section][key]
        where = f"{path}: [{section}] {key}"
        if sub is not None:
            item = _table(where, item)
            _unknown(where, item, ("distance", "angle"))
            if sub not in item:
                raise PunchError(f"{where} has no {sub} (write {key} = "
                                 "{ distance = ..., angle = ... })")
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


def _where(path: str, name: str) -> str:
    for (section, key, sub), n in SPEC_NAMES.items():
        if n == name:
            return f"{path}: [{section}] {key}{'.' + sub if sub else ''}"
    return f"{path}: {name}"


def punch_deck(spec: dict, path: str = "<spec>", any_units: bool = False) -> str:
    """The deck (text, one 80-column card a line) for a parsed spec.  A spec in SI is
    refused (a 1966 deck is in in-lb-sec), and so is a linkage that is not a
    crank-rocker, unless ``any_units``: the modern tools read the values through the deck,
    keep the spec's unit system beside it and judge the linkage's kind themselves."""
    values, ranges, prefix = spec_values(spec, path)
    scene = spec.get("scene")
    if not any_units and isinstance(scene, dict) and scene.get("units", "in-lb-sec") != \
            "in-lb-sec":
        raise PunchError(f"{path}: [scene] units = {scene['units']!r}: a 1966 deck is in the "
                         "report's in-lb-sec units; the modern tools read this spec directly")
    fields: dict[str, str] = {}
    for name in FIELD_NAMES:
        try:
            fields[name] = punch_field(values[name])
        except ValueError as err:
            raise PunchError(f"{_where(path, name)} = {values[name]}: {err}") from None
    range_fields = []
    for n, r in enumerate(ranges, 1):
        row = []
        for key, value in zip(RANGE_KEYS, r):
            try:
                row.append(punch_field(value))
            except ValueError as err:
                raise PunchError(f"{path}: [[range]] {n} {key} = {value}: {err}") from None
        range_fields.append(row)
    _check_design(values, ranges, path)
    rows = [[fields[n] for n in card] for card in CARDS] + range_fields
    lines = []
    for k, row in enumerate(rows, 1):
        text = "".join(row).ljust(72)
        if prefix is None:
            lines.append(text.rstrip())
            continue
        number = str(10 * k).rjust(8 - len(prefix), "0")
        if len(prefix) + len(number) > 8:
            raise PunchError(f"{path}: {len(rows)} cards: sequence numbers past "
                             f"{prefix}{'9' * (8 - len(prefix))} do not fit in columns 73-80")
        lines.append(text + prefix + number)
    return "\n".join(lines) + "\n"


def _check_design(values: dict[str, Decimal], ranges, path: str,
                  any_kind: bool = False) -> Mechanism:
    """The spec's mechanism; PunchError if it is not a crank-rocker (exit 3; with
    ``any_kind`` the modern tools judge the kind themselves) or a range would never end."""
    mechanism = Mechanism(**{n: float(values[n]) + 0.0 for n in FIELD_NAMES})
    failure = crank_rocker_failure(mechanism)
    if failure and not any_kind:
        raise PunchError(f"{path}: [lengths]: THIS IS NOT A CRANK ROCKER MECHANISM: {failure}",
                         EXIT_NOT_CRANK_ROCKER)
    for n, (start, step, stop) in enumerate(ranges, 1):
        if step <= 0 and start <= stop:
            raise PunchError(f"{path}: [[range]] {n}: step = {step} with start = {start} <= "
                             f"stop = {stop}: the 1966 loop would never end")
    return mechanism


def spec_deck(spec: dict, path: str = "<spec>") -> Deck:
    """The deck a parsed spec describes, for the modern tools (``table``, ``check``,
    ``plot``, ``sweep``, ``balance``): its values exactly as written (any of
    :func:`spec_number`'s numbers, no F8.4 field to fit: only ``punch`` makes cards),
    the range cards numbered 7, 8, ... as a punched deck's would be.  Checked as
    :func:`punch_deck` checks (ranges that end), but of any kind: the tools take every
    four-bar and say which it is (:func:`sielaff.tools.common.load_scene`)."""
    values, ranges, _ = spec_values(spec, path)
    mechanism = _check_design(values, ranges, path, any_kind=True)
    return Deck(mechanism, [Range(*(float(x) + 0.0 for x in r)) for r in ranges],
                list(range(len(CARDS) + 1, len(CARDS) + 1 + len(ranges))), path, [],
                dict(values), [tuple(r) for r in ranges])


def punch_file(path: str | os.PathLike[str]) -> str:
    """The deck for the spec file at ``path``."""
    return punch_deck(read_spec(path), os.fspath(path))


def read_spec(path: str | os.PathLike[str]) -> dict:
    """The parsed TOML of the spec file at ``path`` (PunchError naming the file if not)."""
    name = os.fspath(path)
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_SPEC_BYTES + 1)  # /dev/zero, a huge file: never read whole
    except OSError as err:
        raise PunchError(f"{name}: cannot read the spec ({err.strerror or err})") from None
    if len(data) > MAX_SPEC_BYTES:
        raise PunchError(f"{name}: longer than {MAX_SPEC_BYTES:,} bytes: not a spec (a spec "
                         "is a page of TOML)")
    try:
        spec = tomllib.loads(data.decode("utf-8"), parse_float=Decimal)
    except UnicodeDecodeError as err:
        raise PunchError(f"{name}: not a text file (byte {err.start})") from None
    except tomllib.TOMLDecodeError as err:
        raise PunchError(f"{name}: not valid TOML ({err})") from None
    except RecursionError:
        raise PunchError(f"{name}: not a spec (tables or arrays nested too deep)") from None
    except ValueError as err:  # an integer past Python's 4300-digit conversion limit
        raise PunchError(f"{name}: not valid TOML ({err})") from None
    return spec


LINKS_BY_NAME = {"crank": 2, "coupler": 3, "rocker": 4, 2: 2, 3: 3, 4: 4}


def scene_of(spec: dict, path: str = "<spec>") -> tuple[str, Scene]:
    """The spec's unit system and its ``[scene]`` as a :class:`~sielaff.Scene` (see
    docs/effects.md), read here and nowhere else::

        [scene]
        units = "in-lb-sec"           # or "SI" (the whole spec is then in SI)
        branch = "open"               # or "crossed"
        gravity = "down"              # or [gx, gy] in length/sec^2; absent: off
        crank_acceleration = -40.0    # TH2DD, rad/sec^2
        tex = 0.0                     # torque on the rocker, CCW +
        [[scene.load]]
        link = "coupler"              # crank, coupler or rocker
        distance = 8.0                # from the link's base pin (O2, A, O4)
        angle = 10.0                  # degrees CCW from the link's line
        force = [80.0, 0.0]           # frame axes
        torque = 0.0                  # CCW +

    Every value is checked by the Scene itself (finite, within its bound), and a bad
    one is one line naming the spec's key.
    """
    from sielaff.engine.loads import Load
    from sielaff.engine.scene import Scene
    from sielaff.mechanism import STANDARD_GRAVITY

    scene = _table(f"{path}: [scene]", spec.get("scene", {}))
    _unknown(f"{path}: [scene]", scene, ("units", "branch", "gravity", "crank_acceleration",
                                         "tex", "load"))
    units = scene.get("units", "in-lb-sec")
    if units not in STANDARD_GRAVITY:
        raise PunchError(f"{path}: [scene] units = {units!r}: {' or '.join(STANDARD_GRAVITY)}")
    fields: dict = {}
    branch = scene.get("branch", "open")
    if branch not in ("open", "crossed"):
        raise PunchError(f"{path}: [scene] branch = {branch!r}: \"open\" or \"crossed\"")
    fields["branch"] = branch
    gravity = scene.get("gravity")
    if gravity == "down":
        fields["gravity"] = "down"
    elif gravity is not None:
        if not (isinstance(gravity, list) and len(gravity) == 2):
            raise PunchError(f"{path}: [scene] gravity = {gravity!r}: \"down\" or [gx, gy]")
        fields["gravity"] = tuple(_float(f"{path}: [scene] gravity", g) for g in gravity)
    for key, name in (("crank_acceleration", "th2dd"), ("tex", "tex")):
        if key in scene:
            fields[name] = _float(f"{path}: [scene] {key}", scene[key])
    loads = scene.get("load", [])
    if not isinstance(loads, list):
        raise PunchError(f"{path}: write each load as [[scene.load]]")
    fields["loads"] = []
    for n, item in enumerate(loads, 1):
        where = f"{path}: [[scene.load]] {n}"
        item = _table(where, item)
        _unknown(where, item, ("link", "distance", "angle", "force", "torque"))
        link = LINKS_BY_NAME.get(item.get("link"))
        if link is None:
            raise PunchError(f"{where} link = {item.get('link')!r}: crank, coupler or rocker")
        force = item.get("force", [0.0, 0.0])
        if not (isinstance(force, list) and len(force) == 2):
            raise PunchError(f"{where} force = {force!r}: [fx, fy]")
        fx, fy = (_float(f"{where} force", f) for f in force)
        values = (_float(f"{where} distance", item.get("distance", 0)),
                  _float(f"{where} angle", item.get("angle", 0)), fx, fy,
                  _float(f"{where} torque", item.get("torque", 0)))
        try:
            fields["loads"].append(Load(link, *values))
        except ValueError as exc:
            raise PunchError(f"{where}: {exc}") from None
    try:
        return units, Scene(**fields)
    except ValueError as exc:
        raise PunchError(f"{path}: [scene] {exc}") from None


def _float(where: str, value) -> float:
    """A spec's number as a float; a NaN, an infinity or a magnitude past the scene's
    bound is one line naming ``where``."""
    from sielaff.engine.values import LIMIT

    x = float(_number(where, value))
    if not abs(x) <= LIMIT:
        raise PunchError(f"{where} = {value!r}: not a finite value within {LIMIT:g}")
    return x


#: The [sweep] table's own keys (the rest are in [sweep.vary]).
SWEEP_KEYS = ("angles", "cf", "pareto", "vary")
#: Designs a sweep may ask for (each is one block's share of memory only while it runs).
MAX_DESIGNS = 100_000_000


def sweep_of(spec: dict, path: str = "<spec>") -> dict:
    """The spec's ``[sweep]``: ``{"axes": {name: values}, "angles", "cf", "pareto"}``::

        [sweep]
        angles = 360                  # crank angles per revolution (default 360)
        cf = 0.05                     # coefficient of speed fluctuation (flywheel)
        pareto = ["TORQ_PEAK", "SHAK_PEAK"]   # the two figures plotted (both minimised)
        [sweep.vary]                  # listing names (R4, W3, TH2D, ...), TEX, BALANCE,
                                      # CW_R2 and CW_R4 (counterweight radii)
        R4 = { from = 10.0, to = 14.0, n = 41 }   # evenly spaced, both ends
        W3 = [4.0, 8.0, 12.0]                     # or the values themselves
        BALANCE = [0, 1]                          # without and with counterweights
    """
    import numpy as np

    from sielaff.design.figures import FIGURES
    from sielaff.design.sweep import SWEEPABLE

    table = _table(f"{path}: [sweep]", spec.get("sweep", {}))
    if not table:
        raise PunchError(f"{path}: no [sweep] table (decks/sweep.toml has one; docs/design.md)")
    _unknown(f"{path}: [sweep]", table, SWEEP_KEYS)
    angles = table.get("angles", 360)
    if not (isinstance(angles, int) and not isinstance(angles, bool) and 8 <= angles
            <= 100_000 and angles % 2 == 0):
        raise PunchError(f"{path}: [sweep] angles = {angles!r}: an even whole number "
                         "from 8 to 100000")
    cf = float(_number(f"{path}: [sweep] cf", table.get("cf", Decimal("0.05"))))
    if not 0.0 < cf < 2.0:
        raise PunchError(f"{path}: [sweep] cf = {cf:g}: between 0 and 2 (0.05 is usual)")
    pareto = table.get("pareto", ["TORQ_PEAK", "SHAK_PEAK"])
    if not (isinstance(pareto, list) and len(pareto) == 2
            and all(p in FIGURES and p != "KIND" for p in pareto)):
        raise PunchError(f"{path}: [sweep] pareto = {pareto!r}: two of "
                         f"{' '.join(f for f in FIGURES if f != 'KIND')}")
    vary = _table(f"{path}: [sweep.vary]", table.get("vary", {}))
    if not vary:
        raise PunchError(f"{path}: [sweep.vary] is empty: name at least one field to vary")
    # First the shape of every axis and the grid's size, from the lengths alone: nothing
    # is built before the size is known to be within bounds.
    lengths = {}
    for name, item in vary.items():
        where = f"{path}: [sweep.vary] {name}"
        if name not in SWEEPABLE:
            raise PunchError(f"{where}: not a field a sweep can vary "
                             f"({' '.join(SWEEPABLE)})")
        if isinstance(item, list):
            if not item:
                raise PunchError(f"{where} = []: give at least one value")
            lengths[name] = len(item)
            continue
        item = _table(where, item)
        _unknown(where, item, ("from", "to", "n"))
        if not {"from", "to", "n"} <= set(item):
            raise PunchError(f"{where}: write {{ from = ..., to = ..., n = ... }} or a "
                             "list of values")
        n = item["n"]
        if not (isinstance(n, int) and not isinstance(n, bool) and n >= 1):
            raise PunchError(f"{where} n = {n!r}: a whole number, 1 or more")
        if n > MAX_DESIGNS:
            raise PunchError(f"{where} n = {n}: more than {MAX_DESIGNS:,} values")
        lengths[name] = n
    size = 1
    for n in lengths.values():
        size *= n
        if size > MAX_DESIGNS:  # stops at once, however many axes follow
            shape = " x ".join(str(k) for k in lengths.values())
            raise PunchError(f"{path}: [sweep.vary] makes {shape} designs, more than "
                             f"{MAX_DESIGNS:,}")
    axes = {}
    for name, item in vary.items():
        where = f"{path}: [sweep.vary] {name}"
        if isinstance(item, list):
            values = np.array([float(_number(where, v)) for v in item])
        else:
            lo = float(_number(where + " from", item["from"]))
            hi = float(_number(where + " to", item["to"]))
            values = np.linspace(lo, hi, item["n"])
        _check_axis(where, name, values)
        axes[name] = values
    return {"axes": axes, "angles": angles, "cf": cf, "pareto": pareto}


def _check_axis(where: str, name: str, values) -> None:
    """A swept field's values (each already a bounded, finite spec number) that no design
    can have, as one line naming the axis and the first bad value."""
    import numpy as np

    from sielaff.mechanism import LENGTHS, NONNEGATIVE

    rules = [(name in LENGTHS, values > 0.0, "a link length must be > 0"),
             (name in NONNEGATIVE, values >= 0.0,
              "weights and moments of inertia cannot be negative"),
             (name == "BALANCE", np.isin(values, (0.0, 1.0)), "0 (as designed) or 1 (balanced)"),
             (name in ("CW_R2", "CW_R4"), values > 0.0, "a counterweight's radius must be > 0")]
    for applies, ok, why in rules:
        if applies and not np.all(ok):
            raise PunchError(f"{where} = {float(values[np.argmin(ok)]):g}: {why}")


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
