"""What the commands share about positions and linkage kinds: the crank angles of a range
card (exact, counted, rounded once), and a spec's linkage of another kind than the
four-bar (a slider-crank, ...) checked as every command checks it."""

from __future__ import annotations

import sys
from decimal import Decimal
from fractions import Fraction
from typing import Any

import numpy as np

from sielaff.emulator.cards import Deck
from sielaff.engine.scene import Scene  # noqa: TC001
from sielaff.tools.errors import EXIT_NOT_CRANK_ROCKER, CommandError

__all__ = ["angles", "count", "exact_range", "full_turn_failure", "other_kind", "other_kinds",
           "turns_whole"]


def other_kinds() -> tuple[str, ...]:
    """Every ``[linkage] kind`` besides the four-bar (the engine's models of a kind)."""
    from sielaff.tools.spec_fields import FOUR_BAR, kind_names

    return tuple(k for k in kind_names() if k != FOUR_BAR)


def exact_range(deck: Deck, i: int) -> tuple[Fraction, Fraction, Fraction]:
    """Range card i as exact fractions.

    The decimals punched on the card if the deck has them (``Deck.exact_ranges``);
    for a deck built in code, each float's shortest decimal (0.1 means 1/10).
    """
    exact = getattr(deck, "exact_ranges", None) or []
    if i < len(exact):
        values = exact[i]
    else:
        values = tuple(Decimal(repr(float(v))) for v in deck.ranges[i])
    return tuple(Fraction(v) for v in values)  # type: ignore[return-value]


def count(thzero: Fraction, delta: Fraction, thmax: Fraction) -> int:
    """Positions THZERO + k DELTA <= THMAX, k = 0, 1, ... (exact; DELTA > 0 unless empty)."""
    if thzero > thmax:
        return 0
    if delta <= 0:
        raise ValueError(f"DELTA = {float(delta):g} <= 0: the range never ends")
    return int((thmax - thzero) // delta) + 1


def angles(thzero: Fraction, delta: Fraction, start: int, stop: int) -> np.ndarray:
    """THZERO + k DELTA for k in [start, stop), each the double nearest the exact value."""
    k = np.arange(start, stop, dtype=np.int64)
    # Both on a common decimal grid 10^-d: integers, then one correctly rounded division.
    for d in range(0, 23):  # 10^d is an exact double up to 10^22
        scale = 10**d
        t0, dd = thzero * scale, delta * scale
        if t0.denominator == 1 and dd.denominator == 1:
            t0, dd = int(t0), int(dd)
            if abs(t0) + abs(dd) * max(stop - 1, 0) < 2**53:
                num = np.float64(t0) + np.float64(dd) * k.astype(np.float64)  # exact integers
                return num / np.float64(scale)
            break
    # Otherwise (no short decimal grid, or huge counts): THZERO + k DELTA in doubles.
    return float(thzero) + float(delta) * k.astype(np.float64)



def other_kind(deck: Deck, scene: Scene, outputs=None, any_kind: bool = False,
               note: bool = True) -> Deck:
    """A spec's linkage of another kind than the four-bar (a slider-crank; the command
    took its kind, :func:`read_spec_with`), checked as a four-bar is: its range cards (the
    endless loop and the ceiling on positions); one whose crank cannot turn fully on the
    scene's branch is refused (exit 3) unless ``any_kind``, where stderr says so (with
    ``note``) and the positions where it cannot close are left out; results past the IBM
    1410's range over a revolution are refused (exit 2), with an effect's own reason for a
    NaN (a spring of length zero, friction that self-locks)."""
    import warnings

    import numpy as np

    from sielaff.engine import AssemblyWarning, FrictionWarning, analyze
    from sielaff.quantities import unit
    from sielaff.tools.problems import nan_reason, range_problem

    problem = range_problem(deck)
    if problem is not None:
        raise problem
    try:
        failure = full_turn_failure(deck.mechanism, scene.branch)
    except CommandError as exc:
        raise CommandError(f"{deck.path}: {exc}") from None
    if failure and not any_kind:
        raise CommandError(f"{deck.path}: [lengths]: {failure}", EXIT_NOT_CRANK_ROCKER)
    if failure:
        if note:
            print(f"sielaff: {deck.path}: {failure}; positions where it cannot close are "
                  "left out", file=sys.stderr)
        warnings.filterwarnings("ignore", category=AssemblyWarning)
        return deck
    system = deck.mechanism.units
    with np.errstate(all="ignore"), warnings.catch_warnings():
        # friction with no solution is this check's one line below, not a warning besides
        warnings.simplefilter("ignore", AssemblyWarning)
        warnings.simplefilter("ignore", FrictionWarning)
        r = analyze(deck.mechanism, np.arange(0.0, 360.0, 1.0),
                    outputs or model_of(deck.mechanism).results, scene=scene)
    for name, v in r.items():
        bad = ~np.isfinite(v) | (np.abs(v) >= 1e99)
        if bad.any():
            i = int(np.argmax(bad))
            why = nan_reason(deck, scene, float(i)) if np.isnan(v[i]) else None
            if why:
                raise CommandError(f"{deck.path}: [scene] {why}")
            raise CommandError(f"{deck.path}: this linkage and its scene give {name} = "
                               f"{float(v[i]):.3g} {unit(name, system)} at THETA 2 = {i} deg, "
                               "past the IBM 1410's range (1E99) that every command keeps to")
    return deck


def model_of(mechanism: Any) -> Any:
    """The engine's model of ``mechanism`` (its outputs, topology and full-turn test)."""
    from sielaff.engine import model_for

    return model_for(mechanism)


def full_turn_failure(mechanism: Any, branch: Any = "open") -> str | None:
    """Why the crank of ``mechanism`` (another kind) cannot make a whole revolution on
    ``branch`` (one for every dyad, or one per dyad), or None; a branch on which some dyad
    closes nowhere is a CommandError (exit 2) naming it."""
    model = model_of(mechanism)
    failure = model.full_turn(mechanism) if model.full_turn else None
    if branch == "open" or getattr(model, "topology", None) is None:
        return failure
    from sielaff.engine.assembly import assembly_failure, never_assembles

    values = {k: float(v) for k, v in mechanism.as_dict().items()}
    words = (f"the {branch} branch" if isinstance(branch, str) else
             f"branches {', '.join(branch)}")
    never = never_assembles(model.topology, values, branch)
    if never:
        raise CommandError(f"on {words}: {never}")
    failure = assembly_failure(model.topology, values, branch)
    return failure and f"on {words}: {failure}"


def turns_whole(mechanism: Any, branch: Any = "open") -> bool:
    """Whether the commands work ``mechanism`` over whole revolutions: a crank-rocker, or
    another kind's linkage whose crank turns fully on ``branch`` (:func:`full_turn_failure`).
    Every other is worked only where it assembles."""
    from sielaff.mechanism import Mechanism, crank_rocker_failure

    if isinstance(mechanism, Mechanism):
        return crank_rocker_failure(mechanism) is None
    try:
        return full_turn_failure(mechanism, branch) is None
    except CommandError:  # closes nowhere on that branch
        return False
