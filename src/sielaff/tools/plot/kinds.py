"""``sielaff plot`` for a linkage of another kind than the four-bar: which figures it has
(a polar diagram of every pin force and the shaking force; the kinematic figures of its
links, pins and slides), and its drawing (the links between their pins, a ternary link
as a triangle, each slider as a block on its guide, the guide drawn)."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from sielaff.emulator.cards import Deck

__all__ = ["branch_words", "drawing_data", "kind_linkage_images", "kinematic_figures",
           "polar_figures", "write_kind_linkage"]


def _topology(m: Any) -> Any:
    from sielaff.engine import model_for

    return model_for(m).topology


def polar_figures(m: Any) -> tuple[tuple[str, str, str, str, str, bool], ...]:
    """(file stem, title, legend, magnitude, direction, relative) of each polar diagram:
    every pin's force, then the shaking force."""
    from sielaff.engine.joints import joints
    from sielaff.engine.linkage_model import _renamer

    topology = _topology(m)
    rename = _renamer(topology)
    pins, _ = joints(topology)
    out = []
    for j in pins:
        name = rename(j.name)
        on = "the frame" if j.on == 1 else f"link {j.on}"
        out.append((f"force-{name}", f"Polar diagram of the force of link {j.by} on {on} "
                    f"({name}, at {j.point})", f"F {j.by} ON {j.on} ({name})", name,
                    "D" + name, False))
    out.append(("shaking-force", "Polar diagram of the shaking force (SHAK)", "SHAK", "SHAK",
                "DSHAK", False))
    return tuple(out)


def kinematic_figures(m: Any) -> tuple[tuple[str, str, str, list[tuple[str, str]]], ...]:
    """(file stem, title, y label, [(output, legend)]) of each kinematic figure: the link
    angles, their rates and accelerations, the slides, the pins' speeds and
    accelerations."""
    from sielaff.engine import model_for
    from sielaff.engine.joints import joints
    from sielaff.engine.linkage_model import _moving_points, _renamer

    model = model_for(m)
    topology = model.topology
    rename = _renamer(topology)
    moving = [k for k in range(3, topology.links + 1)
              if f"TH{k}D" in model.outputs and not _fixed_slider(topology, k)]
    pins = [p for p in _moving_points(topology) if not p.startswith("G")]
    _, slides = joints(topology)
    figs: list[tuple[str, str, str, list[tuple[str, str]]]] = [
        ("kin-link-angles", "Angles of the links", "angle (deg)",
         [(f"ATH{k}", f"THETA {k} (link {k})") for k in moving]),
        ("kin-angular-velocity", "Angular velocities of the links",
         "angular velocity ({rate})", [(f"TH{k}D", f"ANG VEL {k}") for k in moving]),
        ("kin-angular-acceleration", "Angular accelerations of the links",
         "angular acceleration ({angular acceleration})",
         [(f"TH{k}DD", f"ANG ACC {k}") for k in moving]),
        ("kin-pin-velocity", f"Velocities of pins {', '.join(pins)}", "speed ({speed})",
         [(f"V{p}", f"VEL {p}") for p in pins]),
        ("kin-pin-acceleration", f"Accelerations of pins {', '.join(pins)}",
         "acceleration ({acceleration})", [(f"A{p}", f"ACC {p}") for p in pins])]
    if slides:
        figs.append(("kin-slide", "The slide: position along the guide", "position ({length})",
                     [(rename(f"S{s.label}"), f"S{s.label}") for s in slides]))
        figs.append(("kin-slide-rate", "The slide: rate along the guide", "speed ({speed})",
                     [(rename(f"VS{s.label}"), f"VS{s.label}") for s in slides]))
    return tuple(figs)


def _fixed_slider(topology: Any, k: int) -> bool:
    """Whether link k is a slider on the frame (it never turns: no angle to draw)."""
    from sielaff.engine.joints import joints

    return any(s.slider == k and s.guide == 1 for s in joints(topology)[1])


def drawing_data(deck: Deck, at: np.ndarray, branch: Any) -> dict[str, Any]:
    """What a drawing of another kind needs at the crank angles ``at`` [deg]: each point's
    (x, y) arrays (``points``), the links as polygons of point names with their labels
    (``links``), each slide's block centre, direction and guide (``slides``), and the
    frame's pivots."""
    from sielaff.engine import AssemblyWarning, analyze, model_for
    from sielaff.engine.joints import owner
    from sielaff.engine.linkage_model import _moving_points
    from sielaff.linkage import PRR, RPR, RRP, RRR

    m = deck.mechanism
    model = model_for(m)
    topology = model.topology
    names = [p for p in _moving_points(topology)]
    wanted = [f"{c}{p}" for p in names for c in "XY"] + [f"ATH{k}" for k in
                                                         range(3, topology.links + 1)]
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", AssemblyWarning)
        r = analyze(m, at, wanted, scene=_scene(m, branch))
    zero = np.zeros_like(np.asarray(at, dtype=float))
    points: dict[str, tuple[np.ndarray, np.ndarray]] = {"O2": (zero, zero)}
    values = m.as_dict()
    for p in topology.pivots:
        points[p.name] = tuple(zero + (values[v] if isinstance(v, str) else v)
                               for v in (p.x, p.y))  # type: ignore[assignment]
    for p in names:
        points[p] = (np.asarray(r[f"X{p}"]), np.asarray(r[f"Y{p}"]))
    home = owner(topology)
    on_link: dict[int, list[str]] = {}
    for name, k in home.items():
        on_link.setdefault(k, []).append(name)
    words = model.link_names
    links: list[tuple[list[str], str]] = [(["O2", topology.crank.pin], f"link 2 ({words[2]})")]
    slides = []
    for i, d in enumerate(topology.dyads):
        n = 3 + 2 * i
        if isinstance(d, RRR):
            links.append(([d.p, d.joint] + [q for q in on_link.get(n, []) if q != d.joint],
                          f"link {n} ({words[n]})"))
            links.append(([d.q, d.joint] + [q for q in on_link.get(n + 1, []) if q != d.joint],
                          f"link {n + 1} ({words[n + 1]})"))
        elif isinstance(d, RRP | PRR):
            known = d.p if isinstance(d, RRP) else d.q
            rod = n if isinstance(d, RRP) else n + 1
            slider = n + 1 if isinstance(d, RRP) else n
            links.append(([known, d.joint], f"link {rod} ({words[rod]})"))
            slides.append({"at": d.joint, "link": slider, "label": f"link {slider} "
                           f"({words[slider]})", "guide": d.guide, "moving": d.guide.link != 1})
        elif isinstance(d, RPR):
            slides.append({"at": d.p, "link": n, "label": f"link {n} ({words[n]})",
                           "lever": n + 1, "pivot": d.q,
                           "lever_label": f"link {n + 1} ({words[n + 1]})"})
    for s in slides:
        k = s["lever"] if "lever" in s else s["link"]
        s["angle"] = np.asarray(r[f"ATH{k}"])
    return {"points": points, "links": links, "slides": slides,
            "pivots": ["O2"] + [p.name for p in topology.pivots], "title": topology.title}


def _scene(m: Any, branch: Any) -> Any:
    from sielaff.engine import scene_for

    return scene_for(m)(branch=branch)


def draw(ax: Any, data: dict[str, Any], k: int, alpha: float, labelled: bool) -> list:
    """The links, blocks and guides at angle index ``k``: their artists."""
    colors = ("tab:red", "tab:green", "tab:purple", "tab:blue", "tab:brown", "tab:olive")
    pts = {n: (float(x[k]), float(y[k])) for n, (x, y) in data["points"].items()}
    out = []
    for i, (names, label) in enumerate(data["links"]):
        xy = [pts[n] for n in names]
        if len(xy) > 2:  # a ternary link: its triangle
            xy = xy + [xy[0]]
        out += ax.plot([p[0] for p in xy], [p[1] for p in xy], color=colors[i % len(colors)],
                       lw=4, solid_capstyle="round", alpha=alpha,
                       label=label if labelled else None)
    scale = max((abs(v) for p in pts.values() for v in p if np.isfinite(v)), default=1.0)
    for s in data["slides"]:
        cx, cy = pts[s["at"]]
        a = np.radians(float(s["angle"][k]))
        u = np.array([np.cos(a), np.sin(a)])
        if "lever" in s:  # the lever through its pivot, past the block
            px, py = pts[s["pivot"]]
            reach = 1.3 * max(np.hypot(cx - px, cy - py), 0.2 * scale)
            out += ax.plot([px, px + reach * u[0]], [py, py + reach * u[1]],
                           color="tab:purple", lw=3, alpha=alpha,
                           label=s["lever_label"] if labelled else None)
        out += _block(ax, (cx, cy), u, 0.08 * scale, alpha, s["label"] if labelled else None)
    return out


def _block(ax: Any, c: tuple[float, float], u: np.ndarray, size: float, alpha: float,
           label: Any) -> list:
    """A slider block: a rectangle 2 size long along ``u``, 1.2 size across."""
    n = np.array([-u[1], u[0]])
    corners = [np.array(c) + sx * size * u + sy * 0.6 * size * n
               for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1), (-1, -1))]
    return ax.plot([p[0] for p in corners], [p[1] for p in corners], color="tab:blue", lw=2.5,
                   alpha=alpha, label=label)


def guides(ax: Any, data: dict[str, Any]) -> list:
    """The guides fixed to the frame: a line through the slider's path."""
    out = []
    for s in data["slides"]:
        if "lever" in s or s["moving"]:
            continue
        x, y = data["points"][s["at"]]
        ok = np.isfinite(x)
        if not ok.any():
            continue
        a = np.radians(float(s["angle"][ok][0]))
        u = np.array([np.cos(a), np.sin(a)])
        t = x[ok] * u[0] + y[ok] * u[1]
        lo, hi = float(t.min()), float(t.max())
        pad = 0.15 * (hi - lo + 1e-9)
        x0, y0 = float(x[ok][0]), float(y[ok][0])
        t0 = x0 * u[0] + y0 * u[1]
        base = np.array([x0, y0]) - t0 * u
        ends = [base + (lo - pad) * u, base + (hi + pad) * u]
        out += ax.plot([ends[0][0], ends[1][0]], [ends[0][1], ends[1][1]], color="0.3",
                       lw=1.2, ls="-", label="the slider's guide")
    return out


def write_kind_linkage(deck: Deck, directory: str, at: Any = None, branch: Any = "open",
                       animate: bool = False) -> list[str]:
    """``linkage.png`` (and ``linkage.gif``, one cycle, with ``animate``) for another
    kind, all or none.  ``at``: the crank angles drawn [deg] (None: 40, or the middle of
    the first arc where it assembles); none that assembles is a CommandError."""
    import os

    from sielaff.tools.plot.render import write_files

    images = {os.path.join(directory, name): data
              for name, data in kind_linkage_images(deck, at, branch, animate)[0].items()}
    write_files(images)
    return list(images)


def kind_linkage_images(deck: Deck, at: Any = None, branch: Any = "open",
                        animate: bool = False) -> tuple[dict[str, bytes], np.ndarray]:
    """The images of :func:`write_kind_linkage` ({"linkage.png": PNG bytes, and
    "linkage.gif" with ``animate``}) and the crank angles drawn [deg]."""
    import io

    from sielaff.tools.plot.linkage import _gif
    from sielaff.tools.plot.render import _pyplot, _subtitle

    plt = _pyplot()
    arcs = _arcs(deck, branch)
    if not arcs:
        raise _nowhere(deck)
    at = np.atleast_1d(np.asarray(_default(arcs) if at is None else at, dtype=float))
    data = drawing_data(deck, at, branch)
    ok = np.isfinite(data["points"][data["links"][-1][0][-1]][0]) if data["links"] else \
        np.isfinite(data["points"][data["slides"][0]["at"]][0])
    if not ok.any():
        from sielaff.tools.common import CommandError

        spans = " and from ".join(f"{a:.2f} to {b:.2f} deg" for a, b in arcs)
        raise CommandError(f"{deck.path}: --at {','.join(f'{a:g}' for a in at)}: the linkage "
                           f"does not assemble there; it assembles from THETA 2 = {spans}: "
                           "nothing drawn")
    if not ok.all():
        warnings.warn(f"{deck.path}: --at {','.join(f'{a:g}' for a in at[~ok])}: the linkage "
                      "cannot be put together there; the drawing leaves it out", stacklevel=2)
        at = at[ok]
        data = drawing_data(deck, at, branch)
    sweep = _sweep(arcs)
    path = drawing_data(deck, sweep, branch)
    sub = _subtitle(deck)
    images: dict[str, bytes] = {}

    def picture(ks: list[int], still: bool) -> bytes:
        """The drawing at the angle indices ``ks`` of the still picture (``still``) or of
        the animation's frames (PNG bytes, or raw RGBA of 560 x 400 for a frame)."""
        src, shown = (data, at) if still else (frames, cycle)
        fig, ax = plt.subplots(figsize=(9, 6.4) if still else (7, 5), dpi=100 if still else 80,
                               layout="constrained")
        try:
            ax.set_aspect("equal")
            gx, gy = path["points"]["G3"]
            ax.plot(gx, gy, lw=1.0, ls="--", label="path of G3")
            guides(ax, path)
            for n, k in enumerate(ks):
                draw(ax, src, k, 1.0 if n == 0 else 0.35, labelled=n == 0)
            px = [float(path["points"][n][0][0]) for n in path["pivots"]]
            py = [float(path["points"][n][1][0]) for n in path["pivots"]]
            ax.plot(px, py, "s", color="0.3", ms=9, label="the frame's pivots (link 1)")
            for name, (x, y) in src["points"].items():
                if not name.startswith("G") and np.isfinite(x[ks[0]]):
                    ax.annotate(name, (float(x[ks[0]]), float(y[ks[0]])), xytext=(7, 7),
                                textcoords="offset points", fontsize=9)
            ax.set_title(f"The {path['title']} ({branch_words(branch)}) at THETA 2 = "
                         + ", ".join(f"{shown[k]:g}" for k in ks) + f" deg\n{sub}",
                         fontsize=10)
            ax.set_xlabel(f"x ({_unit(deck)}), along the frame's line from O2")
            ax.set_ylabel(f"y ({_unit(deck)})")
            ax.grid(True, color="0.9")
            if not still:  # every frame the same axes
                ax.set_xlim(*limits[0])
                ax.set_ylim(*limits[1])
            fig.legend(loc="outside lower center", ncol=3, frameon=False, fontsize=8)
            buf = io.BytesIO()
            fig.savefig(buf, format="png" if still else "rgba")
            return buf.getvalue()
        finally:
            plt.close(fig)

    frames = data
    cycle = at
    limits = ((0.0, 1.0), (0.0, 1.0))
    images["linkage.png"] = picture(list(range(len(at))), True)
    if animate:
        cycle = sweep[np.isfinite(sweep)][::max(1, len(sweep) // 36)][:36]
        frames = drawing_data(deck, cycle, branch)
        xs = np.concatenate([x for x, _ in path["points"].values()])
        ys = np.concatenate([y for _, y in path["points"].values()])
        pad = 0.1 * (np.nanmax(xs) - np.nanmin(xs))
        limits = ((float(np.nanmin(xs) - pad), float(np.nanmax(xs) + pad)),
                  (float(np.nanmin(ys) - pad), float(np.nanmax(ys) + pad)))
        pictures = []
        for k in range(len(cycle)):
            raw = picture([k], False)
            pictures.append(np.frombuffer(raw, dtype=np.uint8).reshape(400, 560, 4)[..., :3])
        images["linkage.gif"] = _gif(pictures, fps=12)
    return images, at


def branch_words(branch: Any) -> str:
    """The branch in words: "open branch", or "branches open, crossed" (one per dyad)."""
    return f"{branch} branch" if isinstance(branch, str) else \
        "branches " + ", ".join(branch)


def _unit(deck: Deck) -> str:
    from sielaff.quantities import unit

    return unit("R2", deck.mechanism.units)


def _arcs(deck: Deck, branch: Any) -> list[tuple[float, float]]:
    from sielaff.engine import model_for
    from sielaff.engine.assembly import GRID, arcs, margins

    topology = model_for(deck.mechanism).topology
    th = np.arange(GRID) * (360.0 / GRID)
    values = {k: float(v) for k, v in deck.mechanism.as_dict().items()}
    ok = np.all(np.isfinite(margins(topology, values, th, branch)), axis=0)
    return arcs(ok, th) if ok.any() else []


def _default(arcs: list[tuple[float, float]]) -> float:
    for a, b in arcs:
        if (a, b) == (0.0, 360.0) or (a <= 40.0 <= b):
            return 40.0
    a, b = arcs[0]
    return float((a + ((b - a) % 360.0) / 2.0) % 360.0)


def _sweep(arcs: list[tuple[float, float]]) -> np.ndarray:
    if arcs == [(0.0, 360.0)]:
        return np.linspace(0.0, 360.0, 721)
    return np.concatenate([np.append(np.mod(a + np.linspace(0.0, (b - a) % 360.0, 241), 360.0),
                                     np.nan) for a, b in arcs])


def _nowhere(deck: Deck) -> Exception:
    from sielaff.tools.common import CommandError

    return CommandError(f"{deck.path}: the linkage assembles at no crank angle: nothing drawn")
