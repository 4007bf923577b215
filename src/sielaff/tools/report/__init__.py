"""``sielaff report DECK|SPEC -o report.html``: the page an engineer forwards.

One self-contained HTML file: every image inline (``data:`` URIs), the style inline, no
script, and a Content-Security-Policy that lets the page load nothing from anywhere, so
it reads the same offline in any browser and prints to PDF from it.  It holds:

* the deck or spec with units, the kind of linkage, its Grashof margin, toggles and
  reachable arcs (``sielaff check``'s report, which also carries the transmission
  angle, the peak loads with their angles, the cycle work, the flywheel, the bearings
  and every 1966 quirk the deck triggers);
* the scene (gravity, crank acceleration, loads, TEX, the branch);
* a table of peaks, each with the crank angle where it occurs, in the mechanism's units,
  over the angles where the linkage assembles; a quantity that grows without bound
  toward a toggle is "unbounded", with the toggles and GAMMA there, never a number
  (:mod:`sielaff.design.peaks`);
* the linkage drawn at a chosen angle (default 40 deg, or the middle of the first arc
  where it assembles), and one cycle of it animated (a GIF); a linkage that assembles
  nowhere is said to, and nothing is drawn;
* the report's figures (driving torque, the polar diagrams of the bearing forces and of
  the shaking force) and the bearing picture;
* the balancing answer (Berkof-Lowen counterweights and what they cost);
* for a spec with a ``[sweep]``: the Pareto front of its two figures as a table, and the
  Pareto picture;
* for a spec with a ``[tolerance]``: the study ``sielaff tolerance`` prints (each figure's
  nominal, spread and first-order estimate, and the sensitivities);
* for a spec with a ``[motor]``: its simulation as ``sielaff simulate`` runs it (speed,
  torques and power against time) and the motor sizing (:mod:`sielaff.dynamics.sizing`);
* a footer with the version, the date (``SOURCE_DATE_EPOCH`` when set) and the command
  that made the page.

Printed (Chromium's PDF, A4), every table fits the page: wide tables shrink and wrap,
nothing scrolls (tests/test_report_every_linkage.py).

A spec with a ``[synthesis]`` describes no one linkage: its page is the ranking
``sielaff synth`` computes (:func:`sielaff.tools.synth.synthesize`), its first
:data:`RANK_ROWS` rows as a table with the units in the headers, the best
:data:`DRAWN` candidates drawn by ``plot --linkage``'s drawing, every candidate in the
two Pareto figures with the front, and the spec as written.

This command composes the others' pages (check, plot, balance, sweep, synth,
tolerance): it is the one command that imports other commands (docs/architecture.md),
and nothing imports it; it reads a synthesis or tolerance spec through those commands'
own readers.  The page is
written whole or not at all (``tools/output.py``); bad input is one line, as for every
command.
"""

from __future__ import annotations

import html
import os
import sys
from typing import Any

import numpy as np

from sielaff.emulator.cards import Deck
from sielaff.engine.scene import Scene  # noqa: TC001
from sielaff.tools.report.page import figure, head, page, png
from sielaff.tools.report.sections import (  # noqa: F401  (tests read them here)
    motor_section,
    peak_rows,
    peaks_table,
    scene_section,
    sweep_section,
    tolerance_section,
)

#: Frames of the page's animation: 15 degrees apart for a crank that turns fully (a page
#: is read, not played; ``plot --animate`` draws 36).
FRAMES = 24


#: Rows of a synthesis's ranking shown on the page (``sielaff synth`` writes them all).
RANK_ROWS = 20
#: Candidates drawn, best first.
DRAWN = 8


def _ranking_columns(r: Any) -> list[str]:
    """The figures the ranking table shows: the ranking's, the Pareto front's, the
    constrained ones and the least transmission angle, each once (the page's width; the
    CSV of ``synth`` has all)."""
    from sielaff.synthesis.rank import RANKABLE

    shown: list[str] = []
    for f in [*r.by, *r.pareto_by, *(c for c in r.constraints if c in RANKABLE),
              "GAMMA_MIN"]:
        if f not in shown:
            shown.append(f)
    return shown


def _ranking_table(done: Any) -> str:
    """The first :data:`RANK_ROWS` candidates, best first: rank (shared by ties), where
    each came from (its index as solved, the varied values, a crank-rocker's k and side:
    ``done.trace``), its branch, its four lengths and the figures, each header with its
    unit, the constraint it breaks."""
    from sielaff.design.sweep import column_units
    from sielaff.tools.spec_tables import problem_unit

    r = done.ranking
    figs = _ranking_columns(r)
    lengths = ["R1", "R2", "R3", "R4"]
    units = column_units(lengths + figs, r.units)
    front = {int(i) for i in r.pareto}
    traced = done.traced()

    def head_of(t: str) -> str:
        u = "" if t == "side" else problem_unit(done.task["problem"], t, r.units)
        return t if u in ("", "-") else f"{t} [{u}]"

    head = (["rank", "cand."] + [head_of(t) for t in traced] + ["branch"]
            + [f"{n} [{units[n]}]" for n in lengths + figs] + ["Pareto"]
            + (["breaks"] if r.constraints else []))
    out = ['<div class="wide"><table class="small"><tr>'
           + "".join(f"<th>{html.escape(h)}</th>" for h in head) + "</tr>"]
    for i in r.order[:RANK_ROWS]:
        m, where = r.mechanisms[i], done.trace(int(i))
        cells = ([str(r.ranks[i]), str(int(i))] + [_traced(where[t]) for t in traced]
                 + [r.branches[i]] + [f"{getattr(m, n):.5g}" for n in lengths]
                 + [f"{r.figures[f][i]:.5g}" for f in figs]
                 + ["yes" if int(i) in front else ""]
                 + ([r.violations[i].split(" ")[0]] if r.constraints else []))
        out.append("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in cells) + "</tr>")
    out.append("</table></div>")
    return "\n".join(out)


def _traced(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.4g}"
    if isinstance(v, list | tuple):
        return ", ".join(_traced(x) for x in v)
    return str(v)


def _constraints_text(r: Any) -> str:
    """The ranking's constraints in words, with units, and how many candidates meet them."""
    from sielaff.synthesis.rank import constraint_unit

    if not r.constraints:
        return ""
    said = []
    for name, (lo, hi) in r.constraints.items():
        u = constraint_unit(name, r.units)
        u = "" if u == "-" else f" {u}"
        said.append(" and ".join(b for b in (
            f"{name} at least {lo:g}{u}" if lo is not None else "",
            f"{name} at most {hi:g}{u}" if hi is not None else "") if b))
    met = int(np.sum(r.feasible))
    return (f"<p>Constraints: {html.escape('; '.join(said))}. {_count(met, 'candidate')} "
            f"meet{'s' if met == 1 else ''} them; the others rank after, the first bound "
            "each breaks in <em>breaks</em>, and are left off the Pareto front.</p>")


def _kinds(done: Any) -> str:
    """How many candidates are of each kind of four-bar, in words."""
    from sielaff.engine.classify import KINDS

    k = np.asarray(done.ranking.figures["KIND"], dtype=float)
    counts = [(KINDS[int(v)], int(np.sum(k == v))) for v in np.unique(k[np.isfinite(k)])]
    if len(counts) == 1 and counts[0][1] > 1:
        return f"all {counts[0][0]}s"
    return ", ".join(_count(n, kind) for kind, n in counts)


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'' if n == 1 else 's'}"


def _candidates_figure(done: Any, at: float) -> bytes:
    """The best :data:`DRAWN` candidates, each drawn at THETA 2 = ``at`` on its own branch
    by the linkage drawing of ``sielaff plot --linkage`` (its paths, links, joints and
    toggles), titled with its rank and first ranking figure."""
    from sielaff.design.figures import FIGURES
    from sielaff.quantities import unit
    from sielaff.tools.plot.linkage import _linkage_axes, linkage_data
    from sielaff.tools.plot.render import _pyplot

    plt = _pyplot()
    r = done.ranking
    show = list(r.order[:DRAWN])
    cols = min(2, len(show))
    rows = -(-len(show) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(5.6 * cols, 2.6 * rows + 0.5), dpi=80,
                             layout="constrained", squeeze=False)
    first = r.by[0]
    u = unit(FIGURES[first][0], r.units)
    import warnings

    for k, ax in enumerate(axes.flat):
        if k >= len(show):
            ax.set_axis_off()
            continue
        i = show[k]
        deck = Deck(r.mechanisms[i], [], [], f"candidate {int(i)}")
        with warnings.catch_warnings():  # a candidate that cannot assemble at ``at``
            warnings.simplefilter("ignore")  # is drawn without its links, as plot does
            d = linkage_data(deck, (at,), (), r.branches[i])
        _linkage_axes(ax, d, 0)
        ax.set_aspect("equal", adjustable="datalim")  # the panel filled, to scale
        ax.set_title(f"#{k + 1}: candidate {int(i)} ({r.branches[i]} branch), {first} "
                     f"{r.figures[first][i]:.4g} {u}", fontsize=9)
        ax.tick_params(labelsize=7)
        ax.xaxis.label.set_size(8)
        ax.yaxis.label.set_size(8)
        for t in ax.texts:
            t.set_fontsize(7)
    fig.suptitle(f"The best {len(show)} of {len(r)} candidates at THETA 2 = {at:g} deg, "
                 f"ranked by {', '.join(r.by)} (dashed: the path of G3)", fontsize=10)
    return png(fig)


def _pareto_figure(done: Any) -> bytes:
    """Every candidate in the two Pareto figures (hollow: breaking a constraint), the
    front's points marked (not joined), the first three by rank numbered."""
    from sielaff.design.figures import FIGURES
    from sielaff.quantities import unit
    from sielaff.synthesis.rank import MAXIMISED
    from sielaff.tools.plot.render import _pyplot

    plt = _pyplot()
    r = done.ranking
    px, py = r.pareto_by
    x, y = np.asarray(r.figures[px]), np.asarray(r.figures[py])
    fig, ax = plt.subplots(figsize=(7, 4.6), dpi=90, layout="constrained")
    ok = np.isfinite(x) & np.isfinite(y)
    met = ok & np.asarray(r.feasible, dtype=bool)
    ax.scatter(x[met], y[met], s=14, color="0.6", label=f"candidates ({int(ok.sum())} of "
               f"{len(x)} turn fully)" if not r.constraints else
               f"meeting the constraints ({int(met.sum())})")
    if r.constraints and (ok & ~met).any():
        ax.scatter(x[ok & ~met], y[ok & ~met], s=14, facecolors="none", edgecolors="0.6",
                   label=f"breaking one ({int((ok & ~met).sum())})")
    p = np.asarray(r.pareto, dtype=int)
    # markers only: a line between front points would suggest designs between them
    ax.plot(x[p], y[p], "o", color="tab:red", ms=5, label=f"Pareto front ({len(p)})")
    for i in r.order[:3]:
        if ok[i]:
            ax.annotate(f"#{r.ranks[i]}", (x[i], y[i]), xytext=(5, 5), textcoords="offset points",
                        fontsize=9)

    def label(f: str) -> str:
        how = "maximised" if f in MAXIMISED else "minimised"
        return f"{f} [{unit(FIGURES[f][0], r.units)}], {how}"

    ax.set_xlabel(label(px))
    ax.set_ylabel(label(py))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=9)
    ax.set_title(f"The candidates in {px} and {py}; #k: rank by {', '.join(r.by)}",
                 fontsize=10)
    return png(fig)


def synthesis_html(done: Any, path: str, text: str, command: str, at: float = 40.0) -> str:
    """The page for the ``[synthesis]`` spec at ``path`` (``text``: as written), solved
    and ranked (``done``: :func:`sielaff.tools.synth.synthesize`): the ranking as a table
    and its pictures (the best candidates drawn, the Pareto front), and the spec."""
    from sielaff.tools.common import describe_scene

    r, task = done.ranking, done.task
    effects = describe_scene(done.scene, done.units) or "the 1966 scene (no gravity, no " \
        "loads, constant crank speed)"
    turning = int(np.isfinite(r.figures[r.by[0]]).sum())
    parts = head(os.path.basename(path)) + [
        f'<p class="sub">A synthesis ({html.escape(task["problem"])}) in '
        f"{html.escape(done.units)} units; scene: {html.escape(effects)}.</p>",
        "<h2>The ranking</h2>",
        f"<p>{_count(len(r), 'candidate')} from {_count(len(task['problems']), 'problem')} "
        f"({len(done.refused)} without a solution): {_kinds(done)}, {turning} turning "
        f"fully; ranked by {html.escape(', '.join(r.by))}"
        + (" (the first deciding, ties to the next)" if len(r.by) > 1 else "")
        + f", each at TH2D = {task['speed']:g} rad/sec over {task['angles']} crank angles. "
        + (f"The first {RANK_ROWS}; " if len(r) > RANK_ROWS else "")
        + "<code>sielaff synth</code> writes every one with all its fields"
        + ("; a rank is shared by candidates tied on every ranking figure (within "
           f"{task['tie']:g} of its largest value)") + ".</p>",
        _constraints_text(r),
        _ranking_table(done),
    ]
    for line in done.refused[:5]:
        parts.append(f"<p>Without a solution: {html.escape(line)}</p>")
    parts += [
        "<h2>The best candidates</h2>",
        figure(_candidates_figure(done, at), "image/png",
                f"The best candidates at THETA 2 = {at:g} deg"),
        figure(_pareto_figure(done), "image/png",
                f"The Pareto front of {r.pareto_by[0]} and {r.pareto_by[1]}"),
        "<p>A whole page for a candidate: <code>sielaff synth SPEC --write-best DIR</code>, "
        "then <code>sielaff report DIR/best-1.toml</code>.</p>",
        "<h2>The spec</h2>",
        f"<pre>{html.escape(text)}</pre>",
    ]
    return page(parts, command)


def report_html(deck: Deck, scene: Scene, command: str, at: float | None = None,
                tolerances: dict | None = None, motor: dict | None = None) -> str:
    """The whole page for ``deck`` in ``scene`` (see the module doc); ``tolerances``: a
    spec's checked ``[tolerance]`` table, whose study gets a section."""
    from sielaff.design.balance import balance
    from sielaff.design.report import balance_lines
    from sielaff.engine import linkage_class
    from sielaff.tools.check import check_deck
    from sielaff.tools.common import describe_scene
    from sielaff.tools.plot import plot_data, render_png
    from sielaff.tools.plot.bearings import bearings_figure
    from sielaff.tools.plot.linkage import (
        DEFAULT_AT,
        _animation,
        _draw_linkage,
        default_angle,
        linkage_data,
    )
    from sielaff.tools.plot.render import _pyplot

    m = deck.mechanism
    name = os.path.basename(deck.path)
    c = linkage_class(m)
    effects = describe_scene(scene, m.units) or "the 1966 scene (constant crank speed, " \
        "no gravity, TEX = 0 the only load, the open branch)"
    parts = head(name) + [
        f'<p class="sub">A {html.escape(c.kind)} in {html.escape(m.units)} units; '
        f"scene: {html.escape(effects)}.</p>",
    ]
    parts += scene_section(m, scene, bool(c.turns_fully))
    plt = _pyplot()
    # the linkage, drawn and animated where it assembles
    parts.append("<h2>The linkage</h2>")
    if not c.turns_fully and not c.arcs:
        parts.append("<p>This linkage cannot be put together at any crank angle (link 3 "
                     "never reaches link 4): there is nothing to draw, and no motion, peak "
                     "or figure to give.  The check report below says why.</p>")
    else:
        where = at if at is not None else default_angle(deck, scene.branch)
        fig = _draw_linkage(plt, linkage_data(deck, (where,), (), scene.branch))
        why = "" if at is not None or where == DEFAULT_AT else (
            f" (the middle of the first arc where it assembles; not at {DEFAULT_AT:g} deg)")
        parts.append(figure(png(fig), "image/png",
                             f"The linkage at THETA 2 = {where:.6g} deg{why} "
                             f"({scene.branch} branch)"))
        parts.append(figure(_animation(plt, deck, (), scene.branch, frames=FRAMES),
                             "image/gif", f"One cycle of the linkage (the angles it "
                                          f"reaches, {FRAMES} frames)"))
    # peaks
    rows = peak_rows(deck, scene)
    if rows:
        parts.append("<h2>Peaks</h2>")
        parts.append(peaks_table(rows))
    # the report's figures and the bearings (they need a crank that turns fully)
    if c.turns_fully:
        parts.append("<h2>Figures</h2>")
        for d in plot_data(deck, None, scene).values():
            parts.append(figure(render_png(d), "image/png", d.title.split("\n")[0]))
        fig, _ = bearings_figure(deck, scene)
        parts.append(figure(png(fig), "image/png",
                             "Bearing loads relative to each member (shaded: never loaded)"))
    else:
        parts.append("<p>The crank cannot turn a whole revolution: the revolution figures, "
                     "the flywheel and the bearing cycle do not apply.</p>")
    # check's report: values with units, kind, margins, toggles, quirks, flywheel, bearings
    parts.append("<h2>The check report</h2>")
    parts.append(f"<pre>{html.escape(check_deck(deck, scene=scene).text)}</pre>")
    # balancing
    if c.turns_fully:
        try:
            balanced = balance(m)
            lines = balance_lines(m, balanced, scene=scene)
        except ValueError as exc:
            lines = [f"not balanced: {exc}"]
        parts.append("<h2>Balancing</h2>")
        parts.append(f"<pre>{html.escape(chr(10).join(lines))}</pre>")
    parts += sweep_section(deck.path, deck, scene)
    if motor is not None:
        parts += motor_section(deck, scene, motor)
    if tolerances is not None:
        parts += tolerance_section(deck, scene, tolerances)
    return page(parts, command)


def _spec_tables(path: str) -> set[str]:
    """The top-level tables of a TOML spec (none for a deck, or a spec that cannot be
    read: its reader says why, in one line)."""
    from sielaff.tools.common import is_spec, is_stdin, read_spec
    from sielaff.tools.spec import PunchError

    if not is_spec(path) or not (is_stdin(path) or os.path.isfile(path)):
        return set()
    try:
        return set(read_spec(path))
    except PunchError:
        return set()


def cmd_report(args: Any) -> int:
    """``sielaff report DECK|SPEC -o FILE.html`` (``-o -``: stdout)."""
    from sielaff.tools.common import (
        CommandError,
        load_scene,
        refuse_bad_output,
        spec_source,
    )
    from sielaff.tools.output import atomic_output

    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise CommandError("sielaff: report needs matplotlib: pip install -e \".[plot]\"") \
            from None
    if args.output != "-":
        refuse_bad_output(args.output, [args.deck])
    import shlex

    command = "sielaff " + shlex.join(getattr(args, "argv", ["report", args.deck, "-o",
                                                              args.output]))
    tables = _spec_tables(args.deck)
    if "synthesis" in tables:
        from sielaff.tools.synth import synthesize

        if args.branch:
            raise CommandError(f"sielaff: --branch {args.branch}: {args.deck} is a "
                               "synthesis, whose candidates each have their own branch")
        done = synthesize(args.deck)
        text = spec_source(args.deck)
        with np.errstate(all="ignore"):
            page = synthesis_html(done, args.deck, text, command,
                                  at=40.0 if args.at is None else args.at)
    else:
        task = None
        if "tolerance" in tables:
            from sielaff.tools.tolerance import tolerance_spec

            deck, scene, task = tolerance_spec(args.deck)  # checks the nominal design
        else:
            from sielaff.tools.kinds import other_kinds

            deck, scene = load_scene(args.deck, any_linkage=True, kinds=other_kinds(),
                                     branch=args.branch or None)
        if args.branch:
            scene = scene.replace(branch=args.branch)
        from sielaff.mechanism import Mechanism

        four_bar = isinstance(deck.mechanism, Mechanism)
        motor = None
        if "motor" in tables:
            from sielaff.tools.common import read_spec
            from sielaff.tools.simulate import motor_of
            from sielaff.tools.spec import PunchError

            try:
                motor = motor_of(read_spec(args.deck), args.deck, deck.mechanism.units)
            except PunchError as exc:
                raise CommandError(str(exc), exc.status) from None
        with np.errstate(all="ignore"):
            if four_bar:
                page = report_html(deck, scene, command, at=args.at, tolerances=task,
                                   motor=motor)
            else:
                from sielaff.tools.report.kinds import kind_report_html

                page = kind_report_html(deck, scene, command, at=args.at, motor=motor,
                                        tolerances=task)
    if args.output == "-":
        sys.stdout.write(page)
        return 0
    with atomic_output(args.output) as out:
        out.write(page)
    return 0
