"""``sielaff synth SPEC.toml [-o RANKED.csv] [--write-best DIR]``: synthesis, ranked.

The spec's ``[synthesis]`` table names the problem and the ranking; its ``[scene]`` is the
scene every candidate is analysed in (docs/synthesis.md, decks/synth.toml)::

    [synthesis]
    problem = "crank_rocker"          # crank_rocker, function, motion or path
    by = ["TORQ_PEAK", "SHAK_PEAK"]   # ranking figures, the first deciding
    pareto = ["TORQ_RMS", "SHAK_PEAK"]  # the Pareto front's two figures
    speed = 10.0                      # TH2D of every candidate, rad/sec
    angles = 360                      # crank angles per revolution
    cf = 0.05                         # coefficient of speed fluctuation (FLYWHEEL_I)
    best = 3                          # how many --write-best writes
    density = 0.2836                  # optional mass model (lb/in^3 or kg/m^3) ...
    area = 0.5                        # ... and cross-section (in^2 or m^2): uniform bars
    [synthesis.crank_rocker]          # the problem's parameters (the function's keywords)
    swing = 45.0
    time_ratio = 1.25
    rocker = 10.0
    members = 8                       # crank_rocker only: members per interval of k
    [synthesis.vary]                  # optional: alternatives of any parameter; every
    rocker = [8.0, 10.0]              # combination is one problem, its results candidates

``function`` takes ``f`` by name (:data:`FUNCTIONS`), ``x_range``, ``input_range``,
``output_range``, ``points``, ``frame``; ``motion`` ``poses``, ``moving``, ``fixed``,
``direction``; ``path`` ``points``, ``crank_angles``, ``starts``, ``seed``.  A problem
that has no solution is skipped and counted; none at all is an error.

Constraints and near-ties (:mod:`sielaff.synthesis.rank`)::

    tie = 1e-9                        # figures this close (relative) are tied
    [synthesis.constraints]           # bounds, in each figure's unit
    GAMMA_MIN = {min = 40.0}          # a least transmission angle, deg
    LONGEST = {max = 30.0}            # the longest link, in
    "R3/R2" = {max = 4.0}             # a link ratio

Output: one CSV row per candidate, best first: ``RANK`` (shared by candidates tied on
every ranking figure), ``CANDIDATE`` (its index in the order solved), ``PROBLEM`` (which
combination of [synthesis.vary]), the varied parameters' values and, for a crank-rocker,
its ``K`` and ``SIDE`` (:meth:`Synthesis.trace`), ``BRANCH``, ``PARETO`` (1 on the front),
``FEASIBLE`` (1: meets every constraint) and ``VIOLATES`` (the first it breaks), the 17
fields and the figures, each header naming its unit.
``--write-best DIR`` writes the ``best`` first ones as ``DIR/best-K.toml`` (a spec with
the input's [scene], the candidate's branch and a [[range]] of 0 to 350 deg by 10), and
``DIR/best-K.dat`` (a deck) where a deck can hold it; both carry each field rounded to
the most decimals an 8-column card field holds (every command reads a spec through its
deck), so a field keeps 5 to 7 significant digits.  A deck needs in-lb-sec, the open
branch, a 1966 scene (no gravity, loads or crank acceleration; TEX is the run's --tex)
and a crank-rocker.  All files are written whole or not at all.
"""

from __future__ import annotations

import itertools
import math
import os
import sys
from dataclasses import dataclass
from decimal import Decimal
from typing import Any

import numpy as np  # module level: the ulp-nudge harness reaches the functions f names

from sielaff.tools.spec_tables import MAX_PROBLEMS, PROBLEMS, problem_unit, synthesis_keys

#: The functions ``[synthesis.function] f`` may name.
FUNCTIONS = ("log10", "log", "exp", "sqrt", "square", "cube", "reciprocal", "sin", "cos",
             "tan")


def _plain(v: Any) -> Any:
    """TOML values (Decimals) as floats, lists recursively."""
    if isinstance(v, Decimal):
        return float(v)
    if isinstance(v, list):
        return [_plain(x) for x in v]
    return v


def _function(name: Any):
    table = {"log10": np.log10, "log": np.log, "exp": np.exp, "sqrt": np.sqrt,
             "square": np.square, "cube": lambda x: x ** 3, "reciprocal": np.reciprocal,
             "sin": np.sin, "cos": np.cos, "tan": np.tan}
    if name not in table:
        raise ValueError(f"f = {name!r}: one of {', '.join(FUNCTIONS)}")
    return table[name]


def read_synthesis(spec: dict, path: str, units: str = "in-lb-sec") -> dict:
    """The ``[synthesis]`` table checked: problem, params (list of dicts), ranking."""
    from sielaff.design.sweep import MAX_ANGLES
    from sielaff.synthesis.rank import RANKABLE
    from sielaff.tools.spec import PunchError, spec_whole
    from sielaff.tools.spec_fields import _name

    table = spec.get("synthesis")
    if not isinstance(table, dict) or not table:
        raise PunchError(f"{path}: no [synthesis] table (decks/synth.toml has one)")
    where = f"{path}: [synthesis]"
    keys = [k.name for k in synthesis_keys()]
    extra = [k for k in table if k not in keys]
    if extra:
        raise PunchError(f"{where}: unknown key {extra[0]!r} (expected: {', '.join(keys)})")
    problem = _name(f"{where} problem", table.get("problem"), tuple(PROBLEMS),
                    f"one of {', '.join(PROBLEMS)}")
    params = table.get(problem, {})
    if not isinstance(params, dict):
        raise PunchError(f"{where}.{problem}: expected a table")
    bad = [k for k in params if k not in PROBLEMS[problem]]
    if bad:
        raise PunchError(f"{where}.{problem}: unknown key {bad[0]!r} (expected: "
                         f"{', '.join(PROBLEMS[problem])})")
    vary = table.get("vary", {})
    if not isinstance(vary, dict):
        raise PunchError(f"{where}.vary: expected a table")
    for k, v in vary.items():
        if k not in PROBLEMS[problem]:
            raise PunchError(f"{where}.vary: {k!r} is not a parameter of {problem} "
                             f"({', '.join(PROBLEMS[problem])})")
        if not (isinstance(v, list) and v):
            raise PunchError(f"{where}.vary {k}: a list of alternatives")
    size = math.prod(len(v) for v in vary.values())
    if size > MAX_PROBLEMS:
        raise PunchError(f"{where}.vary: {size} problems, more than {MAX_PROBLEMS}")
    base = {k: _plain(v) for k, v in params.items()}
    combos = [dict(zip(vary, c)) for c in itertools.product(*vary.values())] or [{}]
    problems = [base | {k: _plain(v) for k, v in c.items()} for c in combos]
    by = table.get("by", ["TORQ_PEAK"])
    if not (isinstance(by, list) and by and all(b in RANKABLE for b in by)):
        raise PunchError(f"{where} by = {by!r}: a list of {' '.join(RANKABLE)}")
    pareto = table.get("pareto")
    if pareto is not None and not (isinstance(pareto, list) and len(pareto) == 2
                                   and all(p in RANKABLE for p in pareto)):
        raise PunchError(f"{where} pareto = {pareto!r}: two of {' '.join(RANKABLE)}")
    out: dict[str, Any] = {"problem": problem, "problems": problems, "by": by,
                           "pareto": pareto, "vary": list(vary)}
    for key, default, lo, hi in (("speed", 1.0, -1e6, 1e6), ("cf", 0.05, 0.0, 2.0)):
        v = table.get(key, default)
        if isinstance(v, bool) or not isinstance(v, int | float | Decimal) \
                or not lo < float(v) < hi or float(v) == 0.0:
            raise PunchError(f"{where} {key} = {v!r}: a non-zero number between {lo:g} "
                             f"and {hi:g}")
        out[key] = float(v)
    for key, default, lo, hi in (("angles", 360, 8, MAX_ANGLES), ("best", 1, 0, 1000)):
        out[key] = spec_whole(where, key, table.get(key, default), lo, hi, key == "angles")
    model = {}
    for key in ("density", "area"):
        if key in table:
            v = table[key]
            if isinstance(v, bool) or not isinstance(v, int | Decimal) or not float(v) > 0 \
                    or not math.isfinite(float(v)):
                raise PunchError(f"{where} {key} = {v!r}: a positive number")
            model[key] = float(v)
    out["mass_model"] = model or None
    tie = table.get("tie", 1e-9)
    if isinstance(tie, bool) or not isinstance(tie, int | float | Decimal) \
            or not 0.0 <= float(tie) < 0.1:
        raise PunchError(f"{where} tie = {tie!r}: a fraction from 0 to below 0.1")
    out["tie"] = float(tie)
    out["constraints"] = _constraints(table.get("constraints", {}), where, units)
    return out


def _constraints(table: Any, where: str, units: str) -> dict:
    """``[synthesis.constraints]``: ``NAME = {min = x, max = y}`` -> {NAME: (x, y)}."""
    from sielaff.synthesis.rank import constraint_unit
    from sielaff.tools.spec import PunchError

    if not isinstance(table, dict):
        raise PunchError(f"{where}.constraints: expected a table")
    out = {}
    for name, bounds in table.items():
        at = f"{where}.constraints {name}"
        try:
            constraint_unit(name, units)
        except ValueError as exc:
            raise PunchError(f"{at}: {exc}") from None
        if not isinstance(bounds, dict) or not bounds or set(bounds) - {"min", "max"}:
            raise PunchError(f"{at} = {bounds!r}: an inline table {{min = x, max = y}} "
                             "(either or both)")
        got = []
        for side in ("min", "max"):
            v = bounds.get(side)
            if v is not None and (isinstance(v, bool) or not isinstance(v, int | Decimal)
                                  or not math.isfinite(float(v))):
                raise PunchError(f"{at} {side} = {v!r}: a finite number")
            got.append(None if v is None else float(v))
        if got[0] is not None and got[1] is not None and got[0] > got[1]:
            raise PunchError(f"{at}: min {got[0]:g} is above max {got[1]:g}")
        out[name] = (got[0], got[1])
    return out


def solve(problem: str, params: dict, speed: float, units: str, where: str) -> list:
    """The candidates one problem gives (ValueError: it has none)."""
    from sielaff import synthesis

    p = dict(params)
    try:
        if problem == "crank_rocker":
            members = p.pop("members", 8)
            if not (isinstance(members, int) and 1 <= members <= 100):
                raise ValueError(f"members = {members!r}: a whole number from 1 to 100")
            fam = synthesis.crank_rocker(th2d=speed, units=units, **p)
            return fam.members(members)
        if problem == "function":
            p["f"] = _function(p.get("f"))
            return [synthesis.function(th2d=speed, units=units, **p)]
        if problem == "motion":
            res = synthesis.motion(th2d=abs(speed), units=units, **p)
        else:
            res = synthesis.path(th2d=abs(speed), units=units, **p)
        if res.defects:
            raise ValueError(res.defects[0])
        return [res]
    except TypeError as exc:  # a missing or mistyped parameter
        raise ValueError(f"{problem}: {exc}") from None


def _cell(v: float) -> str:
    return repr(float(v))


def _trace_cell(v: Any) -> str:
    """A traced value in a CSV cell: numbers as Python writes them, lists joined by ';'."""
    if isinstance(v, list | tuple):
        return ";".join(_trace_cell(x) for x in v)
    return repr(float(v)) if isinstance(v, int | float) and not isinstance(v, bool) \
        else str(v).replace(",", ";")


@dataclass(frozen=True)
class Synthesis:
    """A ``[synthesis]`` spec solved and ranked: the parsed spec and its task
    (:func:`read_synthesis`), the unit system and scene, the candidates, which problem
    each came from, the problems refused (one line each) and the :class:`Ranking`."""

    spec: dict
    task: dict
    units: str
    scene: Any
    candidates: list
    origin: list[int]
    refused: list[str]
    ranking: Any

    def traced(self) -> list[str]:
        """The names :meth:`trace` gives, in order: the varied parameters, then a crank-rocker
        family's free choice ``k`` and ``side``."""
        return list(self.task["vary"]) + (["k", "side"] if self.task["problem"] ==
                                          "crank_rocker" else [])

    def trace(self, i: int) -> dict[str, Any]:
        """Where candidate ``i`` came from: the values of [synthesis.vary] of its problem,
        and a crank-rocker's k [-] and side (:mod:`sielaff.synthesis.crank_rocker`)."""
        problem = self.task["problems"][self.origin[i]]
        out = {key: problem[key] for key in self.task["vary"]}
        if self.task["problem"] == "crank_rocker":
            out |= {"k": self.candidates[i].k, "side": self.candidates[i].side}
        return out


def synthesize(path: str) -> Synthesis:
    """Read the spec at ``path``, solve every problem of its ``[synthesis]`` and rank the
    candidates (``sielaff synth``, and the page ``sielaff report`` makes of such a spec);
    bad input is a CommandError of one line."""
    from sielaff import synthesis
    from sielaff.tools.common import CommandError, read_spec_with

    _, scene, (spec, task) = read_spec_with(
        path, lambda spec, where: (spec, read_synthesis(
            spec, where, spec.get("scene", {}).get("units", "in-lb-sec"))), deck=False)
    units = spec.get("scene", {}).get("units", "in-lb-sec")  # checked by scene_of
    cands, origin, refused = [], [], []
    for i, params in enumerate(task["problems"]):
        where = f"{path}: [synthesis.{task['problem']}]"
        try:
            got = solve(task["problem"], params, task["speed"], units, where)
        except ModuleNotFoundError as exc:
            raise CommandError(f"sielaff: {exc}") from None
        except ValueError as exc:
            refused.append(f"{where} problem {i}: {exc}")
            continue
        cands += got
        origin += [i] * len(got)
    if not cands:
        raise CommandError(refused[0] if len(refused) == 1 else
                           f"{path}: none of the {len(refused)} problems has a solution "
                           f"(the first: {refused[0]})")
    try:
        r = synthesis.rank(cands, scene=scene, by=task["by"], pareto=task["pareto"],
                           mass_model=task["mass_model"], n=task["angles"], cf=task["cf"],
                           constraints=task["constraints"], tie=task["tie"])
    except ValueError as exc:
        raise CommandError(f"{path}: {exc}") from None
    return Synthesis(spec, task, units, scene, cands, origin, refused, r)


def cmd_synth(args) -> int:
    from sielaff.design.figures import FIGURES
    from sielaff.engine.classify import KINDS, linkage_class
    from sielaff.mechanism import FIELD_NAMES
    from sielaff.quantities import unit
    from sielaff.tools.common import (
        CommandError,
        refuse_bad_output,
        refuse_stdout,
        spec_path,
    )
    from sielaff.tools.output import atomic_files

    path = args.spec
    if args.output == "-":
        args.output = None  # -o -: the ranked table on stdout, the status on stderr
    refuse_bad_output(args.output, [path])
    refuse_stdout(args.write_best, "--write-best writes several files into a folder",
                  "--write-best")
    if args.write_best and os.path.exists(args.write_best) and \
            not os.path.isdir(args.write_best):
        raise CommandError(f"sielaff: --write-best {args.write_best} is a file: name a folder")
    if args.write_best and args.output and \
            os.path.realpath(args.output) == os.path.realpath(args.write_best):
        raise CommandError(f"sielaff: -o {args.output} and --write-best {args.write_best} "
                           "name the same path: the table is a file, the best a folder")
    if not spec_path(path):
        raise CommandError(f"{path}: synth reads a TOML spec with a [synthesis] table")
    done = synthesize(path)
    spec, task, units, scene = done.spec, done.task, done.units, done.scene
    cands, origin, refused, r = done.candidates, done.origin, done.refused, done.ranking
    front = set(int(i) for i in r.pareto)
    figs = [f for f in FIGURES if f != "KIND"]
    traced = done.traced()
    header = (["RANK", "CANDIDATE", "PROBLEM"]
              + [t.upper() if t == "side" else
                 f"{t.upper()}[{problem_unit(task['problem'], t, units)}]" for t in traced]
              + ["BRANCH", "PARETO", "FEASIBLE", "VIOLATES"]
              + [f"{n}[{unit(n, units)}]" for n in FIELD_NAMES]
              + [f"{f}[{unit(FIGURES[f][0], units)}]" for f in figs] + ["KIND"])
    lines = [",".join(header)]
    for i in r.order:
        m, where = r.mechanisms[i], done.trace(int(i))
        lines.append(",".join(
            [str(r.ranks[i]), str(int(i)), str(origin[i])]
            + [_trace_cell(where[t]) for t in traced]
            + [r.branches[i], str(int(i in front)), str(int(r.feasible[i])),
               r.violations[i].replace(",", ";")]
            + [_cell(getattr(m, n)) for n in FIELD_NAMES]
            + [_cell(r.figures[f][i]) for f in figs] + [KINDS[int(r.figures["KIND"][i])]]))
    csv_text = "\n".join(lines) + "\n"
    written: list[tuple[str, str]] = []
    notes: list[str] = []
    if args.write_best:
        for k, i in enumerate(r.order[:task["best"]], 1):
            m, branch = r.mechanisms[i], r.branches[i]
            base = {key: v for key, v in spec.items() if key == "scene"}
            base.setdefault("scene", {})
            base["scene"] = dict(base["scene"]) | {"branch": branch, "units": units}
            text = _spec_text(m, base, f"candidate {int(i)} of {path}, ranked {k} by "
                              f"{', '.join(task['by'])} (sielaff synth)")
            name = os.path.join(args.write_best, f"best-{k}")
            written.append((name + ".toml", text))
            deck, why = _deck_text(m, branch, scene, base, path, linkage_class, int(i))
            if deck is not None:
                written.append((name + ".dat", deck))
            else:
                notes.append(f"  no deck for best-{k}: {why}")
    paths = ([args.output] if args.output else []) + [p for p, _ in written]
    # an older run's best-K beyond this one's (or its deck where this one has none) would
    # read as this run's: the set is replaced whole, the stale ones removed after it
    import glob

    stale = sorted(set(glob.glob(os.path.join(glob.escape(args.write_best), "best-*.toml"))
                       + glob.glob(os.path.join(glob.escape(args.write_best), "best-*.dat")))
                   - {os.path.join(args.write_best, os.path.basename(p)) for p, _ in written}
                   ) if args.write_best else []
    with atomic_files(paths) as temps:
        texts = ([csv_text] if args.output else []) + [t for _, t in written]
        for tmp, text in zip(temps, texts):
            with open(tmp, "w", newline="") as f:
                f.write(text)
        if not args.output:
            sys.stdout.write(csv_text)
    for old in stale:
        os.unlink(old)
    if stale:
        notes.append(f"  removed {len(stale)} older file{'s' if len(stale) > 1 else ''} of "
                     f"{args.write_best} ({', '.join(os.path.basename(p) for p in stale)})")
    ok = int(np.isfinite(r.figures[task["by"][0]]).sum())
    limits = (f", {int(r.feasible.sum())} meeting the {len(r.constraints)} constraint"
              f"{'s' if len(r.constraints) > 1 else ''}") if r.constraints else ""
    msg = (f"sielaff synth: {len(cands)} candidates from {len(task['problems'])} "
           f"{task['problem']} problem(s) ({len(refused)} without a solution), "
           f"{ok} with a full cycle{limits}, ranked by {', '.join(task['by'])}; Pareto front of "
           f"{' and '.join(r.pareto_by)}: {len(r.pareto)}"
           + (f" -> {args.output}" if args.output else ""))
    if written:
        msg += f"; wrote {', '.join(p for p, _ in written)}"
    print("\n".join([msg] + notes), file=sys.stderr)
    return 0


def _fit(value: float) -> Decimal:
    """``value`` rounded to the most decimals an 8-column card field holds (the spec is
    read through a deck by every command, so its numbers must punch)."""
    from sielaff.tools.spec import punch_field

    d = Decimal(repr(float(value) + 0.0))
    for digits in range(7, -1, -1):
        q = d.quantize(Decimal(1).scaleb(-digits))
        try:
            punch_field(q)
        except ValueError:
            continue
        return _clean(q)
    raise ValueError(f"{float(value):g} does not fit an 8-column field")


def _clean(q: Decimal) -> Decimal:
    """``q`` without trailing zeros, one decimal at least: 10.0000000 is 10.0, 0E-7 is
    0.0 (the same value; a spec reads as a person wrote it)."""
    q = q.normalize()
    return q.quantize(Decimal("0.1")) if q == q.to_integral_value() else q


def _values(m) -> dict:
    from sielaff.mechanism import FIELD_NAMES

    return {n: _fit(getattr(m, n)) for n in FIELD_NAMES}


RANGE = [(Decimal("0.0"), Decimal("10.0"), Decimal("350.0"))]


def _spec_text(m, base: dict, header: str) -> str:
    from sielaff.tools.spec import spec_dict, spec_text

    return spec_text(spec_dict(_values(m), RANGE, base), header)


def _deck_text(m, branch, scene, base, path, linkage_class, i) -> tuple[str | None, str]:
    """A deck for candidate ``m`` where one can hold it, else (None, why not)."""
    from sielaff.tools.spec import PunchError, punch_deck, spec_dict

    if m.units != "in-lb-sec":
        return None, "a 1966 deck is in in-lb-sec units"
    if branch != "open":
        return None, "it runs on the crossed branch; the 1966 program solves the open one"
    if not scene.is_1966:
        return None, "the [scene] has effects a 1966 deck cannot carry"
    if not bool(linkage_class(m).turns_fully):
        return None, "the crank does not turn fully (the 1966 program needs a crank-rocker)"
    try:
        return punch_deck(spec_dict(_values(m), RANGE, {}), f"candidate {i}"), ""
    except (PunchError, ValueError) as exc:
        return None, str(exc)
