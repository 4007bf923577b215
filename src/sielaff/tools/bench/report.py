"""The accuracy study's report: docs/accuracy.md, its figure, and the headline table."""

from __future__ import annotations

import os

from sielaff.emulator.printer import NEARBY_ULPS
from sielaff.tools.bench.study import ENGINE, coarsest_step

#: Where a model's label may go, tried in turn: (dx, dy) offset points from its maximum
#: and the horizontal alignment.
LABEL_SPOTS = ((6, 4, "left"), (6, -26, "left"), (-6, 4, "right"), (-6, -26, "right"),
               (6, 16, "left"), (-6, 16, "right"), (6, -40, "left"), (-6, -40, "right"),
               (6, 30, "left"), (-6, 30, "right"), (6, -54, "left"), (-6, -54, "right"))


def plot(res: dict, path: str) -> None:
    """The study's figure, written to ``path`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = figure(res)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _place(ax, labels, markers) -> None:
    """Each (text, xy, color) of ``labels`` as an annotation at the first of
    :data:`LABEL_SPOTS` where its box, as the renderer draws it, stays inside the axes
    (else inside the figure) and meets no text already drawn (placed labels, legends,
    titles, tick labels) and none of ``markers`` (data points, 5 px either way).  (The
    plot command's tests measure text the same way: tools/plot/render.text_boxes.)"""
    fig = ax.figure
    fig.canvas.draw()  # the layout settled: boxes in display pixels from here on
    renderer = fig.canvas.get_renderer()
    taken = _drawn_texts(fig, renderer)
    frames = (ax.get_window_extent(renderer), fig.bbox)  # inside the axes if it can be
    for other in fig.axes:
        if other.get_legend() is not None:
            taken.append(other.get_legend().get_window_extent(renderer))
    dots = [ax.transData.transform(xy) for xy in markers]

    def free(bb, frame) -> bool:
        if not (frame.x0 <= bb.x0 and bb.x1 <= frame.x1 and frame.y0 <= bb.y0
                and bb.y1 <= frame.y1):
            return False
        if any(bb.overlaps(t) for t in taken):
            return False
        return not any(bb.x0 - 5 < x < bb.x1 + 5 and bb.y0 - 5 < y < bb.y1 + 5
                       for x, y in dots)

    for text, xy, color in labels:
        chosen = None
        for frame, (dx, dy, ha) in ((f, spot) for f in frames for spot in LABEL_SPOTS):
            ann = ax.annotate(text, xy, textcoords="offset points", xytext=(dx, dy), ha=ha,
                              fontsize=8, color=color)
            ann.set_in_layout(False)  # placed after the layout: it must not move the axes
            bb = ann.get_window_extent(renderer)
            if free(bb, frame):
                chosen = bb
                break
            ann.remove()
        if chosen is None:  # nowhere free: the first spot, as before
            dx, dy, ha = LABEL_SPOTS[0]
            ann = ax.annotate(text, xy, textcoords="offset points", xytext=(dx, dy), ha=ha,
                              fontsize=8, color=color)
            ann.set_in_layout(False)
            chosen = ann.get_window_extent(renderer)
        taken.append(chosen)


def _drawn_texts(fig, renderer) -> list:
    """The boxes (display pixels) of every non-empty visible text ``fig`` draws; a tick
    label counts only if its tick is inside the axis's view (the others are not drawn)."""
    from matplotlib.text import Text

    hidden = set()
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                if not lo <= tick.get_loc() <= hi:
                    hidden.update((id(tick.label1), id(tick.label2)))
    out = []
    for t in fig.findobj(Text):
        if id(t) in hidden or not t.get_visible() or not str(t.get_text()).strip():
            continue
        bb = Text.get_window_extent(t, renderer)
        if bb.width > 0 and bb.height > 0:
            out.append(bb)
    return out


def figure(res: dict):
    """The study's figure: (a) the number models, (b) ARCCOS, (c) the step size."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(15, 5.6), constrained_layout=True,
                                     dpi=110)
    # (a) models: cost against accuracy
    colors = {"float64": "C0", "float32": "C1", "ibm1410:8": "C3", "ibm1410:12": "C4",
              "ibm1410:16": "C5", ENGINE: "C2"}
    labels, markers = [], []
    for row in res["models"]["rows"]:
        c = colors[row["model"]]
        t = row["us_per_position"]
        points = [(t, max(row["exact_median"], 1e-17)), (t, row["exact_max"])]
        a1.scatter(*points[0], color=c, marker="o", s=50)
        a1.scatter(*points[1], color=c, marker="^", s=50)
        if row["same_median"] is not None:
            points.append((t, max(row["same_median"], 1e-17)))
            a1.scatter(*points[-1], edgecolors=c, marker="s", facecolors="none", s=50)
        markers += points
        either = f" (+{len(row['boundary'])} either way)" if row["boundary"] else ""
        labels.append((f"{row['model']}\n{row['fields']}/82 fields{either}",
                       (t, row["exact_max"]), c))
    a1.axhline(res["models"]["algorithm_median"], color="grey", ls=":", lw=1)
    a1.text(1.0, res["models"]["algorithm_median"] * 1.4, "1966 algorithm error (median)",
            fontsize=7, color="grey")
    a1.set_xscale("log")
    a1.set_yscale("log")
    a1.set_xlim(0.5, 5000)
    a1.set_ylim(1e-17, 1e-3)
    a1.set_xlabel("time per position (microseconds, log)")
    a1.set_ylabel("scaled error over one revolution (log)")
    a1.set_title("(a) number models, example at 1 degree")
    from matplotlib.lines import Line2D
    a1.legend(handles=[Line2D([], [], marker="^", ls="", color="k",
                              label="max, vs exact mechanics"),
                       Line2D([], [], marker="o", ls="", color="k",
                              label="median, vs exact mechanics"),
                       Line2D([], [], marker="s", ls="", color="k", markerfacecolor="none",
                              label="median, vs same program at 50 digits")],
              fontsize=7, loc="center left")
    # (b) ARCCOS tolerance
    rows = res["arccos"]
    tols = [r["tol"] for r in rows]
    a2.loglog(tols, [r["worst"] for r in rows], "o-", color="C0", label="worst |error| vs acos")
    a2.loglog(tols, tols, ":", color="grey", lw=1, label="error = tolerance")
    a2.axvline(1e-8, color="C3", lw=1, ls="--")
    a2.text(8e-9, 3e-16, " 1966: 1E-8", color="C3", fontsize=8)
    a2.invert_xaxis()
    a2.set_xlabel("stopping tolerance ABS(SUM-SAVE) < tol (log)")
    a2.set_ylabel("worst error over X in [-1, 1] (radians, log)")
    a2.set_title("(b) ARCCOS series, float64")
    b2 = a2.twinx()
    b2.plot(tols, [r["mean_terms"] for r in rows], "s--", color="C1", label="mean terms")
    b2.plot(tols, [r["max_terms"] for r in rows], "v--", color="C1", alpha=0.5, label="max terms")
    b2.set_ylabel("series terms", color="C1")
    h1, l1 = a2.get_legend_handles_labels()
    h2, l2 = b2.get_legend_handles_labels()
    a2.legend(h1 + h2, l1 + l2, fontsize=7, loc="upper left")
    # (c) step size
    rows = res["steps"]
    d = [r["delta"] for r in rows]
    floor = 1e-17
    a3.loglog(d, [max(r["engine_rel"], floor) for r in rows], "o-", color="C2",
              label="cycle work |sum TORQ dth| / sum |TORQ| dth, engine")
    a3.loglog(d, [max(r["peak_rel"], floor) for r in rows], "d:", color="C4",
              label="peak |TORQ| missed by the grid, engine")
    pr = [(r["delta"], max(r["port_rel"], floor)) for r in rows if r["port_rel"] is not None]
    a3.loglog([p[0] for p in pr], [p[1] for p in pr], "s-", color="C0",
              label="cycle-work error, port float64")
    a3.invert_xaxis()
    a3.set_xlabel("step DELTA (degrees, log)")
    a3.set_ylabel("relative error (log)")
    a3.set_title("(c) step size: TORQ over one revolution")
    b3 = a3.twinx()
    b3.loglog(d, [r["engine_s"] * 1e3 for r in rows], "--", color="C2", alpha=0.6,
              label="run time, engine (ms)")
    b3.loglog([r["delta"] for r in rows if r["port_s"] is not None],
              [r["port_s"] * 1e3 for r in rows if r["port_s"] is not None], "--", color="C0",
              alpha=0.6, label="run time, port float64 (ms)")
    b3.set_ylabel("run time for one revolution (ms, log)")
    h1, l1 = a3.get_legend_handles_labels()
    h2, l2 = b3.get_legend_handles_labels()
    a3.set_ylim(1e-18, 10)
    a3.legend(h1 + h2, l1 + l2, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14),
              ncol=2)
    _place(a1, labels, markers)  # last: around everything else drawn in (a)
    return fig


# -- the report --------------------------------------------------------------------------------
def _e(x, digits: int = 1) -> str:
    if x is None:
        return "--"
    if x == 0:
        return "0"
    return f"{x:.{digits}e}"


def write_report(res: dict, path: str, figure: str | None = None, command: str = "") -> str:
    """Write the report (docs/accuracy.md) and its PNG beside it, both or neither (folders
    created); returns the markdown."""
    from sielaff.tools.output import atomic_files

    if figure is None:
        figure = os.path.splitext(path)[0] + ".png"
    with atomic_files([path, figure]) as (tmp_md, tmp_png):
        text = _report_text(res, figure, command)
        plot(res, tmp_png)
        with open(tmp_md, "w", encoding="utf-8") as f:
            f.write(text)
    return text


def headline(res: dict) -> str:
    """The study's headline table, for a terminal."""
    lines = [f"{'model':<12} {'us/position':>12} {'x float64':>10} {'max error':>10}  "
             "Figures 10-11 (of 82 fields)"]
    rows = res["models"]["rows"]
    f64 = next(r["us_per_position"] for r in rows if r["model"] == "float64")
    for r in rows:
        figures = f"{r['fields']} certain"
        if r["diffs"]:
            figures += f", {len(r['diffs'])} differ"
        if r["boundary"]:
            figures += f", {len(r['boundary'])} on a digit boundary"
        lines.append(f"{r['model']:<12} {r['us_per_position']:>12.2f} "
                     f"{r['us_per_position'] / f64:>10.2f} {_e(r['exact_max']):>10}  {figures}")
    lines.append("max error: scaled, against the exact mechanics at 50 digits, over the "
                 f"example's revolution at {res['models']['delta']:g} degree steps")
    lines.append(f"machine: {res['machine']}; {res['seconds']:.0f} s")
    return "\n".join(lines)


def _report_text(res: dict, figure: str, command: str) -> str:
    m = res["models"]
    rows = {r["model"]: r for r in m["rows"]}
    ratio = rows["ibm1410:8"]["us_per_position"] / rows["float64"]["us_per_position"]
    out: list[str] = []
    w = out.append
    w("# Accuracy against cost: number models, ARCCOS, step size\n")
    w(f"Generated by `{command or 'python benchmarks/accuracy.py'}`"
      f"{' (quick: fewer ARCCOS points and port steps)' if res['quick'] else ''} in "
      f"{res['seconds']:.0f} s on: **{res['machine']}**.  Every table and the figure below "
      "come from that one command (`sielaff bench` runs the same study, "
      "`src/sielaff/tools/bench/`)."
      "\n")
    w(f"![accuracy against cost]({os.path.basename(figure)})\n")
    w("*(a)* each number model: time per position against its error over the example's "
      "revolution (360 positions, 1 degree), triangles the maximum and dots the median against "
      "the exact mechanics, squares the median against the same 1966 program run in 50-digit "
      "arithmetic; the label gives the Figure 10/11 fields it reproduces. *(b)* the listing's "
      "ARCCOS series against its stopping tolerance. *(c)* the cycle work of the driving torque, "
      "which is exactly zero, and the peak torque the grid misses, against the step DELTA, with "
      "the run time for one revolution (dashed, right axis).  Errors of exactly 0 are drawn "
      "at the bottom edge.\n")

    # ---- figures 10 and 11
    best = max(r[2] for r in res["variants"])
    w("## 1. Figures 10 and 11, field by field\n")
    w(f"With `--arith ibm1410` (8 digits, default library variant `sine`) **all 82 printed "
      f"fields** of Figures 10 and 11 match the report, including `.1999E 03` for VEL A and "
      f"`129.9` for the direction of VEL G2, which float64 cannot produce (best variant: "
      f"{best} of 82).  `tests/test_accuracy.py` pins, for every model and variant below, the "
      "fields that match, the fields that differ, and the fields on a digit boundary.\n")
    w("A binary model's digits are *certain* when every value within "
      f"{NEARBY_ULPS} ulps of the one computed here prints the same text; where a "
      "printed-digit boundary lies closer (the true value is a round number such as VEL A = "
      "R2 TH2D = 200), which text prints depends on the CPU's libm and is counted apart "
      "(\"What the digits depend on\", below).  The 1410 models are decimal and exact on "
      "every machine.\n")
    w("| model | certain matches (of 82) | certain differences (THETA 2, field, what it prints) "
      "| on a digit boundary (either text may print) |")
    w("|---|---:|---|---|")
    for r in m["rows"]:
        w(f"| {r['model']} | {r['fields']} | {', '.join(r['diffs']) or '--'} | "
          f"{', '.join(r['boundary']) or '--'} |")
    w("")
    w(_DIGITS_NOTES)
    w("The 1410 library routines are lost (shared notes), so the library is a model with "
      "parts to choose (`sielaff.emulator.arithmetic.ibm1410`, variant syntax "
      "`--arith ibm1410:8,PRESET,part=choice`)."
      " Every variant tried, at K = 8:\n")
    w("| variant | what it is | fields | differing fields |")
    w("|---|---|---:|---|")
    for variant, what, count, diffs in res["variants"]:
        w(f"| `{variant}` | {what} | {count} | {', '.join(diffs) or '--'} |")
    w("")
    w(_VARIANT_NOTES)
    w(_trace_section(res["traces"]))

    # ---- models
    w("## 2. Number models: time and error\n")
    w(f"The example's full revolution at DELTA = 1 degree ({m['positions']} positions), the port "
      "without printing (the engine: one vectorised call).  Errors are scaled: "
      "`|x - ref| / max|ref|` per quantity over the revolution; a direction's error (radians) is "
      "weighted by its vector's scaled magnitude (a direction of a zero vector means nothing); "
      "THETA 3 and THETA 4 in radians.  All 39 printed quantities but THETA 2 and TEX count.\n")
    w("* **vs same program** = the port in 50-digit mpmath arithmetic, ARCCOS series, 1E-8 test "
      "and the listing's constants included: the error the *arithmetic* adds.")
    w("* **vs exact mechanics** = the same formulas at 50 digits with an exact arccos and exact "
      "pi and 180/pi: the *total* error.  The 1966 algorithm alone (the 50-digit port against "
      f"exact mechanics) is off by {_e(m['algorithm_median'])} (median) and "
      f"{_e(m['algorithm_max'])} (max, {m['algorithm_worst'][0]} at THETA 2 = "
      f"{m['algorithm_worst'][1] * m['delta']:g}): ARCCOS stops at 1E-8, and PI = 3.14159265, "
      "RAD = 57.295779.  No arithmetic gets below that; the engine, which has neither, does.\n")
    w("| model | us / position | x float64 | fields | vs same: max | median | "
      "vs exact: max | median | worst (vs exact) |")
    w("|---|---:|---:|---:|---:|---:|---:|---:|---|")
    f64 = rows["float64"]["us_per_position"]
    for r in m["rows"]:
        wf = r.get("exact_worst")
        worst = f"{wf[0]} at {wf[1] * m['delta']:g}" if wf else "--"
        w(f"| {r['model']} | {r['us_per_position']:.1f} | {r['us_per_position'] / f64:.2f} | "
          f"{r['fields']} | {_e(r['same_max'])} | {_e(r['same_median'])} | "
          f"{_e(r['exact_max'])} | {_e(r['exact_median'])} | {worst} |")
    w("")
    w(f"**Cost of faithfulness:** ibm1410:8 takes **{ratio:.0f}x** the time of float64 per "
      f"position, measured side by side in this run (goal: at most 50x; best of 3 runs each, "
      "but a busy machine still moves the ratio: 30x to 60x were seen on the machine "
      "above).  More digits cost "
      "more (Python big-int arithmetic on longer mantissas) and buy accuracy only down to the "
      "1966 algorithm's own error: ibm1410:12 and :16 are as far from the exact mechanics as "
      "float64, and, like float64, they print the round numbers the figures show a hair below "
      "(`.2000E 03`, `130.0`) -- 8-digit truncation is what the figures record.  float32 "
      "(24-bit binary, ~7 digits) has the same median error as the 8-digit 1410 model but "
      "rounds where the 1410 truncated, so it misses the same fields as float64.  The worst "
      "scaled errors sit where a quantity nearly cancels (Y SHAKE near 360 degrees) or at the "
      "Case I/II switch at 180 degrees, where ARCCOS's stopping test can end one term earlier "
      "or later in a different arithmetic.\n")

    # ---- arccos
    w("## 3. ARCCOS: stopping tolerance against accuracy and time\n")
    n_pts = 2001 if res["quick"] else 20001
    w(f"The listing's series (`FUNCTION ARCCOS`) in float64 with its test "
      f"`ABS(SUM-SAVE).LT.tol`, on {n_pts} points X in [-1, 1], against `math.acos`.  The "
      "terms fall like `X**(2k)` with |X| <= 0.7 (beyond, the series runs on "
      "`SQRT(1-X*X)` <= 0.71), so each factor 10 of tolerance costs about 3 terms.  The 1966 "
      "tolerance 1E-8 leaves errors near 1E-8 radians (quirk 5), the floor of every "
      "model's accuracy in section 2.  In the 8-digit 1410 arithmetic the test is below one "
      "unit in SUM's last place, so the loop only ends when SUM stops changing "
      "(`tests/test_accuracy.py` checks that it does, on the real port).\n")
    w("| tolerance | mean terms | max terms | worst error (rad) | at X | us / call |")
    w("|---:|---:|---:|---:|---:|---:|")
    for r in res["arccos"]:
        w(f"| {r['tol']:.0e} | {r['mean_terms']:.1f} | {r['max_terms']} | {_e(r['worst'])} | "
          f"{r['worst_x']:.4f} | {r['us_per_call']:.2f} |")
    w("")

    # ---- steps
    w("## 4. Step size: the cycle work of the driving torque\n")
    w("With TEX = 0 the motor's work over one revolution, the integral of TORQ d(theta 2), is "
      "exactly zero: the linkage returns to the same state, so its kinetic energy does too, "
      "and nothing else takes work (the report's argument).  Summing TORQ x DELTA over a "
      "revolution (the rectangle rule, which equals the trapezoidal rule for a periodic "
      "integrand) converges faster than any power of DELTA, because TORQ is smooth and "
      "periodic.  The error is shown relative to the integral of |TORQ|.  The cycle integral "
      "is a weak test of a step, though: it is right to 1E-13 at 10 degrees while the sheets "
      "at 10 degrees can miss the torque's peak between two positions, so the table also "
      "gives how far the largest |TORQ| on the grid falls short of the peak (found on a "
      "0.001-degree grid).  Steps coarser than the brief's 10 degrees show where the "
      "integral breaks down.\n")
    w("| DELTA (deg) | positions | engine: cycle work error | engine: peak torque missed | "
      "engine: time (ms) | port float64: cycle work error | port: time (ms) |")
    w("|---:|---:|---:|---:|---:|---:|---:|")
    for r in res["steps"]:
        ps = "--" if r["port_s"] is None else f"{r['port_s'] * 1e3:.1f}"
        w(f"| {r['delta']:g} | {r['positions']} | {_e(r['engine_rel'])} | "
          f"{_e(r['peak_rel'])} | {r['engine_s'] * 1e3:.2f} | {_e(r['port_rel'])} | {ps} |")
    w("")
    w("**Choosing a step.**  Decide which quantity must meet which accuracy, then take the "
      "coarsest DELTA whose error (and every finer one's) is within it "
      "(`sielaff.tools.bench.coarsest_step(rows, tolerance, key)`, key `engine_rel`, `peak_rel` or "
      "`port_rel`):\n")
    w("| wanted relative error | cycle work, engine | peak torque, engine | "
      "cycle work, port float64 |")
    w("|---:|---:|---:|---:|")

    def pick(tol, key):
        row = coarsest_step(res["steps"], tol, key)
        return f"{row['delta']:g} deg" if row else "none tried"

    for tol in (1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14):
        w(f"| {tol:.0e} | {pick(tol, 'engine_rel')} | {pick(tol, 'peak_rel')} | "
          f"{pick(tol, 'port_rel')} |")
    w("")
    w("For example, a designer who needs the peak driving torque to 0.1 % reads the "
      "`1e-03` row.  The port's cycle work stops improving near 1E-8 whatever the step: its "
      "angles carry the ARCCOS series error (section 3), and the torque with them.\n")
    return "\n".join(out)


_DIGITS_NOTES = """\
### What the digits depend on

* **The 1410 models** (`ibm1410:K`) compute in decimal with integer arithmetic and their own
  library routines: the same digits on every machine.
* **The float64 port** runs on Python's `math`, i.e. the platform's C library (glibc on
  Linux).  `+ - * /` and `sqrt` are correctly rounded everywhere (IEEE 754); `sin`, `cos`
  and `atan` are not required to be, and glibc picks an FMA or an SSE2 build of them by
  CPU, so a result may differ in its last bit between machines.
* **The float32 port and the engine** use numpy's `sin`, `cos`, `arctan2` and `hypot`,
  whose SIMD loops (AVX2, AVX-512, NEON, or none) differ by an ulp or so between CPUs and
  numpy builds.
* A printed field truncates its value, so a last-bit difference changes the text only
  where the value lies within a few ulps of a digit boundary: `219.99999999999997` prints
  `219.9`, `220.0` prints `220.0`.  That happens where the true value is a round number,
  as for the directions of link 2 (THETA 2 + 90, + 180) and VEL A = 200 in/sec.  Those
  fields are listed above as on a boundary; the tests assert only that they print one
  of the two neighbouring texts, and `tests/test_ulp_immunity.py` runs the suite's
  pinned tests with every libm result moved one ulp up and one ulp down.
"""


_VARIANT_NOTES = """\
**How the figures pin the library down.**  Eight fields of each sheet -- VG2, VA, AG2, AA and
their directions -- depend only on the crank's STH2 and CTH2 (DEL2 = 0, so STHDE2 = STH2),
the exact factors 100, 200, 5000 and 10000 (RG2 or R2 times TH2D or SQ2D), ATAN and SQRT.
Treating STH2 and CTH2 at 40 and 50 degrees as unknowns a few units around the true values
and asking which digits reproduce all eight printed fields (a scan, not part of the study):

* `VG2 = .1000E 03` and `AA = .1000E 05` need `trunc(S*S) + trunc(C*C) >= 1` in 8 digits: the
  library's sine and cosine must run *high* by a few units.  A correctly truncated or rounded
  library (exact values, then 8 digits) prints `.9999E 02` at 40 degrees (75 or 77 fields).
  Truncated Horner sums do run high (`1 - t` with `t` truncated rounds up); that is the
  `sine` core's signature.
* `DVG2 = 129.9` but `DVA = 130.0` at 40 degrees: the two differ only in that VAX, VAY are
  `200*S`, `200*C`, which drop a digit where `100*S` does not.  That can move the ratio
  `|Y|/|X|` by one unit, and the printed direction follows only if ATAN has a step exactly
  there: ATAN(1.1917535) must give at least .87266460 (it is .8726645865) and ATAN(1.1917534)
  at most .87266459.  With an ATAN accurate to a unit, the only STH2, CTH2 within 8 units that
  do this are .64278765 and .76604444 -- what the Horner sine core gives with cosines as
  `sine(pi/2 - r)`.  The `pi/2 - atan(1/x)` route for x > 1 (variants `taylor`, `quadrant`) loses
  a digit in the subtraction and returns .87266470: DVA prints 129.9.  The pi/3 offset
  (`atan=pi3`) keeps the series argument small and the sum exact enough.
* At 50 degrees `VA = .1999E 03` needs CTH2 <= .64278764 while STH2 at 40 degrees, the sine of
  almost the same angle, is .64278765: the cosine at 50 degrees is `sine(pi/2 - .87266463)`,
  and `pi/2 - r` must keep r's last digit (.69813167, not .69813170).  With the model
  subtraction (the subtrahend's last digit dropped on alignment) VA prints .2000E 03
  (`sine,reduce=model`, 81 fields).  `reduce=exact` forms those reduction differences
  exactly, as a library doing its reduction in a longer fixed-point field would, while pi/2
  is still the 8-digit constant.

So the best variant is fitted to a handful of threshold facts, by choices each of which a
1960s library plausibly made; it is not evidence of what IBM shipped.  SQRT's algorithm
changes nothing here (Newton from any start gives the truncated root).  Two further ideas
were tried outside the table, in a slow operator-level model: the 1410 adding with one guard
digit (global, not only in the library) gave 73 to 78 fields with every library tried, so the
no-guard-digit rule of the shared notes stands; and the Euler series for ATAN is off by
5E-7 in 8 digits and was dropped.
"""


def _trace_section(traces: dict) -> str:
    keys = ["TH2", "STH2", "CTH2", "VAX", "VAY", "VA X*X+Y*Y", "VA", "VA |Y|/|X|", "VA ATAN",
            "DVA", "VG2X", "VG2Y", "VG2 X*X+Y*Y", "VG2", "VG2 |Y|/|X|", "VG2 ATAN", "DVG2",
            "AG2X", "AG2Y", "AG2 X*X+Y*Y", "AG2", "AA X*X+Y*Y", "AA"]
    lines = ["**The 8-digit values behind the contested fields** "
             "(`sielaff.tools.bench.study.link2_trace`), "
             "for the new default `sine` and the old `taylor`.  VECTOR prints "
             "`SQRT(X*X+Y*Y)` and `(PI -+ ATAN(|Y|/|X|)) * 57.295779`; a printed .1999E 03 "
             "needs the sum of squares below .40000000E+05, 130.0 needs ATAN at most "
             ".87266459 (PI - ATAN aligns away ATAN's last digit; 3.1415926 - .8726646 = "
             "2.2689280 prints 129.9).\n",
             "| quantity | sine, 40 | taylor, 40 | sine, 50 | taylor, 50 |",
             "|---|---|---|---|---|"]
    for k in keys:
        label = k.replace("|Y|/|X|", "ABS(Y)/ABS(X)")  # a | would split the table cell
        cells = [traces[(v, th)][k] for th in (40, 50) for v in ("sine", "taylor")]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    lines.append("")
    lines.append("Figure 10 prints VA .1999E 03, DVA 130.0, VG2 .1000E 03, DVG2 129.9, AG2 "
                 ".5000E 04, AA .1000E 05; Figure 11 the same magnitudes and DVA 140.0.  "
                 "`taylor` has one STH2/CTH2 pair for VA and VG2 (ratio 1.1917536 for both), so "
                 "DVA and DVG2 cannot differ, and `5000*CTH2` drops a 5 (CTH2 odd), which "
                 "leaves AG2's sum of squares at .24999999E+08.\n")
    return "\n".join(lines)
