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
import time
from collections.abc import Callable, Sequence

import numpy as np

from sielaff.emulator.cards import read_deck
from sielaff.emulator.printer import NEARBY_ULPS
from sielaff.emulator.program import SHEET_FIELDS, Program, ProgramError, SheetLimit

MODELS = ("float64", "float32", "ibm1410:8", "ibm1410:12", "ibm1410:16")
ENGINE = "engine"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__))))))  # the checkout: decks/ and golden/
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

    import sielaff.emulator.program as prog

    mp = ar.mpmath
    subs = {"PI = num(3.14159265)": "PI = _EXACT_PI", "RAD = num(57.295779)": "RAD = _EXACT_RAD",
            "PI = ar.num(3.14159265)": "PI = _EXACT_PI",
            "RAD = ar.num(57.2957795)": "RAD = _EXACT_RAD"}
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
    from sielaff.emulator.arithmetic import get_arithmetic

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
    from sielaff.emulator.listing import diff_listings
    from sielaff.emulator.run import run

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
    :data:`~sielaff.emulator.printer.NEARBY_ULPS` of the model's value
    (:func:`~sielaff.emulator.printer.edits_nearby`): one text where the digits are
    certain on any CPU, two where a printed-digit boundary lies within reach of another
    machine's libm.
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
    from sielaff.emulator.arithmetic import get_arithmetic

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
    from sielaff.emulator.listing import parse_listing
    from sielaff.emulator.printer import edits_nearby
    from sielaff.mechanism import EXAMPLE

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
    from sielaff.emulator.arithmetic.ibm1410 import IBM1410

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
    from sielaff.emulator.arithmetic.ibm1410 import IBM1410

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
