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

The spec's parts are read in modules of their own, and every name is importable from
here: the fields, the range cards and a spec's text in :mod:`sielaff.tools.spec_fields`,
``[scene]`` in :mod:`sielaff.tools.spec_scene`, ``[sweep]`` in
:mod:`sielaff.tools.spec_sweep`; this module reads the file, punches the deck and makes
the modern tools' deck (:func:`spec_deck`).  ``[synthesis]``, ``[tolerance]`` and
``[motor]`` are read by their commands (synth, tolerance, simulate).
"""

from __future__ import annotations

import os
import tomllib
from dataclasses import dataclass
from decimal import Decimal
from typing import Any

from sielaff.emulator.cards import Deck, Range, read_field_decimal
from sielaff.mechanism import FIELD_NAMES, STANDARD_GRAVITY, Mechanism, crank_rocker_failure
from sielaff.tools.errors import EXIT_NOT_CRANK_ROCKER
from sielaff.tools.spec_fields import (
    CARDS,
    FOUR_BAR,
    RANGE_KEYS,
    PunchError,
    _where,
    kind_names,
    linkage_kind,
    spec_dict,
    spec_number,
    spec_text,
    spec_values,
    spec_whole,
)
from sielaff.tools.spec_scene import scene_of
from sielaff.tools.spec_sweep import sweep_of

__all__ = ["PunchError", "Spec", "punch_deck", "punch_field", "punch_file", "read_spec", "scene_of",
           "spec_deck", "spec_dict", "spec_number", "spec_text", "spec_values", "spec_whole",
           "sweep_of"]

@dataclass(frozen=True)
class Spec:
    """A spec as ``sielaff.load_spec`` gives it: the file, its mechanism (in its unit
    system), its scene, its range cards ((THZERO, DELTA, THMAX) [deg] each) and its
    ``[motor]`` as simulate reads it (None without one)."""

    path: str
    mechanism: Any
    scene: Any
    ranges: tuple[tuple[float, float, float], ...]
    motor: dict | None


WIDTH = 8
#: A spec file is read up to this many bytes; a longer one (or /dev/zero) is refused.
MAX_SPEC_BYTES = 1 << 20

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


def punch_deck(spec: dict, path: str = "<spec>", any_units: bool = False) -> str:
    """The deck (text, one 80-column card a line) for a parsed spec.  A spec in SI is
    refused (a 1966 deck is in in-lb-sec), and so is a linkage that is not a
    crank-rocker, unless ``any_units``: the modern tools read the values through the deck,
    keep the spec's unit system beside it and judge the linkage's kind themselves."""
    kind = linkage_kind(spec, path)
    if kind != FOUR_BAR:
        from sielaff.tools.spec_fields import KIND_COMMANDS

        raise PunchError(f'{path}: [linkage] kind = "{kind}": a 1966 deck is a four-bar\'s; '
                         f"the modern tools (sielaff {', '.join(KIND_COMMANDS)}) read this spec "
                         "directly")
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
    _check_ranges(ranges, path)
    return mechanism


def _check_ranges(ranges, path: str) -> None:
    """PunchError naming the first range card the 1966 loop would never leave."""
    for n, (start, step, stop) in enumerate(ranges, 1):
        if step <= 0 and start <= stop:
            raise PunchError(f"{path}: [[range]] {n}: step = {step} with start = {start} <= "
                             f"stop = {stop}: the 1966 loop would never end")


def spec_deck(spec: dict, path: str = "<spec>") -> Deck:
    """The deck a parsed spec describes, for the modern tools (``table``, ``check``,
    ``plot``, ``sweep``, ``balance``): its values exactly as written (any of
    :func:`spec_number`'s numbers, no F8.4 field to fit: only ``punch`` makes cards),
    the range cards numbered 7, 8, ... as a punched deck's would be.  Checked as
    :func:`punch_deck` checks (ranges that end), but of any kind: the tools take every
    four-bar and say which it is (:func:`sielaff.tools.common.load_scene`)."""
    kind = linkage_kind(spec, path)
    if kind != FOUR_BAR:
        return _other_deck(spec, path, kind)
    values, ranges, _ = spec_values(spec, path)
    mechanism = _check_design(values, ranges, path, any_kind=True)
    return Deck(mechanism, [Range(*(float(x) + 0.0 for x in r)) for r in ranges],
                list(range(len(CARDS) + 1, len(CARDS) + 1 + len(ranges))), path, [],
                dict(values), [tuple(r) for r in ranges])


def _other_deck(spec: dict, path: str, kind: str) -> Deck:
    """A spec of another linkage kind as a deck for the modern tools: its mechanism (a
    :class:`~sielaff.SliderCrank`), checked by its model in one line naming the spec's
    key, and its range cards (which must end)."""
    from sielaff.engine.analysis import model_named

    names = kind_names()[kind]
    values, ranges, _ = spec_values(spec, path, names)
    model = model_named(kind)
    assert model.mechanism is not None and model.validate is not None
    scene = spec.get("scene")
    units = scene.get("units") if isinstance(scene, dict) else None  # its messages' units
    mechanism = model.mechanism(**{n: float(v) + 0.0 for n, v in values.items()},
                                units=units if units in STANDARD_GRAVITY else "in-lb-sec")
    try:
        model.validate(mechanism)
    except ValueError as exc:
        field = str(exc).split(" ", 1)[0].rsplit(".", 1)[-1]
        where = _where(path, field, names) if field in values else path
        raise PunchError(f"{where}: {exc}") from None
    _check_ranges(ranges, path)
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
    return parse_spec(data, name)


def parse_spec(data: bytes, name: str) -> dict:
    """The parsed TOML of a spec's bytes (at most :data:`MAX_SPEC_BYTES`, one more to
    refuse a longer one); PunchError naming ``name`` if it is not a spec."""
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
