"""The report page of a linkage of another kind than the four-bar (a slider-crank, an
inverted slider-crank, a six-bar, any :class:`sielaff.Linkage` a spec names).

The same page as the four-bar's, composed from the same commands' work for the kind:

* the kind and its scene (each effect's parameters and figures, with units);
* the linkage drawn where it assembles, and one cycle of it animated (``plot --linkage``'s
  drawing: slider blocks on their guides, ternary links as triangles; a kind that
  assembles nowhere is refused when read, as every command refuses it);
* the peaks table (:mod:`sielaff.design.peaks`: every pin force, every guide force, TORQ,
  the shaking force; "unbounded" toward a toggle, never a number);
* the force figures ``sielaff plot`` draws for the kind (driving torque with the cycle
  work, a polar diagram of every pin force and of the shaking force), when the crank
  turns fully;
* ``sielaff check``'s report for the kind (fields, dyads' margins and transmission
  angles, stroke and time ratio, peaks, cycle work, effects);
* balancing: a slider-crank's crank counterweight (:func:`sielaff.design.slider_balance`);
  for the others the page says why none is offered;
* a ``[sweep]``'s Pareto front of the kind's figures (:func:`sections.sweep_section`);
* a ``[motor]`` spec's simulation and sizing (:func:`sections.motor_section`);
* a ``[tolerance]`` study (:func:`sections.tolerance_section`).
"""

from __future__ import annotations

import html
import os
from typing import Any

from sielaff.emulator.cards import Deck
from sielaff.engine.scene import Scene  # noqa: TC001
from sielaff.tools.report.page import figure, head, page
from sielaff.tools.report.sections import (
    motor_section,
    peak_rows,
    peaks_table,
    scene_section,
    sweep_section,
    tolerance_section,
)

__all__ = ["kind_report_html"]


def kind_report_html(deck: Deck, scene: Scene, command: str, at: float | None = None,
                     motor: dict | None = None, tolerances: dict | None = None) -> str:
    """The whole page for ``deck`` (a spec of another kind) in ``scene`` (module doc)."""
    from sielaff.design.kinds import is_slider_crank, kind_name
    from sielaff.tools.check.kinds import check_kind
    from sielaff.tools.common import describe_scene
    from sielaff.tools.kinds import turns_whole
    from sielaff.tools.plot import plot_data, render_png

    m = deck.mechanism
    whole = turns_whole(m, scene.branch)
    effects = describe_scene(scene, m.units) or "no effect but the constant crank speed " \
        "(no gravity, no loads, the open branch)"
    parts = head(os.path.basename(deck.path)) + [
        f'<p class="sub">A {html.escape(kind_name(m))} in {html.escape(m.units)} units; '
        f"scene: {html.escape(effects)}.</p>"]
    parts += scene_section(m, scene, whole)
    # a kind is read only if each dyad closes somewhere (else exit 2): always drawn
    parts += ["<h2>The linkage</h2>", *_drawing(deck, scene, at)]
    rows = peak_rows(deck, scene)
    if rows:
        parts += ["<h2>Peaks</h2>", peaks_table(rows)]
    if whole:
        parts.append("<h2>Figures</h2>")
        for d in plot_data(deck, None, scene).values():
            parts.append(figure(render_png(d), "image/png", d.title.split("\n")[0]))
    else:
        parts.append("<p>The crank cannot turn a whole revolution: the revolution figures "
                     "and the cycle work do not apply.</p>")
    parts.append("<h2>The check report</h2>")
    parts.append(f"<pre>{html.escape(check_kind(deck, scene)[0].text)}</pre>")
    parts.append("<h2>Balancing</h2>")
    parts.append(f"<pre>{html.escape(chr(10).join(_balance_lines(m, whole)))}</pre>"
                 if is_slider_crank(m) else
                 f"<p>No balancing is offered for a {html.escape(kind_name(m))}: the "
                 "counterweights that cancel a four-bar's shaking force (Berkof-Lowen) and "
                 "a slider-crank's crank counterweight are the two methods sielaff has.</p>")
    parts += sweep_section(deck.path, deck, scene)
    if motor is not None:
        parts += motor_section(deck, scene, motor)
    if tolerances is not None:
        parts += tolerance_section(deck, scene, tolerances)
    return page(parts, command)


def _drawing(deck: Deck, scene: Scene, at: float | None) -> list[str]:
    """The still drawing at ``at`` (or the default angle) and one animated cycle."""
    from sielaff.tools.plot.kinds import branch_words, kind_linkage_images

    images, drawn = kind_linkage_images(deck, at, scene.branch, animate=True)
    where = float(drawn[0])
    return [figure(images["linkage.png"], "image/png",
                   f"The linkage at THETA 2 = {where:.6g} deg ({branch_words(scene.branch)})"),
            figure(images["linkage.gif"], "image/gif",
                   "One cycle of the linkage (the angles it reaches)")]


def _balance_lines(m: Any, whole: bool) -> list[str]:
    """A slider-crank's counterweight (half the reciprocating primary) in words."""
    from sielaff.design.report import slider_balance_lines
    from sielaff.design.slider_balance import slider_balance

    if not whole:
        return ["not balanced: the crank cannot turn a whole revolution"]
    try:
        return slider_balance_lines(slider_balance(m))
    except ValueError as exc:
        return [f"not balanced: {exc}"]
