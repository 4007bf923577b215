"""The sections every report page shares, whatever the linkage's kind: the scene's
effects, the peaks table, a ``[sweep]``'s Pareto front, a ``[tolerance]`` study, and a
``[motor]`` spec's simulation with its sizing."""

from __future__ import annotations

import html
import io
import warnings
from typing import Any

import numpy as np

from sielaff.emulator.cards import Deck
from sielaff.engine.scene import Scene  # noqa: TC001
from sielaff.quantities import fmt
from sielaff.tools.report.page import figure, png

__all__ = ["motor_section", "peak_rows", "peaks_table", "scene_section", "sweep_section",
           "tolerance_section"]

#: A sweep larger than this is summarised by ``sielaff sweep``, not run for a page.
SWEEP_LIMIT = 20_000
#: Rows of the Pareto front shown.
FRONT_ROWS = 15


def peak_rows(deck: Deck, scene: Scene, n: int = 3600) -> list[Any]:
    """The peaks table's rows (:func:`sielaff.design.peaks.peaks`): over the angles the
    linkage reaches, a quantity that grows without bound toward a toggle given as such."""
    from sielaff.design.peaks import peaks

    return peaks(deck.mechanism, scene, n)


def peaks_table(rows: list[Any]) -> str:
    out = ["<table><tr><th>peak</th><th>value</th><th>unit</th><th>at THETA 2</th></tr>"]
    for p in rows:
        if p.unbounded:
            where = ", ".join(f"{t:.2f} deg (GAMMA {g:.0f} deg)"
                              for t, g in zip(p.toggles, p.gamma))
            out.append(f"<tr><td>{html.escape(p.label)}</td><td>unbounded</td>"
                       f"<td>{html.escape(p.unit)}</td><td>grows without bound toward the "
                       f"toggle{'s' if len(p.toggles) > 1 else ''} at "
                       f"{html.escape(where)}</td></tr>")
        else:
            out.append(f"<tr><td>{html.escape(p.label)}</td><td>{p.value:.5g}</td>"
                       f"<td>{html.escape(p.unit)}</td><td>{p.at:.1f} deg</td></tr>")
    out.append("</table>")
    if any(p.unbounded for p in rows):
        out.append("<p>At a toggle the coupler and the rocker are in line (the transmission "
                   "angle GAMMA is 0 or 180 deg): a crank that keeps turning cannot drive "
                   "the rocker through it, and the rates and the forces grow without bound "
                   "as THETA 2 nears it.  Those rows give no number: the largest value "
                   "depends only on how near to the toggle one looks.</p>")
    return "\n".join(out)


def motor_section(deck: Deck, scene: Scene, run: dict) -> list[str]:
    """A ``[motor]`` spec's simulation as ``sielaff simulate`` runs it: what happened, the
    speed, torques and power against time, and the motor sizing."""
    from sielaff.tools.plot.render import _pyplot
    from sielaff.tools.simulate import draw

    m = deck.mechanism
    out = ["<h2>The motor</h2>",
           f"<p>{html.escape(run['motor'].describe(m.units))}; flywheel "
           f"{html.escape(fmt(run['flywheel'], 'inertia', m.units, '.6g'))}; "
           + ("the periodic steady state" if run["steady"] else
              f"{run['revolutions']:g} revolutions from "
              + ("the deck's TH2D" if run["speed"] is None else
                 html.escape(fmt(run["speed"], "rate", m.units, ".6g"))))
           + ".</p>"]
    try:
        import scipy  # noqa: F401
    except ImportError:
        return out + ['<p>Not simulated here: simulate needs scipy (pip install -e '
                      '".[dynamics]").</p>']
    from sielaff.dynamics import SimulationError, simulate
    from sielaff.dynamics.sizing import FIGURES, sizing

    try:
        r = simulate(m, run["motor"], flywheel=run["flywheel"], scene=scene,
                     speed0=run["speed"], revolutions=run["revolutions"],
                     steady=run["steady"], outputs=["TORQ"], method=run["method"],
                     rtol=run["rtol"])
    except SimulationError as exc:
        return out + [f"<p>Not simulated: {html.escape(str(exc))}</p>"]
    plt = _pyplot()
    fig = plt.figure(figsize=(8, 7.5))
    draw(fig, r)
    fig.tight_layout()
    out.append(f"<p>{html.escape(r.message)}.</p>")
    out.append(figure(png(fig), "image/png",
                       "The crank speed, the torques and the motor's power against time"))
    s = sizing(r)
    rows = [f"<tr><td>{html.escape(words)}</td><td>{s[key]:.6g}</td>"
            f"<td>{html.escape(s['units'][key])}</td></tr>"
            for key, words, _ in FIGURES if key in s]
    out += [f"<p>Motor sizing over {html.escape(s['window'])}:</p>",
            "<table><tr><th>figure</th><th>value</th><th>unit</th></tr>", *rows,
            "</table>"]
    out += [f"<p><b>Warning:</b> {html.escape(w)}.</p>" for w in s["warnings"]]
    return out


def scene_section(m: Any, scene: Scene, figures: bool) -> list[str]:
    """The scene's effects as each declares itself (its parameters with their units, its
    figures over a revolution when the crank turns fully): check's lines, as a table."""
    from sielaff.design.effects import effect_facts
    from sielaff.engine.declare import fact_lines

    facts = effect_facts(m, scene, figures=figures)
    if not facts:
        return []
    rows = []
    for f in facts:
        lines = fact_lines(f.parameters, m.units, "") + fact_lines(f.figures, m.units, "")
        rows.append(f"<tr><th>{html.escape(f.name)}</th><td>{html.escape(f.summary)}</td>"
                    f"<td>{'<br>'.join(html.escape(x) for x in lines)}</td></tr>")
    return ["<h2>The scene</h2>",
            "<table><tr><th>effect</th><th>in brief</th><th>its parameters and figures"
            + (" (over one revolution)" if figures else "") + "</th></tr>",
            *rows, "</table>"]


def sweep_section(path: str, deck: Deck, scene: Scene) -> list[str]:
    """For a spec with a ``[sweep]``: its Pareto front as a table (the designs no other
    beats in both figures, by the first) and the Pareto picture; nothing otherwise."""
    from sielaff.design.sweep import Grid, column_units, columns, iter_blocks
    from sielaff.engine import AssemblyWarning
    from sielaff.tools.common import is_spec, read_spec
    from sielaff.tools.spec import sweep_of
    from sielaff.tools.sweep import _pareto, _plot

    if not is_spec(path):
        return []
    spec = read_spec(path)
    if "sweep" not in spec:
        return []
    sw = sweep_of(spec, path, deck.mechanism)
    grid = Grid(deck.mechanism, sw["axes"])
    out = ["<h2>The sweep</h2>"]
    if grid.size > SWEEP_LIMIT:
        return out + [f"<p>{grid.size:,} designs: more than a page runs "
                      f"({SWEEP_LIMIT:,}); <code>sielaff sweep</code> evaluates them.</p>"]
    cols = columns(grid)
    with warnings.catch_warnings():  # designs that do not assemble: NaN figures, shown
        warnings.simplefilter("ignore", AssemblyWarning)
        data = np.concatenate(list(iter_blocks(grid, sw["angles"], sw["cf"], scene)), axis=0)
    px, py = sw["pareto"]
    senses = sw.get("senses", ("min", "min"))  # each figure minimised or maximised
    x, y = data[:, cols.index(px)], data[:, cols.index(py)]
    front = _pareto(x, y, senses)
    units = column_units(cols, deck.mechanism.units)
    shown = ["DESIGN", *grid.names, px, py]
    out.append(f"<p>{grid.size:,} designs ({' x '.join(str(n) for n in grid.shape)}: "
               f"{html.escape(', '.join(grid.names))}); the Pareto front of {px} and {py} "
               f"({' and '.join(s + 'imised' for s in senses)}) has {len(front)} designs; "
               "the first "
               f"{min(len(front), FRONT_ROWS)} by {px}:</p>")
    rows = ["<table><tr>" + "".join(
        f"<th>{html.escape(c)}" + (f" [{html.escape(units[c])}]" if units[c] != "-" else "")
        + "</th>" for c in shown) + "</tr>"]
    for i in front[:FRONT_ROWS]:
        rows.append("<tr>" + "".join(f"<td>{data[i, cols.index(c)]:.5g}</td>" for c in shown)
                    + "</tr>")
    rows.append("</table>")
    buf = io.BytesIO()
    _plot(buf, x, y, (px, py), deck.mechanism.units, grid.size, senses,
          designs=data[:, cols.index("DESIGN")], mechanism=deck.mechanism)
    return out + rows + [figure(buf.getvalue(), "image/png",
                                 f"The sweep's designs and the Pareto front of {px} and {py}")]


def tolerance_section(deck: Deck, scene: Scene, task: dict) -> list[str]:
    """For a spec with a ``[tolerance]``: the study it asks for, as ``sielaff tolerance``
    prints it (each figure's nominal, sampled spread and first-order estimate, and the
    sensitivities, every number with its unit)."""
    from sielaff.tools.tolerance import run_tolerance, table_lines

    t = run_tolerance(deck, scene, task)
    return ["<h2>Tolerances</h2>",
            f"<pre>{html.escape(chr(10).join(table_lines(t, deck.path)))}</pre>"]
