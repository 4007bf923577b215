"""``sielaff table``: the modern engine's results for a deck, one row per position.

For every range card (THZERO, DELTA, THMAX) of the deck the crank angles are
THZERO, THZERO + DELTA, ... up to and including THMAX: there are
``floor((THMAX - THZERO) / DELTA) + 1`` of them, counted exactly from the
decimals punched on the card, so the 1966 loop's extra sheet past THMAX
(docs/quirks.md, quirks 1 and 2) has no row, and THZERO = THMAX gives one
row.  Each angle is the exact decimal THZERO + k DELTA rounded once to the
nearest double (``0.3``, not ``0.1 + 0.2``).  A card with THZERO > THMAX has
no positions: it gives no rows and a warning.  A card the 1966 loop would
never leave (DELTA <= 0 with THZERO <= THMAX) is an error (exit 2) naming the
card, as for ``sielaff run``; so is a mechanism that is not a crank-rocker
(exit 3, one line naming card 3).  Nothing is written then.

Columns
    ``CARD`` (the deck line of the range card the row comes from, as in the
    error messages), then the engine's names (:data:`sielaff.engine.RESULTS`,
    in that order, ATH2 first)::

        CARD ATH2 ATH3 ATH4 GAMMA TH3D TH4D TH3DD TH4DD TEX
        VG2 DVG2 VG2X VG2Y VA DVA VAX VAY VG3 DVG3 VG3X VG3Y VB DVB VBX VBY
        VG4 DVG4 VG4X VG4Y AG2 DAG2 AG2X AG2Y AA DAA AAX AAY AG3 DAG3 AG3X AG3Y
        AB DAB ABX ABY AG4 DAG4 AG4X AG4Y FA32 DFA32 FA32X FA32Y
        FB34 DFB34 FB34X FB34Y FOA DFOA FOAX FOAY FOB DFOB FOBX FOBY
        SHAK DSHAK SHAKX SHAKY TORQ SHAKM

    With ``--only kinematics``: ``CARD`` and :data:`sielaff.engine.KINEMATIC_OUTPUTS`
    (the same order, without TEX and everything from FA32 on); the force
    steps are then never run.  Units and meanings are the listing's (see
    :mod:`sielaff.engine`): angles and directions in degrees, rates in
    rad/sec and rad/sec^2, lengths in inches, forces in lb, torques in in-lb.
    TEX is 0, as in the 1966 program.

    After them come the outputs of each effect the spec's scene calls for
    (docs/effects.md; each effect declares which): ``TORQ_GRAVITY`` with gravity,
    ``TORQ_LOADS`` with external loads, ``TORQ_TEX`` with a torque TEX on link 4,
    ``TH2DD`` with a crank acceleration, ``TORQ_ELEMENTS`` and each spring's or
    damper's ``SPRINGk_L``, ``_LD``, ``_F`` with springs and dampers,
    ``TORQ_FRICTION``, each pin's friction loss ``PLOSS_O2`` ... ``PLOSS_O4`` and
    ``FRICTION_STATUS`` with pin friction.  ``--torque-parts`` puts first every part
    of TORQ (TORQ_INERTIA and each effect's share, whatever the scene: a part the
    scene lacks is 0); they sum to TORQ to roundoff.  Every column carries its unit
    in the spec's system.

Formats
    ``csv`` (default): a header row of the column names with their units,
    ``NAME[unit]`` (``TORQ[in-lb]``, ``ATH3[deg]``; ``CARD`` has none), then one
    line per position (``--header names``: the bare names), fields separated
    by commas, lines ending ``\\n``.  Numbers are written with Python's
    ``repr`` (the shortest decimal that reads back as the same double: full
    precision); CARD is an integer.  A value that is
    not finite (only possible for a mechanism at or past the limits of
    double precision) is written ``nan``, ``inf`` or ``-inf``.

    ``json``: one object ``{"columns": [...], "units": [...], "descriptions":
    [...], "rows": [[...], ...]}``, units and descriptions (:mod:`sielaff.quantities`)
    aligned with ``columns``, each row a list in the order of ``columns`` (one row
    per line).  This form
    keeps the column order explicit and costs the names once, not once per
    row.  Numbers as in the CSV; a non-finite value is ``null`` (JSON has no
    NaN).

The output is written atomically (:func:`sielaff.tools.output.atomic_output`) and
streamed: the engine runs on blocks of :data:`BLOCK` positions (the positions of
many small range cards share one block) and the text is produced :data:`CHUNK`
rows at a time, so memory stays bounded however
many positions a deck asks for.  Formatting dominates the time (a million
full rows take about 40 s, almost all of it in ``repr``; the engine itself
needs about a second).
"""

from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Iterator
from typing import TextIO

import numpy as np

from sielaff import engine
from sielaff.emulator.cards import Deck
from sielaff.engine.scene import Scene  # noqa: TC001
from sielaff.tools.kinds import angles, count, exact_range

__all__ = ["BLOCK", "CHUNK", "FORMATS", "columns", "count", "angles",
           "header", "torque_parts", "write_table", "cmd_table"]

#: Positions per engine call.
BLOCK = 100_000
#: Rows formatted at a time (bounds the Python objects alive at once).
CHUNK = 10_000
FORMATS = ("csv", "json")


def torque_parts(mechanism=None) -> tuple[str, ...]:
    """The parts TORQ is the sum of (the mechanism's model's: TORQ_INERTIA, then each
    effect's share, docs/effects.md), in this order."""
    return (engine.FOURBAR if mechanism is None else engine.model_for(mechanism)).torque_parts


def columns(kinematics_only: bool = False, scene: Scene | None = None,
            torque_parts: bool = False, mechanism=None) -> tuple[str, ...]:
    """The table's column names, in order: CARD, the engine's results, then each effect
    the ``scene`` calls for shows its outputs (its declaration's ``columns``: TORQ_GRAVITY
    with gravity, TORQ_FRICTION and each pin's PLOSS with friction, ...); with
    ``torque_parts`` every part of TORQ (:func:`torque_parts`, a part the scene lacks
    is 0) comes first."""
    model = engine.FOURBAR if mechanism is None else engine.model_for(mechanism)
    if kinematics_only:
        return ("CARD",) + model.kinematics
    sc = scene or engine.scene_of(model)()
    extra: list[str] = list(model.torque_parts) if torque_parts else []
    for effect in model.effects_on(sc):
        extra += [n for n in effect.shown(sc) if n not in model.results]
    return ("CARD",) + model.results + tuple(dict.fromkeys(extra))


# --------------------------------------------------------------------------
# Writers
# --------------------------------------------------------------------------


def _lines(card: int, block: np.ndarray, json: bool) -> Iterator[str]:
    """Text of a chunk of rows (``block``: rows x value columns)."""
    fr = float.__repr__
    finite = bool(np.isfinite(block).all())
    rows = block.tolist()
    if json:
        head, tail = f"[{card},", "]"
        if finite:
            yield ",\n".join([head + ",".join(map(fr, row)) + tail for row in rows])
        else:
            def num(v: float) -> str:
                return fr(v) if v - v == 0.0 else "null"

            yield ",\n".join([head + ",".join(map(num, row)) + tail for row in rows])
    else:
        head = f"{card},"
        yield "".join([head + ",".join(map(fr, row)) + "\n" for row in rows])


def header(names: tuple[str, ...], units: bool = True, system: str = "in-lb-sec") -> str:
    """The CSV header row: ``NAME[unit]`` for each column (``CARD`` has none), or the bare
    names with ``units=False``.  pandas.read_csv reads either as plain column names."""
    from sielaff.quantities import unit

    if not units:
        return ",".join(names)
    return ",".join(n if n == "CARD" else f"{n}[{unit(n, system)}]" for n in names)


def write_table(deck: Deck, out: TextIO, fmt: str = "csv", kinematics_only: bool = False,
                warn=None, units: bool = True, scene: Scene | None = None,
                assembled_only: bool = False, torque_parts: bool = False) -> int:
    """Write the table of ``deck`` on ``out``; returns the number of rows.

    With ``assembled_only`` (a linkage whose crank cannot turn fully) a position where
    the loop does not close, or a toggle where the rates are infinite, is left out
    (counted in one warning per card): rows only where the linkage assembles.

    ``warn(text)`` receives one line per range card with no positions, and per
    card with values that are not finite.  The caller has checked the deck
    (:func:`sielaff.tools.common.load_for_engine`: the crank-rocker test, the ranges).
    """
    if fmt not in FORMATS:
        raise ValueError(f"unknown table format {fmt!r} ({', '.join(FORMATS)})")
    warn = warn or (lambda text: None)
    scene = scene or engine.scene_of(engine.model_for(deck.mechanism))()
    json = fmt == "json"
    system = getattr(deck.mechanism, "units", "in-lb-sec")
    names = columns(kinematics_only, scene, torque_parts, deck.mechanism)
    wanted = names[1:]
    if json:
        import json as json_module

        from sielaff.quantities import describe, unit

        def strings(items) -> str:
            return json_module.dumps(list(items))

        out.write('{"columns": ' + strings(names) + ',\n"units": '
                  + strings(unit(n, system) for n in names) + ',\n"descriptions": '
                  + strings(describe(n) for n in names) + ',\n"rows": [\n')
    else:
        out.write(header(names, units, system) + "\n")
    rows = 0
    buffers = np.empty((len(wanted), BLOCK))
    bad: dict[int, list[int]] = {}  # card -> [positions not finite, positions]
    skipped: dict[int, list[int]] = {}  # card -> [positions left out, positions]
    batch: list[tuple[int, int, np.ndarray]] = []  # (card, positions, angles): one call
    batched = 0

    def flush() -> None:
        nonlocal rows, batched, buffers
        if not batch:
            return
        ath2 = np.concatenate([a for _, _, a in batch])
        # the engine writes into the same buffers block after block: no fresh pages
        if buffers.shape[1] < ath2.size:  # a batch may pass BLOCK by one card's share
            buffers = np.empty((len(wanted), ath2.size))
        view = buffers[:, :ath2.size]
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", engine.AssemblyWarning)  # counted below
            engine.analyze(deck.mechanism, ath2, scene=scene,
                           out={name: view[j] for j, name in enumerate(wanted)})
        block = view.T
        start = 0
        for card, n, a in batch:
            part = block[start:start + a.size]
            start += a.size
            ok = np.isfinite(part).all(axis=1)
            nonfinite = int(np.count_nonzero(~ok))
            if nonfinite and assembled_only:
                skipped.setdefault(card, [0, n])[0] += nonfinite
                part = part[ok]
                a = a[ok]
            elif nonfinite:
                bad.setdefault(card, [0, n])[0] += nonfinite
            for lo in range(0, a.size, CHUNK):
                for text in _lines(card, part[lo:lo + CHUNK], json):
                    if json and rows:
                        out.write(",\n")
                    out.write(text)
                rows += min(CHUNK, a.size - lo)
        batch.clear()
        batched = 0

    for i, card in enumerate(deck.range_cards):
        thzero, delta, thmax = exact_range(deck, i)
        n = count(thzero, delta, thmax)
        if n == 0:
            warn(f"{deck.path}: card {card}: THZERO = {float(thzero):g} > THMAX = "
                 f"{float(thmax):g}: no positions (the 1966 program prints one sheet, "
                 "at THZERO)")
            continue
        for start in range(0, n, BLOCK):
            a = angles(thzero, delta, start, min(start + BLOCK, n))
            batch.append((card, n, a))
            batched += a.size
            if batched >= BLOCK:
                flush()
    flush()
    for card, (left, n) in skipped.items():
        warn(f"{deck.path}: card {card}: {left} of {n} positions left out, where the "
             "linkage does not assemble (or is at a toggle)")
    for card, (nonfinite, n) in bad.items():
        warn(f"{deck.path}: card {card}: {nonfinite} of {n} positions have values "
             f"that are not finite (written as {'null' if json else 'nan or inf'})")
    out.write("\n]}\n" if json and rows else "]}\n" if json else "")
    return rows


# --------------------------------------------------------------------------
# The command
# --------------------------------------------------------------------------


def cmd_table(args: argparse.Namespace) -> int:
    """``sielaff table DECK [--format csv|json] [--only kinematics] [-o FILE]``."""
    from sielaff.tools.common import load_scene, refuse_overwriting_inputs
    from sielaff.tools.kinds import other_kinds, turns_whole
    from sielaff.tools.output import atomic_output

    refuse_overwriting_inputs(args.output, [args.deck])
    parts = getattr(args, "torque_parts", False)
    if parts and args.only == "kinematics":
        from sielaff.tools.common import CommandError

        raise CommandError("sielaff: --torque-parts needs the force analysis that --only "
                           "kinematics leaves out")
    kinematics = args.only == "kinematics"
    deck, scene = load_scene(args.deck, lambda m: columns(kinematics, mechanism=m)[1:],
                             branch=getattr(args, "branch", None), any_kind=True,
                             kinds=other_kinds())

    def warn(text: str) -> None:
        print(f"sielaff: warning: {text}", file=sys.stderr)

    with atomic_output(args.output) as out:
        write_table(deck, out, args.format, args.only == "kinematics", warn,
                    units=getattr(args, "header", "units") == "units", scene=scene,
                    assembled_only=not turns_whole(deck.mechanism, scene.branch),
                    torque_parts=parts)
    return 0

