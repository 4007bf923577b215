"""Accuracy against cost: the study behind ``docs/accuracy.md``.

``sielaff bench`` (quick) and ``benchmarks/accuracy.py`` (full) both call
:func:`study` and :func:`write_report`.  Three questions:

1. **Arithmetic models.**  The line-by-line port on float64, float32 and the
   IBM 1410 model at K = 8, 12, 16 digits, and the numpy engine: time per
   position, the error over the example's revolution at 1 degree, and how many
   of the 82 printed fields of Figures 10 and 11 each reproduces.  Two
   references, both the port run in 50-digit mpmath arithmetic (:class:`MPMath`):

   * *same program* -- the listing exactly, its ARCCOS series with the 1E-8
     stopping test and its short constants (``PI=3.14159265``,
     ``RAD=57.295779``) included.  The difference is the **arithmetic error**:
     what the number model adds to the 1966 algorithm.
   * *exact mechanics* -- the same formulas with an exact arccos and exact pi
     and 180/pi (:func:`exact_program`).  The difference is the **total error**;
     total minus arithmetic is the 1966 program's algorithm error (the 1E-8
     ARCCOS tolerance, the 8-9 digit constants), which no arithmetic removes.

   Errors are *scaled*: ``|x - ref| / max |ref|`` with the maximum over the
   revolution of that quantity (a relative error that stays meaningful where a
   force component passes through zero).  A direction is the direction of a
   vector: its error (radians, modulo 2 pi) is weighted by ``|magnitude| / max
   |magnitude|``, so a velocity that passes through zero (VB at the rocker's
   dead centre) does not count its meaningless direction; THETA 3 and THETA 4
   count their error in radians.  Every printed quantity but THETA 2 and TEX
   (the inputs) counts.

2. **ARCCOS tolerance**: the listing's series in float64 with its stopping test
   ``ABS(SUM-SAVE) < tol`` for tol = 1E-2 .. 1E-15: terms used, worst error
   against ``math.acos`` over X in [-1, 1], time per call.

3. **Step size**: the cycle work of the driving torque, ``sum TORQ * DELTA``
   over one revolution, which is exactly zero for TEX = 0 (the report's energy
   argument), against DELTA from 10 to 0.01 degrees, with the run time, for the
   engine and the port in float64.
"""

from __future__ import annotations

import dataclasses
import io
import math
import os
import platform
import statistics
import sys
import time
from collections.abc import Callable, Sequence

import numpy as np

from sielaff.cards import read_deck
from sielaff.printer import NEARBY_ULPS
from sielaff.program import SHEET_FIELDS, Program, ProgramError, SheetLimit

MODELS = ("float64", "float32", "ibm1410:8", "ibm1410:12", "ibm1410:16")
ENGINE = "engine"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLE_DECK = os.path.join(ROOT, "decks", "example.dat")
GOLDEN_FILES = (os.path.join(ROOT, "golden", "figure10.asa"),
                os.path.join(ROOT, "golden", "figure11.asa"))

#: printed quantities compared (all but the inputs ATH2 and TEX)
FIELDS = tuple(f for group in SHEET_FIELDS for f in group if f not in ("ATH2", "TEX"))
#: directions in degrees (compared modulo 360)
ANGLES = frozenset(f for f in FIELDS if f.startswith("D") or f in ("ATH3", "ATH4"))


# -- a 50-digit arithmetic for the port ------------------------------------------------
class MPMath:
    """mpmath numbers at ``dps`` digits with the mpmath library: the reference model.

    Set ``mpmath.mp.dps`` with :meth:`precision` around a run (mpmath's precision
    is global).  Python float literals in the port convert exactly from binary,
    as they do for float64.
    """

    def __init__(self, dps: int = 50) -> None:
        import mpmath

        self.mpmath = mpmath
        self.dps = dps
        self.name = f"mpmath:{dps}"
        self.ABS = abs
        self.SIN, self.COS, self.ATAN = mpmath.sin, mpmath.cos, mpmath.atan
        self.on_error = lambda _msg: None

    def precision(self):
        return self.mpmath.workdps(self.dps)

    def num(self, value):
        return self.mpmath.mpf(value if isinstance(value, str) else float(value))

    def SQRT(self, x):
        return self.mpmath.sqrt(abs(x))


def exact_program(ar: MPMath) -> Program:
    """The port with exact arccos, and exact pi and 180/pi in MAIN and VECTOR.

    Built by substituting the listing's constants in the source of ``MAIN`` and
    ``VECTOR`` (and raising if they are not found, so a change to the port is
    noticed); ARCCOS is replaced by ``mpmath.acos``.
    """
    import inspect
    import textwrap

    import sielaff.program as prog

    mp = ar.mpmath
    subs = {"PI = 3.14159265": "PI = _EXACT_PI", "RAD = 57.295779": "RAD = _EXACT_RAD",
            "RAD = 57.2957795": "RAD = _EXACT_RAD"}
    namespace = dict(vars(prog))
    namespace["_EXACT_PI"] = mp.pi
    namespace["_EXACT_RAD"] = 180 / mp.pi
    methods = {}
    for name in ("MAIN", "VECTOR"):
        src = textwrap.dedent(inspect.getsource(getattr(Program, name)))
        lines = src.splitlines()
        hits = 0
        for i, line in enumerate(lines):
            code = line.split("#", 1)[0].strip()
            if code in subs:
                lines[i] = line.replace(code, subs[code])
                hits += 1
        if hits < 2:
            raise RuntimeError(f"exact_program: the constants of Program.{name} were not found")
        exec("\n".join(lines), namespace)  # noqa: S102 - our own source, substituted
        methods[name] = namespace[name]

    class ExactProgram(Program):
        MAIN = methods["MAIN"]
        VECTOR = methods["VECTOR"]

        def ARCCOS(self, X):
            return mp.acos(X)

    return ExactProgram(ar)


# -- running the port ----------------------------------------------------------------------
def example_deck(thzero: float = 0.0, delta: float = 1.0, thmax: float | None = None,
                 mechanism=None):
    """The report's example deck with one range card (default: 0..359 by 1 degree)."""
    deck = read_deck(EXAMPLE_DECK)
    if thmax is None:  # the 1966 loop prints one sheet past THMAX: 360 - delta is the last
        thmax = 360.0 - 1.5 * delta  # (half a step of slack for the float sum TH + I*DELTA)
    deck = dataclasses.replace(deck, ranges=[(thzero, delta, thmax)])
    if mechanism is not None:
        deck = dataclasses.replace(deck, mechanism=mechanism)
    return deck


def port_values(program: Program, deck, fields: Sequence[str] = FIELDS) -> dict[str, np.ndarray]:
    """Run ``program`` on ``deck``; the printed quantities as float arrays (one per field)."""
    values: dict[str, list[float]] = {f: [] for f in fields}
    wanted = frozenset(fields)
    group = [0]

    def write(fmt: int, *vals) -> None:
        if fmt == 18:
            group[0] = 0
        elif vals:
            for name, v in zip(SHEET_FIELDS[group[0]], vals):
                if name in wanted:
                    values[name].append(float(v))
            group[0] += 1

    program.MAIN(deck, write)
    return {f: np.array(v) for f, v in values.items()}


def make_arithmetic(name: str):
    from sielaff.arithmetic import get_arithmetic

    return get_arithmetic(name)


def time_port(name: str, deck, repeat: int = 1) -> tuple[float, int]:
    """Best wall time of ``repeat`` runs of the port (no printing), and the sheet count."""
    best = math.inf
    sheets = 0
    for _ in range(repeat):
        ar = make_arithmetic(name)
        count = [0]

        def write(fmt, *_v, count=count):
            if fmt == 18:
                count[0] += 1

        t0 = time.perf_counter()
        Program(ar).MAIN(deck, write)
        best = min(best, time.perf_counter() - t0)
        sheets = count[0]
    return best, sheets


def time_engine(mechanism, ath2, repeat: int = 5) -> float:
    from sielaff.engine import analyze

    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        analyze(mechanism, ath2)
        best = min(best, time.perf_counter() - t0)
    return best


def engine_values(mechanism, ath2, fields: Sequence[str] = FIELDS) -> dict[str, np.ndarray]:
    from sielaff.engine import analyze

    out = analyze(mechanism, np.asarray(ath2, dtype=float), outputs=list(fields))
    return {f: np.asarray(out[f], dtype=float) for f in fields}


# -- errors ----------------------------------------------------------------------------------
def _field_errors(f: str, x: np.ndarray, r: np.ndarray, ref: dict[str, np.ndarray]) -> np.ndarray:
    if f in ANGLES:
        d = np.radians(np.abs((x - r + 180.0) % 360.0 - 180.0))
        mag = ref.get(f[1:]) if f.startswith("D") else None
        if mag is not None:  # the direction of a vector: weight by its scaled magnitude
            scale = np.max(np.abs(mag))
            d = d * (np.abs(mag) / scale if scale else 0.0)
        return d
    scale = np.max(np.abs(r))
    return np.abs(x - r) / scale if scale else np.abs(x - r)


def scaled_errors(values: dict[str, np.ndarray], ref: dict[str, np.ndarray]) -> np.ndarray:
    """All scaled errors (see the module doc), one per field and position, flattened."""
    return np.concatenate([_field_errors(f, values[f], ref[f], ref) for f in FIELDS])


def worst_field(values, ref) -> tuple[str, int, float]:
    """(field, position index, scaled error) of the largest scaled error."""
    best = ("", 0, -1.0)
    for f in FIELDS:
        d = _field_errors(f, values[f], ref[f], ref)
        i = int(np.argmax(d))
        if d[i] > best[2]:
            best = (f, i, float(d[i]))
    return best


# -- Figures 10 and 11 ---------------------------------------------------------------------
def golden_text() -> str:
    return "".join(open(p, encoding="ascii").read() for p in GOLDEN_FILES)


def figure_diffs(arithmetic) -> list[str]:
    """``diff_listings`` lines of the example's 40- and 50-degree sheets against the figures."""
    from sielaff.emulator import run
    from sielaff.listing import diff_listings

    out = io.StringIO()
    try:
        run(read_deck(EXAMPLE_DECK), out, arithmetic=arithmetic, max_sheets=5)
    except SheetLimit:
        pass
    return diff_listings(out.getvalue(), golden_text())


@dataclasses.dataclass(frozen=True)
class FigureField:
    """One printed field of Figures 10-11: what a model prints and what the 1410 printed.

    ``nearby`` holds every text the field prints for values within
    :data:`~sielaff.printer.NEARBY_ULPS` of the model's value (:func:`printer.edits_nearby`):
    one text where the digits are certain on any CPU, two where a printed-digit boundary
    lies within reach of another machine's libm.
    """

    theta: int
    name: str
    got: str
    golden: str
    nearby: tuple[str, ...]

    @property
    def certain(self) -> bool:
        return len(self.nearby) == 1

    @property
    def short(self) -> str:
        return f"{self.theta} {self.name} {self.got}"


def _raw_sheets(arithmetic, count: int) -> list[dict]:
    """The port's unprinted values (in the model's own number type), first ``count`` sheets."""
    from sielaff.arithmetic import get_arithmetic

    sheets: list[dict] = []
    current: dict = {}
    group = [0]

    class Enough(Exception):
        pass

    def write(fmt: int, *vals) -> None:
        if fmt == 18:  # the page eject that ends a sheet
            sheets.append(dict(current))
            current.clear()
            group[0] = 0
            if len(sheets) == count:
                raise Enough
        elif vals:
            current.update(zip(SHEET_FIELDS[group[0]], vals))
            group[0] += 1

    try:
        Program(get_arithmetic(arithmetic)).MAIN(read_deck(EXAMPLE_DECK), write)
    except Enough:
        pass
    return sheets


def figure_fields(model) -> list[FigureField]:
    """Every printed field of the 40- and 50-degree sheets: ``model`` (an arithmetic, its
    name, or :data:`ENGINE`) against the figures, with the texts within reach."""
    from sielaff.listing import parse_listing
    from sielaff.mechanism import EXAMPLE
    from sielaff.printer import edits_nearby

    golden = parse_listing(golden_text())
    if model == ENGINE:
        raw = []
        for sheet in golden:
            theta = float(sheet.theta2)
            vals = engine_values(EXAMPLE, [theta], [f for f in sheet.fields if f != "ATH2"])
            row = {k: v[0] % 360.0 if k in ANGLES else v[0] for k, v in vals.items()}
            raw.append({"ATH2": np.float64(theta), **row})
    else:
        by_theta = {}
        for values in _raw_sheets(model, 5):
            by_theta[int(float(values["ATH2"]))] = values
        raw = [by_theta[int(float(sheet.theta2))] for sheet in golden]
    out = []
    for sheet, values in zip(golden, raw):
        for name, fld in sheet.fields.items():
            # ATH2 and TEX are inputs, made by correctly rounded + and * alone
            exact = name not in FIELDS or values[name] == 0
            nearby = edits_nearby(values[name], fld.kind, ulps=0 if exact else NEARBY_ULPS)
            got = (nearby[0] if len(nearby) == 1 else
                   edits_nearby(values[name], fld.kind, ulps=0)[0])
            out.append(FigureField(int(float(sheet.theta2)), name, got.strip(),
                                   fld.text.strip(), tuple(t.strip() for t in nearby)))
    return out


#: The library variants tried against Figures 10 and 11 (docs/accuracy.md explains each).
VARIANTS_TRIED: tuple[tuple[str, str], ...] = (
    ("sine", "new default: SIN core in Horner form, COS = sine(pi/2 - r), exact reduction, "
             "ATAN pi/6 + pi/3 offsets"),
    ("taylor", "previous default: Taylor to convergence on [0, pi/4], ATAN pi/6 offset"),
    ("quadrant", "Taylor on [0, pi/2], ATAN pi/4 offset, SQRT Newton from 1"),
    ("hastings", "Hastings polynomials (A&S 4.3.97, 4.3.99, 4.4.49), fixed Newton steps"),
    ("taylor,cos=shift", "COS(X) = SIN(X + pi/2)"),
    ("taylor,final=round2", "library with 2 guard digits, result rounded"),
    ("taylor,atan=pi3", "ATAN with pi/6 and pi/3 offsets (no inversion up to tan 75)"),
    ("taylor,reduce=exact", "Taylor, reduction subtractions exact then truncated"),
    ("sine,reduce=model,atan=pi6", "SIN core, K-digit reduction, ATAN pi/6 offset"),
    ("sine,reduce=model", "SIN core, K-digit reduction (pi/2 - r drops a digit)"),
    ("sine,atan=pi6", "SIN core, exact reduction, ATAN pi/6 offset"),
    ("sine,atan=pi4", "SIN core, exact reduction, ATAN pi/4 offset"),
    ("sine,atan=hastings", "SIN core, exact reduction, Hastings ATAN"),
    ("sine,trig=hastings", "exact reduction, Hastings SIN and COS polynomials"),
    ("sine,final=round2", "the default with 2 guard digits, result rounded"),
    ("sine,sqrt=one", "the default, SQRT Newton from 1.0"),
    ("sine,sqrt=fixed", "the default, SQRT with fixed Newton steps"),
)


def variant_table() -> list[tuple[str, str, int, list[str]]]:
    from sielaff.ibm1410 import IBM1410

    rows = []
    for variant, what in VARIANTS_TRIED:
        d = figure_diffs(IBM1410(8, variant=variant))
        rows.append((variant, what, 82 - len(d), [_short(x) for x in d]))
    return rows


def _short(diff_line: str) -> str:
    """'THETA 2 = 40.0: DVA (VEL A direction): got 129.9, ...' -> '40 DVA 129.9'."""
    head, _, rest = diff_line.partition(": ")
    name = rest.split(" ", 1)[0]
    got = rest.split("got ", 1)[1].split(",", 1)[0]
    return f"{head.split('= ')[1].split('.')[0]} {name} {got}"


# -- the field-by-field explanation at 40 and 50 degrees ------------------------------------
def link2_trace(variant: str, theta: int) -> dict[str, str]:
    """The 1410 model's digits of every step from TH2 to VA, DVA, VG2, DVG2, AG2, AA."""
    from sielaff.ibm1410 import IBM1410

    A = IBM1410(8, variant=variant)
    n = A.num
    P = Program(A)
    th2 = n(theta) / n(57.295779)
    s, c = A.SIN(th2), A.COS(th2)
    R2, RG2, TH2D = n(4.0), n(2.0), n(50.0)
    SQ2D = TH2D * TH2D
    t = {"TH2": th2, "STH2": s, "CTH2": c}
    for name, x, y in (("VA", -R2 * TH2D * s, R2 * TH2D * c),
                       ("VG2", -RG2 * TH2D * s, RG2 * TH2D * c),
                       ("AA", -R2 * SQ2D * c, -R2 * SQ2D * s),
                       ("AG2", -RG2 * SQ2D * c, -RG2 * SQ2D * s)):
        t[name + "X"], t[name + "Y"] = x, y
        t[name + " X*X+Y*Y"] = x * x + y * y
        t[name + " |Y|/|X|"] = abs(y) / abs(x)
        t[name + " ATAN"] = A.ATAN(abs(y) / abs(x))
        mag, direction = P.VECTOR(x, y)
        t[name] = mag
        t["D" + name] = direction
    return {k: str(v) for k, v in t.items()}


# -- ARCCOS ------------------------------------------------------------------------------------
ARCCOS_MAX_TERMS = 10_000


def arccos_listing(X: float, tol: float) -> tuple[float, int]:
    """FUNCTION ARCCOS in float64 with the stopping test ``ABS(SUM-SAVE) < tol``.

    Returns (value, terms).  Raises ProgramError past ARCCOS_MAX_TERMS terms."""
    PI = 3.14159265358979323846
    ZMULT = PROD = 1.0
    SAVE = 0.1e-50
    XX = X
    X2 = XX * XX
    if not abs(XX) <= 0.7:
        XX = math.sqrt(abs(1.0 - X2))
        X2 = XX * XX
    SUM = PI / 2.0 - XX
    VAL = XX
    A = 0.0
    terms = 0
    for terms in range(1, ARCCOS_MAX_TERMS + 1):  # noqa: B007 - the count is returned
        A = A + 2.0
        PROD = PROD * A
        VAL = VAL * X2
        ZMULT = ZMULT * (A - 1.0)
        SUM = SUM - (ZMULT * VAL) / (PROD * (A + 1.0))
        if abs(SUM - SAVE) < tol:
            break
        SAVE = SUM
    else:
        raise ProgramError(f"ARCCOS({X}) did not converge to {tol} in {ARCCOS_MAX_TERMS} terms")
    if X < -0.70:
        return PI / 2.0 + SUM, terms
    if X > 0.70:
        return PI / 2.0 - SUM, terms
    return SUM, terms


def arccos_study(tolerances: Sequence[float], points: int) -> list[dict]:
    xs = np.linspace(-1.0, 1.0, points)
    rows = []
    for tol in tolerances:
        worst = 0.0
        worst_x = 0.0
        terms = []
        t0 = time.perf_counter()
        for x in xs:
            v, k = arccos_listing(float(x), tol)
            terms.append(k)
            e = abs(v - math.acos(x))
            if e > worst:
                worst, worst_x = e, float(x)
        dt = (time.perf_counter() - t0) / points
        rows.append({"tol": tol, "mean_terms": statistics.fmean(terms), "max_terms": max(terms),
                     "worst": worst, "worst_x": worst_x, "us_per_call": dt * 1e6})
    return rows


# -- step size -------------------------------------------------------------------------------
STEPS = (90.0, 60.0, 45.0, 30.0, 20.0, 10.0, 5.0, 2.0, 1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01)


def cycle_work(torq: np.ndarray, delta_deg: float) -> tuple[float, float]:
    """(sum TORQ dtheta, sum |TORQ| dtheta) over one revolution sampled every delta_deg."""
    h = math.radians(delta_deg)
    return float(np.sum(torq) * h), float(np.sum(np.abs(torq)) * h)


def step_study(steps: Sequence[float], port_min_step: float) -> list[dict]:
    from sielaff.engine import analyze
    from sielaff.mechanism import EXAMPLE

    fine = analyze(EXAMPLE, np.arange(360_000) * 0.001, outputs=["TORQ"])["TORQ"]
    peak = float(np.max(np.abs(fine)))  # the peak driving torque, on a 0.001-degree grid
    rows = []
    for delta in steps:
        n = round(360.0 / delta)
        ath2 = np.arange(n) * delta
        best = math.inf
        for _ in range(3):
            t0 = time.perf_counter()
            torq = analyze(EXAMPLE, ath2, outputs=["TORQ"])["TORQ"]
            best = min(best, time.perf_counter() - t0)
        w, wabs = cycle_work(np.asarray(torq, dtype=float), delta)
        row = {"delta": delta, "positions": n, "engine_rel": abs(w) / wabs, "engine_s": best,
               "work_abs": wabs, "port_rel": None, "port_s": None,
               "peak_rel": (peak - float(np.max(np.abs(torq)))) / peak}
        if delta >= port_min_step:
            deck = example_deck(0.0, delta)
            t0 = time.perf_counter()
            vals = port_values(Program(make_arithmetic("float64")), deck, ["TORQ"])["TORQ"]
            row["port_s"] = time.perf_counter() - t0
            if len(vals) != n:
                raise RuntimeError(f"the port printed {len(vals)} positions, not {n}")
            w, wabs = cycle_work(vals, delta)
            row["port_rel"] = abs(w) / wabs
        rows.append(row)
    return rows


def coarsest_step(rows: list[dict], tolerance: float, key: str = "engine_rel") -> dict | None:
    """The row with the largest DELTA whose cycle-work error (and every finer one's) is <= tol."""
    ok = None
    for row in sorted(rows, key=lambda r: r["delta"]):
        if row[key] is None:  # not computed at this step
            continue
        if row[key] > tolerance:
            break
        ok = row
    return ok


# -- the model study ---------------------------------------------------------------------------
def model_study(delta: float = 1.0, repeat: int = 3, progress: Callable[[str], None] = print):
    """Per model: time per position, scaled errors against both references, figure fields."""
    from sielaff.mechanism import EXAMPLE

    deck = example_deck(0.0, delta)
    ref_ar = MPMath(50)
    with ref_ar.precision():
        progress("reference: the port at 50 digits")
        same = port_values(Program(ref_ar), deck)
        progress("reference: exact mechanics at 50 digits")
        exact = port_values(exact_program(ref_ar), deck)
    n = len(same["TH3D"])
    ath2 = np.arange(n) * delta
    rows = []
    for name in MODELS:
        progress(f"model {name}")
        secs, sheets = time_port(name, deck, repeat=repeat)
        vals = port_values(Program(make_arithmetic(name)), deck)
        rows.append(_model_row(name, secs / sheets, vals, same, exact, figure_fields(name)))
    progress("engine")
    secs = time_engine(EXAMPLE, ath2)
    vals = engine_values(EXAMPLE, ath2)
    rows.append(_model_row(ENGINE, secs / n, vals, None, exact, figure_fields(ENGINE)))
    algo = scaled_errors(same, exact)
    return {"rows": rows, "positions": n, "delta": delta,
            "algorithm_max": float(np.max(algo)), "algorithm_median": float(np.median(algo)),
            "algorithm_worst": worst_field(same, exact)}


def _model_row(name, per_position, vals, same, exact, fields: list[FigureField]) -> dict:
    """``fields``: certain matches; ``diffs``: certain differences; ``boundary``: the
    fields within reach of a printed-digit boundary (either text may print)."""
    row = {"model": name, "us_per_position": per_position * 1e6,
           "fields": sum(f.certain and f.got == f.golden for f in fields),
           "diffs": [f.short for f in fields if f.certain and f.got != f.golden],
           "boundary": [f"{f.theta} {f.name}" for f in fields if not f.certain]}
    for label, ref in (("same", same), ("exact", exact)):
        if ref is None:
            row[label + "_max"] = row[label + "_median"] = None
            continue
        e = scaled_errors(vals, ref)
        row[label + "_max"] = float(np.max(e))
        row[label + "_median"] = float(np.median(e))
        row[label + "_worst"] = worst_field(vals, ref)
    return row


# -- the whole study and the report ------------------------------------------------------------
def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        load = f", load average {os.getloadavg()[0]:.1f} at the start"
    except (AttributeError, OSError):
        load = ""
    return (f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()} "
            f"({platform.python_implementation()}), numpy {np.__version__}, {platform.system()}"
            f"{load}")


def study(quick: bool = False, progress: Callable[[str], None] = print) -> dict:
    t0 = time.perf_counter()
    res = {"machine": machine(), "quick": quick}
    progress("figure fields of the library variants")
    res["variants"] = variant_table()
    res["models"] = model_study(delta=1.0, repeat=1 if quick else 3, progress=progress)
    progress("ARCCOS tolerance")
    tols = [10.0**-k for k in range(2, 16)]
    res["arccos"] = arccos_study(tols, 2001 if quick else 20001)
    progress("step size")
    res["steps"] = step_study(STEPS, port_min_step=0.1 if quick else 0.01)
    res["traces"] = {(v, th): link2_trace(v, th) for v in ("sine", "taylor") for th in (40, 50)}
    res["seconds"] = time.perf_counter() - t0
    return res


# -- the figure --------------------------------------------------------------------------------
def plot(res: dict, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(15, 5.6), constrained_layout=True)
    # (a) models: cost against accuracy
    colors = {"float64": "C0", "float32": "C1", "ibm1410:8": "C3", "ibm1410:12": "C4",
              "ibm1410:16": "C5", ENGINE: "C2"}
    for row in res["models"]["rows"]:
        c = colors[row["model"]]
        t = row["us_per_position"]
        a1.scatter([t], [max(row["exact_median"], 1e-17)], color=c, marker="o", s=50)
        a1.scatter([t], [row["exact_max"]], color=c, marker="^", s=50)
        if row["same_median"] is not None:
            a1.scatter([t], [max(row["same_median"], 1e-17)], edgecolors=c, marker="s",
                       facecolors="none", s=50)
        dy = {"ibm1410:12": -26, "ibm1410:16": 14}.get(row["model"], 4)
        either = f" (+{len(row['boundary'])} either way)" if row["boundary"] else ""
        a1.annotate(f"{row['model']}\n{row['fields']}/82 fields{either}", (t, row["exact_max"]),
                    textcoords="offset points", xytext=(6, dy), fontsize=8, color=c)
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
    fig.savefig(path, dpi=110)
    plt.close(fig)


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
    from sielaff.output import atomic_files

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
      "come from that one command (`sielaff bench` runs the same study, `src/sielaff/bench.py`)."
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
      "parts to choose (`sielaff.ibm1410`, variant syntax `--arith ibm1410:8,PRESET,part=choice`)."
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
      "(`sielaff.bench.coarsest_step(rows, tolerance, key)`, key `engine_rel`, `peak_rel` or "
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
    lines = ["**The 8-digit values behind the contested fields** (`sielaff.bench.link2_trace`), "
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


def main(argv: Sequence[str] | None = None) -> int:
    import argparse

    p = argparse.ArgumentParser(description="the accuracy/cost study (docs/accuracy.md)")
    p.add_argument("--quick", action="store_true", help="fewer ARCCOS points and port steps")
    p.add_argument("-o", "--output", default=os.path.join(ROOT, "docs", "accuracy.md"))
    args = p.parse_args(argv)
    res = study(args.quick, progress=lambda s: print(f"bench: {s}", file=sys.stderr))
    write_report(res, args.output, command="python benchmarks/accuracy.py"
                 + (" --quick" if args.quick else ""))
    print(f"wrote {args.output}", file=sys.stderr)
    return 0
