"""What each effect a scene calls for is, and does over one revolution, as the tools
show it (``check``'s text and JSON, the report's scene section).

Nothing here knows an effect: each declares its words (``summary``, ``describe``) and
its headline figures (``figure_outputs``, ``figures``) in its own module
(:class:`sielaff.engine.registry.Effect`); this runs them.  The figures are over one
revolution on the grid :func:`sielaff.engine.derived.revolution` (0 to 360 degrees, the
end left out: a mean over it is the periodic trapezoid rule), at the crank speed |TH2D|.
Any kind of linkage: its scene's effects are its model's, and their figures its outputs.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.engine.declare import Fact, fact_lines
from sielaff.engine.derived import revolution
from sielaff.engine.scene import Scene

__all__ = ["EffectFacts", "effect_facts", "effects_json", "effects_lines"]


@dataclass(frozen=True)
class EffectFacts:
    """One effect of a scene: its name, its few words, its parameters and its figures."""

    name: str
    summary: str
    parameters: list[Fact]
    figures: list[Fact]


def effect_facts(mechanism: Any, scene: Scene, figures: bool = True
                 ) -> list[EffectFacts]:
    """Each effect ``scene`` calls for, in the model's order, with its parameters and
    (with ``figures``, for a crank that turns fully) its figures over one revolution.

    Parameters
    ----------
    mechanism : Mechanism or another kind (SliderCrank, WattII, ..., Linkage)
        The design [its unit system's units].
    scene : Scene
        What acts on it, of its kind's Scene type [-].
    figures : bool
        Whether to compute the revolution's figures [-].
    """
    from sielaff.engine import analyze

    units = mechanism.units
    out = []
    grid = revolution()[:-1]
    for e in scene.effects:
        params = e.describe(scene, units) if e.describe else []
        figs: list[Fact] = []
        if figures and e.figures is not None and e.figure_outputs is not None:
            names = list(e.figure_outputs(scene))
            with warnings.catch_warnings(), np.errstate(all="ignore"):
                warnings.simplefilter("ignore")  # a figure says what did not converge
                r = analyze(mechanism, grid, names, scene=scene) if names else {}
            figs = e.figures(r, scene, units, abs(float(mechanism.TH2D)))
        out.append(EffectFacts(e.name, e.summary(scene, units) if e.summary else e.name,
                               params, figs))
    return out


def effects_lines(facts: list[EffectFacts], units: str, indent: str = "  ") -> list[str]:
    """The effects as text: a line naming each, then its parameters and figures."""
    lines = []
    for f in facts:
        lines.append(f"{indent}{f.name}: {f.summary}" if f.summary != f.name
                     else f"{indent}{f.name}")
        lines += fact_lines(f.parameters, units, indent + "  ")
        if f.figures:
            lines += fact_lines(f.figures, units, indent + "  ")
    return lines


def _json(facts: list[Fact], units: str) -> dict[str, Any]:
    from sielaff.quantities import unit_of

    out: dict[str, Any] = {}
    for f in facts:
        value: Any
        if f.kind is None or isinstance(f.value, str):
            value = f.value
        else:
            x = float(f.value)
            value = {"value": x if np.isfinite(x) else None, "unit": unit_of(f.kind, units)}
        target = out.setdefault(f.group, {}) if f.group else out
        key, k = f.label, 2
        while key in target:  # "from ... to ...": the second is "to"; keep both
            key, k = f"{f.label} {k}", k + 1
        target[key] = value
    return out


def effects_json(facts: list[EffectFacts], units: str) -> list[dict[str, Any]]:
    """The effects for a JSON report: name, summary, parameters and figures, each
    number ``{"value": x, "unit": "..."}`` in the unit system ``units``."""
    return [{"name": f.name, "summary": f.summary, "parameters": _json(f.parameters, units),
             "figures": _json(f.figures, units)} for f in facts]
