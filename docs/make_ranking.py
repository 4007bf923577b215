"""Regenerate the ranking and tolerance examples of docs/synthesis.md (between its
``make_ranking.py`` markers) and draw docs/img/ranking.png.

    PYTHONPATH=src python docs/make_ranking.py          # rewrite the block, redraw
    PYTHONPATH=src python docs/make_ranking.py --print  # show it, change nothing

Every number is computed here by sielaff.synthesis.rank and sielaff.design.tolerance
(seeded: the same on every run and path) and printed to 5 significant digits;
tests/test_rank.py regenerates the block and compares it, number by number within the
last printed digit, with the committed one.
"""

from __future__ import annotations

import os
import sys
import warnings

import numpy as np

import sielaff
from sielaff import Scene, design, synthesis
from sielaff.mechanism import EXAMPLE

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "synthesis.md")
PNG = os.path.join(ROOT, "docs", "img", "ranking.png")
#: The two blocks: (begin marker, end marker) of each.
MARKERS = {name: (f"<!-- BEGIN make_ranking.py: {name} -->",
                  f"<!-- END make_ranking.py: {name} -->") for name in ("ranking", "tolerances")}

SCENE = Scene(tex=-50.0)
BY = ["TORQ_PEAK", "SHAK_PEAK"]
PARETO = ["TORQ_RMS", "GAMMA_MIN"]
DEV = {"R1": 0.005, "R2": 0.005, "R3": 0.005, "R4": 0.005, "ADEL3": 0.5, "RG3": 0.05,
       "W3": 0.1}


def g(x: float) -> str:
    return f"{x:.5g}"


def ranking():
    fam = synthesis.crank_rocker(45.0, 1.25, rocker=10.0, th2d=10.0)
    cands = fam.members(8)
    return cands, synthesis.rank(cands, scene=SCENE, by=BY, pareto=PARETO)


def ranking_lines() -> list[str]:
    cands, r = ranking()
    f = r.figures
    out = [
        "### Example: the quick-return crank-rockers, ranked",
        "",
        "The family of the worked example above (swing 45 deg, time ratio 1.25, rocker 10 in),",
        f"sampled: `members(8)` gives {len(cands)} members (8 per interval of k on each side),",
        "each of steel bars (the default mass model), at TH2D = 10 rad/sec against TEX = -50",
        "in-lb on the rocker, ranked by peak driving torque, then peak shaking force:",
        "",
        "```python",
        "fam = synthesis.crank_rocker(45.0, 1.25, rocker=10.0, th2d=10.0)",
        "r = synthesis.rank(fam.members(8), scene=sielaff.Scene(tex=-50.0),",
        '                   by=["TORQ_PEAK", "SHAK_PEAK"], pareto=["TORQ_RMS", "GAMMA_MIN"])',
        "```",
        "",
        "| rank | k | side | R1 [in] | R2 [in] | R3 [in] | TORQ_PEAK [in-lb] | TORQ_RMS [in-lb] "
        "| SHAK_PEAK [lb] | GAMMA_MIN [deg] | FLYWHEEL_I [in-lb-sec^2] | Pareto |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    front = set(int(i) for i in r.pareto)
    for k, i in enumerate(r.order, 1):
        c, m = cands[i], r.mechanisms[i]
        out.append(f"| {k} | {g(c.k)} | {c.side} | {g(m.R1)} | {g(m.R2)} | {g(m.R3)} | "
                   f"{g(f['TORQ_PEAK'][i])} | {g(f['TORQ_RMS'][i])} | {g(f['SHAK_PEAK'][i])} | "
                   f"{g(f['GAMMA_MIN'][i])} | {g(f['FLYWHEEL_I'][i])} | "
                   f"{'yes' if i in front else ''} |")
    b = cands[r.order[0]]
    kin = synthesis.crank_rocker(45.0, 1.25, rocker=10.0, th2d=10.0).best
    differ = "a different linkage: the" if abs(kin.k - b.k) > 1e-6 else "the same linkage: the"
    out += [
        "",
        f"The best by torque is k = {g(b.k)} ({b.side} side); the family's best by",
        f"transmission angle (`fam.best`, k = {g(kin.k)}, {kin.side} side) is {differ}",
        "kinematic and the dynamic choice " + ("differ." if "different" in differ
                                               else "agree.")
        + "  The Pareto front of TORQ_RMS (minimised)",
        f"and GAMMA_MIN (maximised) has {len(r.pareto)} members.  The picture draws the",
        "candidates best first (each at THETA 2 = 60 deg, in its own frame) and the front:",
        "",
        "![the candidates, best first, and the Pareto front](img/ranking.png)",
        "",
    ]
    return out


def tolerance_lines() -> list[str]:
    t = design.tolerance(EXAMPLE, DEV, n=2000, seed=1, scene=Scene(tex=-200.0))
    units = {"TORQ_PEAK": "in-lb", "TORQ_RMS": "in-lb", "FLYWHEEL_I": "in-lb-sec^2",
             "FOA_PEAK": "lb", "FA32_PEAK": "lb", "FB34_PEAK": "lb", "FOB_PEAK": "lb",
             "SHAK_PEAK": "lb", "SHAKM_PEAK": "in-lb", "GAMMA_MIN": "deg"}
    out = [
        "### Example: the report's linkage, machined to 0.005 in",
        "",
        "The report's example (decks/tolerance.toml) with its four lengths held to 0.005 in,",
        "the coupler's centre of mass to 0.5 deg and 0.05 in and its weight to 0.1 lb (each a",
        "standard deviation, normal), against TEX = -200 in-lb; 2000 samples, seed 1",
        "(`sielaff tolerance decks/tolerance.toml` prints the same table):",
        "",
        "```python",
        "t = design.tolerance(sielaff.EXAMPLE, {\"R1\": 0.005, \"R2\": 0.005, \"R3\": 0.005, "
        "\"R4\": 0.005,",
        "                     \"ADEL3\": 0.5, \"RG3\": 0.05, \"W3\": 0.1}, n=2000, seed=1,",
        "                     scene=sielaff.Scene(tex=-200.0))",
        "```",
        "",
        "| figure | unit | nominal | mean | std | 5% | 95% | first-order std | d/d R2 [per in] |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for f in t.nominal:
        out.append(f"| {f} | {units[f]} | {g(t.nominal[f])} | {g(t.mean[f])} | {g(t.std[f])} "
                   f"| {g(t.p5[f])} | {g(t.p95[f])} | {g(t.predicted_std[f])} | "
                   f"{g(t.sensitivity[f]['R2'])} |")
    ratio = [t.std[f] / t.predicted_std[f] for f in t.nominal]
    n = t.n
    se = 4.0 / np.sqrt(2.0 * (n - 1))
    parts = {k: abs(t.sensitivity["TORQ_PEAK"][k]) * t.sigma[k] for k in t.sigma}
    top = max(parts, key=parts.get)
    share = parts[top] ** 2 / sum(v * v for v in parts.values())
    out += [
        "",
        "The sampled std agrees with the first-order one to "
        f"{100 * max(abs(x - 1) for x in ratio):.2g}% at worst, within the",
        "bound tests/test_tolerance.py checks (4 standard errors of a sample std,",
        f"4/sqrt(2(n-1)) = {100 * se:.2g}% at n = {n}, plus 2% for second-order terms).  Of",
        f"TORQ_PEAK's first-order variance, {top}'s deviation gives the largest part",
        f"({100 * share:.2g}%: |d TORQ_PEAK / d {top}| x sigma = {g(parts[top])} in-lb).",
        "",
    ]
    return out


def block(name: str) -> str:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lines = ranking_lines() if name == "ranking" else tolerance_lines()
    return "\n".join(lines).rstrip() + "\n"


def figure(path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cands, r = ranking()
    show = list(r.order[:8])
    fig = plt.figure(figsize=(12, 7.5))
    for k, i in enumerate(show):
        a = fig.add_subplot(3, 4, k + 1)
        m, br = r.mechanisms[i], r.branches[i]
        t = 60.0
        kb = sielaff.point_motion(m, [t], 4, m.R4, branch=br)
        A = (m.R2 * np.cos(np.radians(t)), m.R2 * np.sin(np.radians(t)))
        a.plot([0, A[0], kb["X"][0], m.R1], [0, A[1], kb["Y"][0], 0], "o-", color="C0")
        th = np.linspace(0, 360, 361)
        kk = sielaff.point_motion(m, th, 4, m.R4, branch=br)
        a.plot(kk["X"], kk["Y"], color="C1", lw=2, alpha=0.6)
        a.set_aspect("equal", adjustable="datalim")
        a.set_title(f"#{k + 1}: TORQ_PEAK {r.figures['TORQ_PEAK'][i]:.4g} in-lb", fontsize=9)
        a.tick_params(labelsize=7)
    a = fig.add_subplot(3, 1, 3)
    x, y = r.figures[PARETO[0]], r.figures[PARETO[1]]
    a.scatter(x, y, s=12, color="0.6", label=f"candidates ({len(x)})")
    p = r.pareto
    a.plot(x[p], y[p], "o-", color="C3", ms=4, label=f"Pareto front ({len(p)})")
    a.set_xlabel("TORQ_RMS, RMS driving torque [in-lb]")
    a.set_ylabel("GAMMA_MIN [deg]")
    a.legend(loc="best")
    a.grid(True, alpha=0.3)
    fig.suptitle("crank-rockers for a 45 deg swing, Q = 1.25, ranked by peak torque "
                 "(B's arc in orange; lengths in in)", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=80, metadata={"Software": None})
    plt.close(fig)


def main() -> None:
    texts = {name: block(name) for name in MARKERS}
    if "--print" in sys.argv:
        print("\n".join(texts.values()))
        return
    doc = open(DOC).read()
    for name, (begin, end) in MARKERS.items():
        if begin not in doc:
            raise SystemExit(f"{DOC}: no {begin} marker")
        head, rest = doc.split(begin, 1)
        _, tail = rest.split(end, 1)
        doc = head + begin + "\n" + texts[name] + end + tail
    with open(DOC, "w") as f:
        f.write(doc)
    print(DOC)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        figure(PNG)
    print(PNG)


if __name__ == "__main__":
    main()
