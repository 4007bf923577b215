"""``sielaff plot DECK --bearings``: bearings.png, the load on each member at each pin,
relative to the member (the report's Fig. 14 for every pin), with the arcs never loaded
shaded (oil-groove candidates; :mod:`sielaff.design.bearings`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from sielaff.engine.scene import Scene

import io
import os

import numpy as np

from sielaff.emulator.cards import Deck
from sielaff.tools.plot.render import _pyplot, _subtitle, write_files


def bearings_figure(deck: Deck, scene: Scene, threshold: float | None = None):
    """The figure (2 rows of 4 polar axes: each pin's two members) and the pins: the
    same computation as ``check``'s bearings section (design.bearings, its default
    positions), ``threshold`` its threshold (the default when None)."""
    from sielaff.design.bearings import THRESHOLD, bearings
    from sielaff.quantities import unit

    plt = _pyplot()
    threshold = THRESHOLD if threshold is None else threshold
    pins = bearings(deck.mechanism, scene=scene, threshold=threshold)
    force = unit("FA32", deck.mechanism.units)
    fig, axes = plt.subplots(2, 4, subplot_kw={"projection": "polar"}, figsize=(13, 8.4),
                             dpi=110)
    for col, pin in enumerate(pins.values()):
        for row, member in enumerate(pin.members):
            ax = axes[row, col]
            d = np.radians(member.direction)
            ax.plot(d, pin.load, lw=1.2, color="C0")
            if threshold > 0.0:  # the loads inside this circle do not count
                ring = np.linspace(0.0, 2.0 * np.pi, 181)
                ax.plot(ring, np.full(ring.shape, threshold * pin.peak), lw=0.8, ls=":",
                        color="0.4")
            top = pin.peak * 1.05
            for a, b in member.unloaded:
                w = np.radians((b - a) % 360.0)
                ax.bar(np.radians(a) + w / 2, top, width=w, color="C2", alpha=0.2,
                       edgecolor="none")
            ax.set_ylim(0, top)
            ax.set_yticks([pin.peak / 2, pin.peak])
            # each ring with its unit (three digits: a small load does not print as 0)
            ax.set_yticklabels([f"{pin.peak / 2:.3g} {force}", f"{pin.peak:.3g} {force}"],
                               fontsize=7)
            ax.set_xticks(np.radians([0, 90, 180, 270]))
            ax.set_xticklabels(["0", "90", "180", "270"], fontsize=7)
            ax.set_title(f"pin {pin.name}: load on the {member.name}", fontsize=9, pad=12)
    fig.suptitle("Bearing loads relative to each member (deg from its line; shaded: never "
                 f"loaded by {100 * threshold:g}% of the pin's peak or more, the dotted "
                 f"circle)\n{_subtitle(deck, scene)}", fontsize=10)
    fig.tight_layout(h_pad=3.0)
    return fig, pins


def write_bearings(deck: Deck, folder: str, scene: Scene,
                   threshold: float | None = None) -> list[str]:
    """bearings.png in ``folder``; ``threshold`` as for :func:`bearings_figure`."""
    fig, _ = bearings_figure(deck, scene, threshold)
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    _pyplot().close(fig)
    path = os.path.join(folder, "bearings.png")
    write_files({path: buf.getvalue()})
    return [path]
