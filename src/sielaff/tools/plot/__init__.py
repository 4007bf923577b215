"""``sielaff plot DECK -o DIR``: the report's figures, from the modern engine.

One PNG per figure, named after the report's figure ("AN EXAMPLE PROBLEM",
Figures 12-16):

==================================== =====================================================
file                                 what
==================================== =====================================================
``fig12-driving-torque.png``         driving torque TORQ against THETA 2, the zero line,
                                     the cycle work (the integral of TORQ over a revolution)
``fig13-force-4-on-1.png``           polar diagram of the force of 4 on 1 (FOB, at O4)
``fig14-force-3-on-4-rel-link4.png`` polar diagram of the force of 3 on 4 relative to
                                     link 4 (direction DFB34 - ATH4), link 4 dotted
``force-2-on-1.png``                 polar diagram of the force of 2 on 1 (FOA, at O2)
``force-3-on-2.png``                 polar diagram of the force of 3 on 2 (FA32, at A)
``fig16-shaking-force.png``          polar diagram of the shaking force (SHAKE)
==================================== =====================================================

(The OCR of the report keeps the captions of Figures 13 and 14 only; the
text places the shaking force in Figure 16 and leaves 15 and 17 to the other
bearings, so those two are named for what they show.)

Polar diagrams carry THETA 2 marks around the curve, as the report's do.
A kinematics-only request (``only="kinematics"``) draws instead the link
angles, the angular velocities and accelerations of links 3 and 4, and the
velocity and acceleration magnitudes of pins A and B against THETA 2.

The deck's range cards say which crank angles are drawn: THZERO to THMAX of
every card (overlapping cards merge; separate ones leave a gap), sampled
every ``STEP`` degrees or at the card's DELTA if finer, whatever DELTA the
deck uses (the 1966 trailing sheet past THMAX is not drawn).  A card with
THZERO > THMAX is its single position.

``plot_data(deck, only=None)`` returns the data behind every figure
(:class:`PlotData`), and ``render(data, path)`` draws one with matplotlib's
Agg backend; ``write_plots(deck, directory, only)`` does both for a deck.
PNG files are written all or none (temporary files, renamed together at the end).
"""

from __future__ import annotations

import io
import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from sielaff.emulator.cards import Deck
from sielaff.engine import analyze
from sielaff.engine.derived import cycle_work
from sielaff.engine.scene import Scene  # noqa: TC001
from sielaff.quantities import KINDS, fmt, unit_of
from sielaff.tools.common import work_text
from sielaff.tools.plot.render import (  # noqa: F401 (part of this module's interface)
    _pyplot,
    _subtitle,
    overlapping,
    text_boxes,
    write_files,
)

__all__ = ["STEP", "PlotData", "plot_data", "render", "sample_angles", "write_plots"]

#: Largest sampling step, degrees.
STEP = 0.5
#: Most points drawn per merged range (a tiny DELTA over a wide range is thinned).
MAX_POINTS = 20_000


@dataclass
class PlotData:
    """The data behind one figure.

    ``kind`` is ``"line"`` (``series`` against ``ath2``) or ``"polar"``
    (magnitude ``r`` in direction ``theta`` degrees, point by point with
    ``ath2``).  NaN in ``ath2`` separates disjoint ranges.  ``marks`` are
    THETA 2 values labelled on a polar curve, ``mark_theta``/``mark_r``
    where they fall.  ``notes`` are extra legend lines; ``points`` the
    deck's own positions (THETA 2, value) for a line plot.
    """

    name: str
    title: str
    kind: str
    ath2: np.ndarray
    xlabel: str
    ylabel: str
    series: dict[str, np.ndarray] = field(default_factory=dict)
    theta: np.ndarray | None = None
    r: np.ndarray | None = None
    marks: np.ndarray | None = None
    mark_theta: np.ndarray | None = None
    mark_r: np.ndarray | None = None
    notes: list[str] = field(default_factory=list)
    points: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    link_outline: bool = False
    zero_line: bool = False
    #: the unit of a polar figure's magnitude (its rings)
    r_unit: str = "lb"

    @property
    def filename(self) -> str:
        return self.name + ".png"


# --------------------------------------------------------------------------
# Which crank angles
# --------------------------------------------------------------------------


def _intervals(deck: Deck) -> list[tuple[float, float, float]]:
    """Merged (start, stop, step) intervals of the deck's range cards.

    A range that samples a whole revolution at its DELTA (THMAX - THZERO + DELTA >= 360,
    as the example's 10 to 360 by 10) is drawn over the whole revolution, so polar curves
    close and the torque curve has no gap: from a multiple of 360 at either end if there
    is one (the example: 0 to 360), else from THZERO.
    """
    spans = []
    for thzero, delta, thmax in deck.ranges:
        step = min(STEP, delta) if delta > 0 else STEP
        spans.append((thzero, max(thzero, thmax), step, max(delta, 0.0)))
    spans.sort()
    merged: list[list[float]] = []
    for a, b, step, delta in spans:
        if merged and a <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], b)
            merged[-1][2] = min(merged[-1][2], step)
            merged[-1][3] = max(merged[-1][3], delta)
        else:
            merged.append([a, b, step, delta])
    out = []
    for a, b, step, delta in merged:
        if b - a < 360.0 <= b - a + delta + 1e-9:
            if b % 360.0 == 0.0:
                a = b - 360.0
            else:
                b = a + 360.0
        out.append((a, b, step))
    return out


def _segments(deck: Deck) -> list[np.ndarray]:
    out = []
    for a, b, step in _intervals(deck):
        n = min(MAX_POINTS, math.ceil((b - a) / step - 1e-9) + 1) if b > a else 1
        out.append(np.linspace(a, b, n))
    return out


def sample_angles(deck: Deck) -> np.ndarray:
    """The crank angles drawn (degrees), NaN between disjoint ranges."""
    return _join(_segments(deck))


def _join(parts: list[np.ndarray]) -> np.ndarray:
    out: list[np.ndarray] = []
    for k, part in enumerate(parts):
        if k:
            out.append(np.array([np.nan]))
        out.append(np.asarray(part, dtype=float))
    return np.concatenate(out) if out else np.array([])


def _evaluate(deck: Deck, names: list[str], scene: Scene
              ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    segs = _segments(deck)
    results = [analyze(deck.mechanism, seg, names, scene=scene) for seg in segs]
    return _join(segs), {n: _join([r[n] for r in results]) for n in names}


def _mark_angles(deck: Deck) -> np.ndarray:
    """THETA 2 marks for polar curves: a round spacing giving at most 12 marks."""
    spans = _intervals(deck)
    total = sum(b - a for a, b, _ in spans)
    spacing = next((s for s in (1, 2, 5, 10, 15, 30, 45, 90) if total / s <= 12), None)
    if spacing is None:  # a range of many revolutions: a power of ten
        spacing = 10.0 ** math.ceil(math.log10(total / 12))
    marks = []
    for a, b, _ in spans:
        k0 = math.ceil(a / spacing - 1e-9)
        k1 = math.floor(b / spacing + 1e-9)
        marks.extend(k * spacing for k in range(k0, k1 + 1))
    if not marks:
        marks = [a for a, _, _ in spans]
    return np.array(sorted(set(float(m) for m in marks)))


def _deck_points(deck: Deck) -> np.ndarray | None:
    """The deck's own positions THZERO, THZERO + DELTA, ... <= THMAX, if not too many."""
    pts: list[float] = []
    for thzero, delta, thmax in deck.ranges:
        if delta <= 0 or thzero > thmax:
            pts.append(thzero)
            continue
        n = math.floor((thmax - thzero) / delta + 1e-9) + 1
        if len(pts) + n > 100:
            return None
        pts.extend(thzero + k * delta for k in range(n))
    return np.array(pts)


# --------------------------------------------------------------------------
# The figures' data
# --------------------------------------------------------------------------

POLAR_FIGURES = (
    # name, title, legend, magnitude, direction, relative to ATH4?
    ("fig13-force-4-on-1", "Fig. 13  Polar diagram of the force of 4 on 1 (FOB, at O4)",
     "F 4 ON 1 (FOB)", "FOB", "DFOB", False),
    ("fig14-force-3-on-4-rel-link4",
     "Fig. 14  Polar diagram of the force of 3 on 4 (FB34, at B), relative to link 4",
     "F 3 ON 4 (FB34)", "FB34", "DFB34", True),
    ("force-2-on-1", "Polar diagram of the force of 2 on 1 (FOA, at O2)",
     "F 2 ON 1 (FOA)", "FOA", "DFOA", False),
    ("force-3-on-2", "Polar diagram of the force of 3 on 2 (FA32, at A)",
     "F 3 ON 2 (FA32)", "FA32", "DFA32", False),
    ("fig16-shaking-force", "Fig. 16  Polar diagram of the shaking force (SHAKE)",
     "SHAKE", "SHAK", "DSHAK", False),
)



def _turns_fully(m: Any) -> bool:
    from sielaff.engine import linkage_class

    return bool(linkage_class(m).turns_fully)


def _break_wraps(y):
    """``y`` [deg] with NaN where it jumps by more than 180 deg from the last position
    (a link angle wrapping a revolution), so the line breaks there instead of being
    drawn across the figure."""
    y = np.array(y, dtype=float)
    with np.errstate(invalid="ignore"):
        jump = np.abs(np.diff(y)) > 180.0
    y[1:][jump] = np.nan
    return y


KINEMATIC_FIGURES = (
    # name, title, y label, [(listing name, legend label)]
    ("kin-link-angles", "Angles of links 3 and 4, and the transmission angle",
     "angle (deg)", [("ATH3", "THETA 3 (link 3)"), ("ATH4", "THETA 4 (link 4)"),
                     ("GAMMA", "transmission angle GAMMA")]),
    ("kin-angular-velocity", "Angular velocities of links 3 and 4", "angular velocity ({rate})",
     [("TH3D", "ANG VEL 3 (TH3D)"), ("TH4D", "ANG VEL 4 (TH4D)")]),
    ("kin-angular-acceleration", "Angular accelerations of links 3 and 4",
     "angular acceleration ({angular acceleration})",
     [("TH3DD", "ANG ACC 3 (TH3DD)"), ("TH4DD", "ANG ACC 4 (TH4DD)")]),
    ("kin-pin-velocity", "Velocities of pins A and B", "speed ({speed})",
     [("VA", "VEL A"), ("VB", "VEL B")]),
    ("kin-pin-acceleration", "Accelerations of pins A and B", "acceleration ({acceleration})",
     [("AA", "ACC A"), ("AB", "ACC B")]),
)

XLABEL = "THETA 2, crank angle (deg)"


def plot_data(deck: Deck, only: str | None = None, scene: Scene | None = None
              ) -> dict[str, PlotData]:
    """The data of every figure for ``deck``, keyed by file stem (see module doc).

    ``only="kinematics"`` gives the kinematic figures instead of the force ones.
    """
    from sielaff.engine import scene_for
    from sielaff.mechanism import Mechanism

    four_bar = isinstance(deck.mechanism, Mechanism)
    scene = scene or scene_for(deck.mechanism)()
    if only not in (None, "kinematics"):
        raise ValueError(f"only={only!r}: the choices are None and 'kinematics'")
    sub = _subtitle(deck, scene)
    system = deck.mechanism.units
    units = {kind: unit_of(kind, system) for kind in KINDS}
    out: dict[str, PlotData] = {}
    from sielaff.tools.plot import kinds

    kinematic = KINEMATIC_FIGURES if four_bar else kinds.kinematic_figures(deck.mechanism)
    polar = POLAR_FIGURES if four_bar else kinds.polar_figures(deck.mechanism)
    if only == "kinematics":
        names = [n for fig in kinematic for n, _ in fig[3]]
        ath2, v = _evaluate(deck, names, scene)
        for name, title, ylabel, curves in kinematic:
            out[name] = PlotData(name, f"{title}\n{sub}", "line", ath2, XLABEL,
                                 ylabel.format_map(units),
                                 series={label: _break_wraps(v[n]) if n.startswith("ATH")
                                         else v[n] for n, label in curves})
        return out

    ath2, v = _evaluate(deck, ["TORQ"], scene)
    from sielaff.tools.kinds import turns_whole

    if _turns_fully(deck.mechanism) if four_bar else turns_whole(deck.mechanism, scene.branch):
        work, abs_work = cycle_work(deck.mechanism, scene=scene)
        work_notes = [f"cycle work \u222e TORQ d\u03b8\u2082 = "
                      f"{work_text(work, abs_work, system)}\n(\u222e |TORQ| d\u03b8\u2082 = "
                      f"{fmt(abs_work, 'work', system, '.0f')})"]
    else:  # no revolution, no cycle: a NaN would be the only number to print
        work_notes = ["no cycle work: the crank swings between toggles and makes no "
                      "revolution\n(TORQ grows without bound toward each toggle)"]
    fig12 = PlotData(
        "fig12-driving-torque", f"Fig. 12  Driving torque against THETA 2\n{sub}", "line",
        ath2, XLABEL, f"driving torque TORQ ({units['torque']})",
        series={"driving torque TORQ": v["TORQ"]},
        zero_line=True,
        notes=work_notes)
    pts = _deck_points(deck)
    if pts is not None:
        fig12.points["deck positions (listing sheets)"] = (
            pts, analyze(deck.mechanism, pts, ["TORQ"], scene=scene)["TORQ"])
    out[fig12.name] = fig12

    names = sorted({n for fig in polar for n in fig[3:5]} | ({"ATH4"} if four_bar else set()))
    ath2, v = _evaluate(deck, names, scene)
    marks = _mark_angles(deck)
    mv = analyze(deck.mechanism, marks, names, scene=scene)
    for name, title, legend, mag, direction, relative in polar:
        theta, mark_theta = v[direction], mv[direction]
        if relative:
            theta = np.mod(theta - v["ATH4"], 360.0)
            mark_theta = np.mod(mark_theta - mv["ATH4"], 360.0)
        out[name] = PlotData(
            name, f"{title}\n{sub}", "polar", ath2, "direction (deg)",
            f"{legend}, {units['force']}", r_unit=units["force"],
            theta=theta, r=v[mag], marks=marks, mark_theta=mark_theta, mark_r=mv[mag],
            link_outline=relative)
    return out


# --------------------------------------------------------------------------
# Drawing
# --------------------------------------------------------------------------


def _draw_line(plt, d: PlotData):
    fig, ax = plt.subplots(figsize=(9, 5.6), dpi=110, layout="constrained")
    colors = ("tab:blue", "tab:red", "tab:green", "tab:purple")
    single = np.count_nonzero(np.isfinite(d.ath2)) == 1
    for (label, y), color in zip(d.series.items(), colors):
        ax.plot(d.ath2, y, color=color, lw=1.6, label=label, marker="o" if single else None)
    for (label, (x, y)), color in zip(d.points.items(), colors):
        ax.plot(x, y, "o", ms=3.5, color=color, mfc="white", mew=1.0, label=label)
    ys = np.concatenate([np.ravel(y) for y in d.series.values()])
    ys = ys[np.isfinite(ys)]
    if d.zero_line or (ys.size and ys.min() < 0.0 < ys.max()):
        ax.axhline(0.0, color="black", lw=0.9, zorder=2.5)
    for note in d.notes:
        ax.plot([], [], " ", label=note)
    finite = d.ath2[np.isfinite(d.ath2)]
    lo, hi = float(finite.min()), float(finite.max())
    if 90 <= hi - lo <= 1080:
        step = 30 if hi - lo <= 400 else 90
        ax.set_xticks(np.arange(math.ceil(lo / step) * step, hi + 1e-9, step))
    if hi > lo:
        ax.set_xlim(lo, hi)
    ax.set_xlabel(d.xlabel)
    ax.set_ylabel(d.ylabel)
    ax.set_title(d.title, fontsize=11)
    ax.grid(True, color="0.85", lw=0.6)
    # outside the axes, in room the constrained layout reserves: clear of every tick label
    fig.legend(loc="outside lower center", ncol=3, frameon=False, fontsize=9)
    return fig


# Polar figure geometry: fixed, so label placement can work in pixels.
_POLAR_SIZE, _POLAR_DPI = (8.0, 8.4), 110
_POLAR_AXES = (0.11, 0.13, 0.78, 0.78 * 8.0 / 8.4)  # left, bottom, width, height (square)
_LABEL_PT = 8


def _mark_groups(d: PlotData) -> list[tuple[str, float, float]]:
    """(label, direction rad, magnitude) per mark; marks at one point share a label."""
    groups: list[list] = []
    for t2, t, r in zip(d.marks, d.mark_theta, d.mark_r):
        if not (np.isfinite(t) and np.isfinite(r)):
            continue
        for g in groups:
            if abs(g[2] - r) <= 1e-9 * max(1.0, r) and abs((g[1] - t + 180) % 360 - 180) < 1e-7:
                g[0].append(t2)
                break
        else:
            groups.append([[t2], t, r])
    return [("/".join(f"{v:g}" for v in g[0]), math.radians(g[1]), g[2]) for g in groups]


#: Marks closer than this on the page [px] share one label (near the pole several
#: crank angles land on one spot; separate labels there cannot all sit by their marks).
_CROWDED_PX = 9.0


def _merge_crowded(groups: list[tuple[str, float, float]], scale: float
                   ) -> list[tuple[str, float, float]]:
    """``groups`` with marks closer than :data:`_CROWDED_PX` on the page merged: one label
    "180/270" at the first of them (the order of the marks: THETA 2 ascending)."""
    out: list[list] = []
    for text, t, r in groups:
        x, y = r * math.cos(t) * scale, r * math.sin(t) * scale
        for g in out:
            if math.hypot(g[3] - x, g[4] - y) < _CROWDED_PX:
                g[0].append(text)
                break
        else:
            out.append([[text], t, r, x, y])
    return [("/".join(g[0]), g[1], g[2]) for g in out]


def _ring_every(plt, fig, ticks: np.ndarray, scale: float, angle_deg: float, unit: str
                ) -> int:
    """Label every n-th ring so that the labels, laid along the ring-label direction, do
    not run into each other (their extent along it against the rings' spacing)."""
    from matplotlib.font_manager import FontProperties

    if len(ticks) < 2:
        return 1
    renderer = fig.canvas.get_renderer()
    w, h, _ = renderer.get_text_width_height_descent(f"{ticks[-1]:g} {unit}",
                                                    FontProperties(size=8), ismath=False)
    a = math.radians(angle_deg)
    extent = w * abs(math.cos(a)) + h * abs(math.sin(a)) + 4.0
    spacing = float(ticks[1] - ticks[0]) * scale
    return max(1, math.ceil(extent / spacing)) if spacing > 0 else 1


def _place_labels(marks, curve_xy: np.ndarray, obstacles=(),
                  sizes=None) -> list[tuple[float, float, bool]]:
    """Pixel offsets (dx, dy, leader?) for labels of ``marks`` [(text, x px, y px)].

    Each label goes where it overlaps no other label, ``obstacles`` box or
    mark and as little of the curve as possible, preferably close to its
    mark and outward.  ``sizes`` are the labels' (width, height) in pixels as
    the renderer measures them (estimated from the font size if not given).
    """
    placed: list[tuple[float, float, float, float]] = list(obstacles)  # x0, y0, x1, y1
    dots = np.array([(x, y) for _, x, y in marks]).reshape(-1, 2)
    out = []
    for k_mark, (text, x, y) in enumerate(marks):
        if sizes is not None:
            w, h = sizes[k_mark][0] + 4.0, sizes[k_mark][1] + 3.0
        else:
            h = _LABEL_PT * _POLAR_DPI / 72.0 + 2.0
            w = 0.62 * h * len(text) + 4.0
        outward = math.atan2(y, x) if math.hypot(x, y) > 1 else math.pi / 4
        best = None
        for dist in (7.0, 14.0, 24.0, 36.0, 52.0, 72.0, 96.0):
            for k in range(16):
                phi = outward + k * math.pi / 8
                ext = 0.5 * w * abs(math.cos(phi)) + 0.5 * h * abs(math.sin(phi))
                cx, cy = x + (dist + ext) * math.cos(phi), y + (dist + ext) * math.sin(phi)
                box = (cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2)
                hits = sum(1 for b in placed if not (box[2] < b[0] or b[2] < box[0]
                                                     or box[3] < b[1] or b[3] < box[1]))
                inside = ((dots[:, 0] > box[0] - 3) & (dots[:, 0] < box[2] + 3)
                          & (dots[:, 1] > box[1] - 3) & (dots[:, 1] < box[3] + 3))
                near = ((curve_xy[:, 0] > box[0] - 1) & (curve_xy[:, 0] < box[2] + 1)
                        & (curve_xy[:, 1] > box[1] - 1) & (curve_xy[:, 1] < box[3] + 1))
                turn = abs((phi - outward + math.pi) % (2 * math.pi) - math.pi)
                score = (1000 * hits + 300 * int(inside.sum()) + 3 * int(near.sum())
                         + dist + 4 * turn)
                if best is None or score < best[0]:
                    best = (score, cx - x, cy - y, box, dist)
        _, dx, dy, box, dist = best
        placed.append(box)
        out.append((dx, dy, dist > 10))
    return out


def _rlabel_angle(th: np.ndarray, r: np.ndarray) -> float:
    """Direction (deg) for the ring labels: the one the curve stays furthest from."""
    ok = np.isfinite(th) & np.isfinite(r)
    th, r = th[ok], r[ok]
    best, best_r = 100.0, math.inf
    for a in (100.0, 80.0, 125.0, 55.0, 145.0, 35.0, 170.0, 10.0, 190.0, 350.0, 215.0, 325.0,
              235.0, 305.0, 260.0, 280.0):
        near = np.abs((np.degrees(th) - a + 180.0) % 360.0 - 180.0) < 15.0
        reach = float(r[near].max()) if near.any() else 0.0
        if reach < best_r - 1e-9:
            best, best_r = a, reach
    return best


def _draw_polar(plt, d: PlotData):
    fig = plt.figure(figsize=_POLAR_SIZE, dpi=_POLAR_DPI)
    ax = fig.add_axes(_POLAR_AXES, projection="polar")
    th = np.radians(d.theta)
    ax.plot(th, d.r, color="tab:blue", lw=1.5, zorder=3, label=d.ylabel)
    finite = d.r[np.isfinite(d.r)]
    rmax = float(finite.max()) if finite.size and finite.max() > 0 else 1.0
    rlim = rmax * 1.1
    if d.link_outline:
        # Link 4 seen from pin B (the origin): it runs back toward O4, at 180 deg.
        w, length = 0.05 * rlim, 0.6 * rlim
        xs = np.concatenate([np.linspace(0, -length, 60), np.full(20, -length),
                             np.linspace(-length, 0, 60)])
        ys = np.concatenate([np.full(60, w), np.linspace(w, -w, 20), np.full(60, -w)])
        arc = np.linspace(-np.pi / 2, np.pi / 2, 30)
        xs = np.concatenate([xs, w * np.cos(arc)])
        ys = np.concatenate([ys, w * np.sin(arc)])
        ax.plot(np.arctan2(ys, xs), np.hypot(xs, ys), ls=":", color="0.25", lw=1.4, zorder=2,
                label="link 4 (B at the centre, O4 at 180\u00b0)")
    # Label placement in pixels: the axes is a circle of known radius.
    radius_px = 0.5 * _POLAR_AXES[2] * _POLAR_SIZE[0] * _POLAR_DPI
    scale = radius_px / rlim
    groups = _merge_crowded(_mark_groups(d), scale)
    ax.plot([t for _, t, _ in groups], [r for _, _, r in groups], "o", ms=4.5,
            color="tab:red", zorder=4, label="THETA 2 (deg) at the marks")
    ok = np.isfinite(th) & np.isfinite(d.r)
    curve = np.column_stack((d.r[ok] * np.cos(th[ok]), d.r[ok] * np.sin(th[ok]))) * scale
    marks = [(text, r * math.cos(t) * scale, r * math.sin(t) * scale) for text, t, r in groups]
    ax.set_ylim(0, rlim)
    if d.link_outline:
        ring_angle = _rlabel_angle(np.concatenate([th, np.radians([180.0])]),
                                   np.concatenate([d.r, [rlim]]))
    else:
        ring_angle = _rlabel_angle(th, d.r)
    ax.set_rlabel_position(ring_angle)
    ticks = np.array([v for v in ax.get_yticks() if 0.0 <= v <= 0.9 * rlim])
    every = _ring_every(plt, fig, ticks, scale, ring_angle, d.r_unit)
    step = float(ticks[1] - ticks[0]) if len(ticks) > 1 else 1.0

    def ring_label(v: float, _: Any) -> str:
        # none in the outer tenth (it would reach the title or the angle labels); every
        # n-th where the labels would run into each other
        if v > 0.9 * rlim or round(v / step) % every:
            return ""
        return f"{v:g} {d.r_unit}"

    ax.yaxis.set_major_formatter(plt.FuncFormatter(ring_label))
    ax.tick_params(axis="y", labelsize=8, colors="0.3")
    ax.set_xticks(np.radians(np.arange(0, 360, 45)))
    ax.grid(True, color="0.82", lw=0.6)
    fig.text(0.5, 0.975, d.title, ha="center", va="top", fontsize=11)
    around = ("from link 4's line O4 to B (DFB34 - ATH4)" if d.link_outline
              else "from the +x axis (O2 to O4)")
    fig.text(0.5, 0.075,
             f"force magnitude in {d.r_unit} (rings); direction in degrees {around}, CCW",
             ha="center", va="center", fontsize=9)
    fig.legend(loc="lower center", bbox_to_anchor=(0.5, 0.01), ncol=3, frameon=False,
               fontsize=9)
    # Every text drawn so far (ring and angle labels, titles, legend) is an obstacle, in
    # pixels about the polar centre, as the renderer measures it.
    cx, cy = ax.transData.transform((0.0, 0.0))
    static = [(b[0] - cx, b[1] - cy, b[2] - cx, b[3] - cy) for _, b in text_boxes(fig)]
    renderer = fig.canvas.get_renderer()
    from matplotlib.font_manager import FontProperties
    from matplotlib.text import Text

    font = FontProperties(size=_LABEL_PT)
    sizes = [renderer.get_text_width_height_descent(text, font, ismath=False)[:2]
             for text, _, _ in marks]
    to_pt = 72.0 / _POLAR_DPI
    labels = []
    for (text, t, r), (dx, dy, leader) in zip(groups, _place_labels(marks, curve, static,
                                                                    sizes)):
        labels.append(ax.annotate(
            text, (t, r), xytext=(dx * to_pt, dy * to_pt), textcoords="offset points",
            fontsize=_LABEL_PT, color="tab:red", zorder=5, ha="center", va="center",
            arrowprops=dict(arrowstyle="-", color="tab:red", lw=0.6, shrinkA=0,
                            shrinkB=3) if leader else None))
    measured = text_boxes(fig)
    if overlapping(measured):
        # Rare: the estimate of a box was off.  Put the labels that collide on the curve's
        # outside, further out, with a leader, avoiding everything measured now.  The
        # figure is measured again (a whole draw) only after a label has moved.
        for label in labels:
            others = [b for t, b in measured if t != label.get_text()]
            mine = Text.get_window_extent(label, renderer)
            if not any(mine.x0 < b[2] and b[0] < mine.x1 and mine.y0 < b[3] and b[1] < mine.y1
                       for b in others):
                continue
            k = [g[0] for g in groups].index(label.get_text())
            boxes = [(b[0] - cx, b[1] - cy, b[2] - cx, b[3] - cy) for b in others]
            (dx, dy, _), = _place_labels([marks[k]], curve, boxes, [sizes[k]])
            label.set_position((dx * to_pt, dy * to_pt))
            measured = text_boxes(fig)
    return fig


def render_png(d: PlotData) -> bytes:
    """The PNG image of one figure."""
    plt = _pyplot()
    fig = _draw_polar(plt, d) if d.kind == "polar" else _draw_line(plt, d)
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png")
    finally:
        plt.close(fig)
    return buf.getvalue()


def render(d: PlotData, path: str) -> None:
    """Draw ``d`` and write it to ``path`` as a PNG (atomically)."""
    write_files({path: render_png(d)})


def write_plots(deck: Deck, directory: str, only: str | None = None,
                scene: Scene | None = None) -> list[str]:
    """Write every figure of ``deck`` into ``directory`` (created if needed), all of them or
    none; the paths."""
    _pyplot()  # fail before any work if matplotlib is missing
    images = {os.path.join(directory, d.filename): render_png(d)
              for d in plot_data(deck, only, scene).values()}
    write_files(images)
    return list(images)


def _file_names(args, mechanism: Any = None) -> list[str]:
    """The files ``plot`` will write for ``args`` (checked before any work but reading the
    deck: another kind's figures are its own)."""
    from sielaff.mechanism import Mechanism
    from sielaff.tools.plot import kinds

    if args.linkage or args.animate:
        return (["linkage.png"] + (["linkage.gif"] if args.animate else [])
                + (["bearings.png"] if args.bearings else []))
    if args.bearings:
        return ["bearings.png"]
    four_bar = mechanism is None or isinstance(mechanism, Mechanism)
    if args.only == "kinematics":
        figs = KINEMATIC_FIGURES if four_bar else kinds.kinematic_figures(mechanism)
        return [f"{fig[0]}.png" for fig in figs]
    polar = POLAR_FIGURES if four_bar else kinds.polar_figures(mechanism)
    return ["fig12-driving-torque.png"] + [f"{fig[0]}.png" for fig in polar]


def cmd_plot(args) -> int:
    """``sielaff plot DECK -o DIR [--only kinematics]``: writes the PNGs, lists them on stdout."""
    import sys

    from sielaff.tools.common import CommandError, load_scene, refuse_stdout

    refuse_stdout(args.output, "plot writes several PNG files into a folder")
    try:
        _pyplot()
    except ImportError as exc:
        raise CommandError(f"sielaff: {exc}") from None
    if not args.output:
        raise CommandError("sielaff: -o '': an empty folder name")
    drawing = args.linkage or args.animate
    if not drawing and (args.at is not None or args.point):
        raise CommandError(f"sielaff: {'--at' if args.at is not None else '--point'} draws "
                           "on the linkage: add --linkage")
    if getattr(args, "bearing_threshold", None) is not None and not args.bearings:
        raise CommandError("sielaff: --bearing-threshold is for the bearings drawing: add "
                           "--bearings")
    if os.path.exists(args.output) and not os.path.isdir(args.output):
        raise CommandError(f"sielaff: -o {args.output} is a file, not a folder: plot writes "
                           "several PNG files into a folder")
    from sielaff.tools.output import check_targets

    try:  # before any work: a folder where a figure goes, say
        check_targets([os.path.join(args.output, name) for name in _file_names(args)])
    except OSError as exc:
        raise CommandError(f"sielaff: {exc.filename}: {exc.strerror}") from None
    from sielaff.mechanism import Mechanism
    from sielaff.tools.kinds import other_kinds

    deck, scene = load_scene(args.deck, any_linkage=args.linkage or args.animate,
                             branch=args.branch, any_kind=True, kinds=other_kinds())
    other = not isinstance(deck.mechanism, Mechanism)
    if other:
        try:
            check_targets([os.path.join(args.output, n)
                           for n in _file_names(args, deck.mechanism)])
        except OSError as exc:
            raise CommandError(f"sielaff: {exc.filename}: {exc.strerror}") from None
        if args.bearings or args.point:
            raise CommandError(f"{args.deck}: {'--bearings' if args.bearings else '--point'} "
                               f"draws a four-bar's; this is a {deck.mechanism.KIND}")
    paths: list[str] = []
    if (args.linkage or args.animate) and other:
        from sielaff.tools.plot.kinds import write_kind_linkage

        paths += write_kind_linkage(deck, args.output, args.at, scene.branch, args.animate)
    elif args.linkage or args.animate:  # with --bearings too: both drawings
        from sielaff.tools.plot.linkage import write_linkage

        paths += write_linkage(deck, args.output, args.at, args.point, scene.branch,
                               args.animate)
    if args.bearings:
        from sielaff.tools.plot.bearings import write_bearings

        try:
            paths += write_bearings(deck, args.output, scene,
                                    getattr(args, "bearing_threshold", None))
        except ValueError as exc:
            raise CommandError(f"{args.deck}: {exc}") from None
    if not (args.bearings or args.linkage or args.animate):
        paths = write_plots(deck, args.output, args.only, scene)
    for path in paths:
        print(path)
    sys.stdout.flush()
    return 0
