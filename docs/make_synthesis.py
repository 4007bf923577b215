"""Regenerate the worked examples of docs/synthesis.md (the block between its markers).

    PYTHONPATH=src python docs/make_synthesis.py          # rewrite the block, redraw
    PYTHONPATH=src python docs/make_synthesis.py --print  # show it, change nothing

It also draws docs/img/synthesis.png (the examples; matplotlib).
Every number in the block is computed here by sielaff.synthesis and checked by the engine
(the poses and points met, the swing and time ratio found again) before it is printed.
Numbers are printed to 5 significant digits (far from the roundoff of any platform); a
quantity that is zero to roundoff is printed as a bound ("< 1E-12"), never its digits.
tests/test_synthesis_doc.py regenerates the block and compares it, number by number
within the last printed digit, with the committed one.
"""

from __future__ import annotations

import os
import sys
import warnings

import numpy as np

import sielaff
from sielaff import synthesis

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "synthesis.md")
BEGIN, END = "<!-- BEGIN make_synthesis.py -->", "<!-- END make_synthesis.py -->"


def g(x: float) -> str:
    """5 significant digits."""
    return f"{x:.5g}"


def bound(x: float, unit: str) -> str:
    """A roundoff-sized quantity as a bound, so no digit of roundoff is printed."""
    for b in (1e-12, 1e-10, 1e-9):
        if abs(x) < b:
            return f"< {b:.0E} {unit}"
    return f"{g(x)} {unit}"


def lengths(m) -> str:
    return (f"R1 = {g(m.R1)}, R2 = {g(m.R2)}, R3 = {g(m.R3)}, R4 = {g(m.R4)} "
            f"{'in' if m.units == 'in-lb-sec' else 'm'}")


def crank_rocker_example() -> list[str]:
    swing, Q = 45.0, 1.25
    fam = synthesis.crank_rocker(swing, Q, rocker=10.0, th2d=10.0)
    b = fam.best
    m = b.mechanism
    # checked again by the engine: THETA 4 at the toggles, the swing over a turn
    th = np.linspace(0.0, 360.0, 36001)
    a4 = sielaff.analyze(m, th, ["ATH4"], branch=b.branch)["ATH4"]
    psi = np.degrees(np.unwrap(np.radians(a4)))
    assert abs((psi.max() - psi.min()) - swing) < 1e-4
    out = [
        "### Crank-rocker: swing 45 deg, time ratio 1.25, rocker 10 in",
        "",
        "```python",
        "fam = synthesis.crank_rocker(45.0, 1.25, rocker=10.0, th2d=10.0)",
        "```",
        "",
        f"delta = 180 (Q - 1)/(Q + 1) = {g(fam.delta)} deg.  The members (k = (R3 - R2)/R4):",
        "",
    ]
    for side, spans in fam.intervals.items():
        for lo, hi in spans:
            low = "just above 0" if lo < 1e-6 else g(lo)  # k -> 0: R3 -> R2, a change point
            out.append(f"* side `{side}`: k from {low} to {g(hi)}")
    out += ["", "| side | k | R1 [in] | R2 [in] | R3 [in] | min transmission [deg] |",
            "|---|---|---|---|---|---|"]
    for cr in fam.members(3):
        mm = cr.mechanism
        out.append(f"| {cr.side} | {g(cr.k)} | {g(mm.R1)} | {g(mm.R2)} | {g(mm.R3)} | "
                   f"{g(cr.min_transmission)} |")
    out += ["", f"The best (largest minimum transmission angle): side `{b.side}`, k = {g(b.k)}: "
            f"{lengths(m)}; minimum transmission angle {g(b.min_transmission)} deg; branch "
            f"`{b.branch}`; the stretched and folded toggles at THETA 2 = {g(b.toggles[0])} "
            f"and {g(b.toggles[1])} deg, the rocker there at THETA 4 = {g(b.rocker[0])} and "
            f"{g(b.rocker[1])} deg.  Re-analysed over a turn (36001 crank angles) the rocker "
            f"swings {g(psi.max() - psi.min())} deg.",
            "",
            f"Its default masses (steel bars, 0.5 in^2): W2 = {g(m.W2)}, W3 = {g(m.W3)}, "
            f"W4 = {g(m.W4)} lb; ZI2 = {g(m.ZI2)}, ZI3 = {g(m.ZI3)}, ZI4 = {g(m.ZI4)} "
            "in-lb-sec^2; each G half-way along its link.", ""]
    return out


def function_example() -> list[str]:
    out = ["### Function generator: y = log10 x, 1 <= x <= 2", "",
           "```python",
           "gen = synthesis.function(np.log10, (1.0, 2.0), (30.0, 60.0), (90.0, 60.0))",
           "```", "",
           "THETA 2 = 30 + 60 (x - 1) deg and THETA 4 = 90 + 60 log10(x)/log10(2) deg.",
           "", "| precision point x | THETA 2 [deg] | THETA 4 [deg] |", "|---|---|---|"]
    gen = synthesis.function(np.log10, (1.0, 2.0), (30.0, 60.0), (90.0, 60.0))
    for x, t2, t4 in zip(*gen.precision):
        out.append(f"| {g(x)} | {g(t2)} | {g(t4)} |")
    got = sielaff.analyze(gen.mechanism, gen.precision[1], ["ATH4"], branch=gen.branch)["ATH4"]
    miss = float(np.max(np.abs((got - gen.precision[2] + 180) % 360 - 180)))
    assert miss < 1e-9
    m = gen.mechanism
    k1, k2, k3 = gen.K
    out += ["", f"K1 = {g(k1)}, K2 = {g(k2)}, K3 = {g(k3)}; with R1 = 1: {lengths(m)} "
            f"(branch `{gen.branch}`, a {sielaff.linkage_class(m).kind}).  The engine puts "
            f"THETA 4 at the precision points within {bound(miss, 'deg')} of the wanted.  "
            f"Structural error over the range (361 x): largest {g(gen.max_error)} deg.", ""]
    five = synthesis.function(np.log10, (1.0, 2.0), (30.0, 60.0), (90.0, 60.0), points=7)
    out += [f"With 7 Chebyshev points fitted by least squares: {lengths(five.mechanism)}, "
            f"largest structural error {g(five.max_error)} deg.", ""]
    x15 = synthesis.function(lambda x: x ** 1.5, (1.0, 3.0), (165.0, 90.0), (210.0, 60.0))
    out += ["y = x^1.5, 1 <= x <= 3, THETA 2 = 165 + 90 (x - 1)/2, THETA 4 from 210 over "
            f"60 deg: {lengths(x15.mechanism)}, a {sielaff.linkage_class(x15.mechanism).kind}; "
            "largest structural error "
            f"{g(x15.max_error)} deg.", ""]
    return out


def pose_error(res, poses) -> tuple[float, float]:
    m = res.mechanism
    pm = sielaff.point_motion(m, res.crank_angles, 3, res.coupler.r, res.coupler.angle,
                              branch=res.branch)
    ux, uy = res.placement.to_user(pm["X"], pm["Y"])
    P = np.asarray(poses, dtype=float)
    d = float(np.max(np.hypot(ux - P[:, 0], uy - P[:, 1])))
    if P.shape[1] == 3:
        th3 = sielaff.analyze(m, res.crank_angles, ["ATH3"], branch=res.branch)["ATH3"]
        a = th3 + res.placement.angle + res.line_angle - P[:, 2]
        return d, float(np.max(np.abs((a + 180) % 360 - 180)))
    return d, 0.0


def motion_example() -> list[str]:
    out = []
    for poses, what, kw in (
            ([(0.0, 0.0, 0.0), (1.0, 0.5, 20.0), (2.0, 0.3, 45.0)], "three", {}),
            ([(0.0, 0.0, 0.0), (2.0, 1.0, -30.0)], "two",
             {"moving": ((0.5, 1.0), (1.5, -0.5)), "fixed": (1.0, -2.0)})):
        res = synthesis.motion(poses, **kw)
        call = ", ".join([str(poses)] + [f"{k}={v}" for k, v in kw.items()])
        d, a = pose_error(res, poses)
        assert d < 1e-9 and a < 1e-9 and not res.defects
        m, pl, cp = res.mechanism, res.placement, res.coupler
        out += [f"### Motion generation: {what} poses (x [in], y [in], angle [deg])", "",
                "```python", f"res = synthesis.motion({call})", "```", "",
                f"{'Given' if kw else 'Searched'}: moving pivots (coupler frame) A = "
                f"({g(res.choices['moving'][0][0])}, {g(res.choices['moving'][0][1])}) in, "
                f"B = ({g(res.choices['moving'][1][0])}, {g(res.choices['moving'][1][1])}) in"
                + (f"; fixed pivots at t = {g(res.choices['fixed'][0])} and "
                   f"{g(res.choices['fixed'][1])} in on the bisectors" if "fixed" in res.choices
                   else "") + ".",
                f"{lengths(m)} (a {sielaff.linkage_class(m).kind}, branch `{res.branch}`, "
                f"TH2D {'> 0 (CCW)' if res.direction > 0 else '< 0 (CW)'}).  O2 at "
                f"({g(pl.x)}, {g(pl.y)}) in, O2->O4 at {g(pl.angle)} deg.  The pose point P: "
                f"r = {g(cp.r)} in from A at {g(cp.angle)} deg from A->B; the pose's line at "
                f"{g(res.line_angle)} deg from A->B.  THETA 2 at the poses: "
                + ", ".join(g(t) for t in res.crank_angles) + " deg.  Defects: none.  The "
                f"engine's coupler passes the poses within {bound(d, 'in')} and "
                f"{bound(a, 'deg')}.", ""]
    return out


def path_example() -> list[str]:
    try:
        import scipy  # noqa: F401
    except ImportError:
        return ["### Path generation", "", "(scipy is not installed: not run)", ""]
    # five points on the coupler curve of a known linkage (4, 1, 3.5, 3 in; P 2 in from A
    # at 30 deg), THETA 2 = 0, 40, 90, 150, 200 deg: reachable, so the fit can be exact
    known = sielaff.EXAMPLE.replace(R1=4.0, R2=1.0, R3=3.5, R4=3.0)
    k = sielaff.point_motion(known, [0.0, 40.0, 90.0, 150.0, 200.0], 3, 2.0, 30.0)
    pts = [(round(float(x), 4), round(float(y), 4)) for x, y in zip(k["X"], k["Y"])]
    res = synthesis.path(pts)
    d, _ = pose_error(res, pts)
    assert d < 1e-9 and not res.defects
    m, pl, cp = res.mechanism, res.placement, res.coupler
    return ["### Path generation: five points", "", "```python",
            f"res = synthesis.path({pts})", "```", "",
            f"{lengths(m)} (a {sielaff.linkage_class(m).kind}, branch `{res.branch}`); O2 at "
            f"({g(pl.x)}, {g(pl.y)}) in, O2->O4 at {g(pl.angle)} deg; P: r = {g(cp.r)} in "
            f"from A at {g(cp.angle)} deg; THETA 2 at the points: "
            + ", ".join(g(t) for t in res.crank_angles) + " deg.  Residuals (distance of each "
            f"point from the coupler curve): all {bound(float(np.max(res.residuals)), 'in')}."
            "  (A local solver from seeded starts: another platform's floating point may "
            "lead it to another linkage through the same points; the tests check the "
            "properties, not these digits.)", ""]


def figure(path: str) -> None:
    """docs/img/synthesis.png: the four examples drawn (matplotlib, Agg)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(11, 9.5))
    # (a) the best crank-rocker at its two toggles
    b = synthesis.crank_rocker(45.0, 1.25, rocker=10.0, th2d=10.0).best
    m = b.mechanism
    a = ax[0, 0]
    for t, style in zip(b.toggles, ("-", "--")):
        k = sielaff.point_motion(m, [t], 4, m.R4, branch=b.branch)
        A = (m.R2 * np.cos(np.radians(t)), m.R2 * np.sin(np.radians(t)))
        a.plot([0, A[0], k["X"][0], m.R1], [0, A[1], k["Y"][0], 0], "o" + style, color="C0")
    th = np.linspace(0, 360, 721)
    k = sielaff.point_motion(m, th, 4, m.R4, branch=b.branch)
    a.plot(k["X"], k["Y"], color="C1", lw=3, alpha=0.5, label="B's arc (45 deg)")
    a.plot(m.R2 * np.cos(np.radians(th)), m.R2 * np.sin(np.radians(th)), ":", color="C0")
    a.set_title("crank-rocker, swing 45 deg, Q = 1.25: the best member\n"
                "at its two toggles (solid: stretched, dashed: folded) [in]")
    a.legend(loc="best")
    # (b) structural error of the function generators
    a = ax[0, 1]
    for pts, lab in ((3, "3 Chebyshev points (exact there)"), (7, "7 points, least squares")):
        gen = synthesis.function(np.log10, (1.0, 2.0), (30.0, 60.0), (90.0, 60.0), points=pts)
        a.plot(gen.x, gen.structural_error, label=lab)
        if pts == 3:
            a.plot(gen.precision[0], 0 * gen.precision[0], "ko")
    a.axhline(0, color="k", lw=0.5)
    a.set_xlabel("x")
    a.set_ylabel("THETA 4 generated - wanted [deg]")
    a.set_title("function generator, y = log10 x: structural error")
    a.legend(loc="best")
    # (c) motion through three poses; (d) path through five points
    poses = [(0.0, 0.0, 0.0), (1.0, 0.5, 20.0), (2.0, 0.3, 45.0)]
    known = sielaff.EXAMPLE.replace(R1=4.0, R2=1.0, R3=3.5, R4=3.0)
    k = sielaff.point_motion(known, [0.0, 40.0, 90.0, 150.0, 200.0], 3, 2.0, 30.0)
    pts = [(round(float(x), 4), round(float(y), 4)) for x, y in zip(k["X"], k["Y"])]
    for a, res, targets, title in (
            (ax[1, 0], synthesis.motion(poses), poses, "motion: three poses (arrows)"),
            (ax[1, 1], synthesis.path(pts), pts, "path: five points (crosses)")):
        mm, pl, cp = res.mechanism, res.placement, res.coupler
        th = np.linspace(0, 360, 721)
        c = sielaff.point_motion(mm, th, 3, cp.r, cp.angle, branch=res.branch)
        a.plot(*pl.to_user(c["X"], c["Y"]), color="C1", label="coupler curve")
        for t in res.crank_angles:
            kk = sielaff.point_motion(mm, [t], 3, cp.r, cp.angle, branch=res.branch)
            kb = sielaff.point_motion(mm, [t], 4, mm.R4, branch=res.branch)
            A = (mm.R2 * np.cos(np.radians(t)), mm.R2 * np.sin(np.radians(t)))
            xs = [0, A[0], kb["X"][0], mm.R1]
            ys = [0, A[1], kb["Y"][0], 0]
            a.plot(*pl.to_user(xs, ys), "o-", color="C0", alpha=0.6)
            a.fill(*pl.to_user([A[0], kb["X"][0], kk["X"][0]], [A[1], kb["Y"][0], kk["Y"][0]]),
                   color="C0", alpha=0.15)
        T = np.asarray(targets, dtype=float)
        if T.shape[1] == 3:
            a.quiver(T[:, 0], T[:, 1], np.cos(np.radians(T[:, 2])), np.sin(np.radians(T[:, 2])),
                     color="C3", angles="xy", scale_units="xy", scale=2.0)
        else:
            a.plot(T[:, 0], T[:, 1], "x", color="C3", ms=10, mew=2)
        a.set_title(title + " [in]")
        a.legend(loc="best")
    for a in (ax[0, 0], ax[1, 0], ax[1, 1]):
        a.set_aspect("equal", adjustable="datalim")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def block() -> str:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lines = (crank_rocker_example() + function_example() + motion_example()
                 + path_example())
    return "\n".join(lines).rstrip() + "\n"


def main() -> None:
    text = block()
    if "--print" in sys.argv:
        print(text)
        return
    doc = open(DOC).read()
    head, rest = doc.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(DOC, "w") as f:
        f.write(head + BEGIN + "\n" + text + END + tail)
    print(DOC)
    png = os.path.join(ROOT, "docs", "img", "synthesis.png")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        figure(png)
    print(png)


if __name__ == "__main__":
    main()
