"""Build and run the reconstructed 1966 FORTRAN deck (``decks/sielaff.f``) with gfortran.

This is a helper module for tests and benchmarks, not a test file.

The deck reads its cards on unit 1 and writes its listing on unit 3, as on the
IBM 1410.  gfortran connects unnumbered units to files named ``fort.<n>`` in the
working directory, so :func:`run` works in a fresh temporary directory, copies the
card deck to ``fort.1`` and reads the listing back from ``fort.3``.

Typical use::

    exe = build()
    text = run(exe, "decks/example.dat")
    sheets = parse_listing(text)
    sheets[3]["TORQ"]          # driving torque at the 4th position

gfortran prints ``E12.4`` as ``  0.5456E+03`` and ``F12.1`` rounded; the 1410 printed
``   .5456E 03`` and truncated.  :func:`parse_listing` reads the gfortran form (and
also the 1410 form with a blank exponent sign, so it can read transcribed listings).
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent
DECK_SOURCE = REPO_ROOT / "decks" / "sielaff.f"
LIB1410_SOURCE = REPO_ROOT / "decks" / "lib1410.f"

#: Flags that give the 1966 program's implicit REAL/INTEGER typing with REAL*8 reals.
BASE_FLAGS = ("-std=legacy", "-fdefault-real-8", "-fdefault-double-8")

#: The message FORMAT 20 prints when the link lengths fail the crank-rocker tests.
NOT_CRANK_ROCKER = "THIS IS NOT A CRANK ROCKER MECHANISM"

#: Each heading of an output sheet, and the names (from the listing's WRITE lists)
#: of the values printed under it, in order.
SHEET_LAYOUT: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("THETA 2", ("ATH2", "ATH3", "ATH4")),
    ("ANG VEL 3", ("TH3D", "TH4D", "TH3DD", "TH4DD")),
    ("EX TORQ ON 4", ("TEX",)),
    ("VEL G2", ("VG2", "VA", "VG3", "VB", "VG4", "DVG2", "DVA", "DVG3", "DVB", "DVG4")),
    ("ACC G2", ("AG2", "AA", "AG3", "AB", "AG4", "DAG2", "DAA", "DAG3", "DAB", "DAG4")),
    ("F 3 ON 2", ("FA32", "FB34", "FOA", "FOB", "DFA32", "DFB34", "DFOA", "DFOB")),
    ("SHAKE", ("SHAK", "SHAKX", "SHAKY", "DSHAK")),
    ("DRIVING TORQ", ("TORQ",)),
)

#: All 41 printed quantities of one sheet, in print order.
SHEET_KEYS: tuple[str, ...] = tuple(k for _, keys in SHEET_LAYOUT for k in keys)

_HEADINGS = {heading: keys for heading, keys in SHEET_LAYOUT}


def gfortran_available() -> bool:
    """True if a ``gfortran`` executable is on the PATH."""
    return shutil.which("gfortran") is not None


def _compiler_id() -> str:
    try:
        out = subprocess.run(
            ["gfortran", "--version"], capture_output=True, text=True, check=True
        ).stdout
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return out.splitlines()[0] if out else "unknown"


def _default_cache_root() -> Path:
    return Path(tempfile.gettempdir()) / "sielaff-fortran-build"


def build(
    tmpdir: str | os.PathLike[str] | None = None,
    opt: str = "-O0",
    extra_flags: tuple[str, ...] | list[str] = (),
    source: str | os.PathLike[str] | None = None,
    lib1410: bool = False,
) -> Path:
    """Compile the deck and return the path of the executable.

    The executable is cached under ``<tmpdir>/<hash>/sielaff`` (``tmpdir`` defaults to
    a fixed directory in the system temp dir), keyed on the source text, the flags and
    the compiler version, so repeated calls (and repeated test sessions) compile once.
    Raises ``RuntimeError`` with the compiler output if compilation fails.

    ``lib1410=True`` links ``decks/lib1410.f`` (SQRT of a negative argument
    returns SQRT(ABS(X)), as the 1410 library did) by declaring ``EXTERNAL
    SQRT`` at the top of each program unit of a copy of the deck.
    """
    if not gfortran_available():
        raise RuntimeError("gfortran is not installed")
    src = Path(source) if source is not None else DECK_SOURCE
    flags = [*BASE_FLAGS, opt, *extra_flags]
    key = hashlib.sha256()
    key.update(src.read_bytes())
    if lib1410:
        key.update(b"lib1410" + LIB1410_SOURCE.read_bytes())
    key.update("\0".join(flags).encode())
    key.update(_compiler_id().encode())
    root = Path(tmpdir) if tmpdir is not None else _default_cache_root()
    outdir = root / key.hexdigest()[:16]
    exe = outdir / "sielaff"
    if exe.exists():
        return exe
    outdir.mkdir(parents=True, exist_ok=True)
    # Compile in a private scratch dir (gfortran may drop .mod files there), then
    # rename into place so concurrent builders never see a half-written file.
    with tempfile.TemporaryDirectory(dir=outdir) as scratch:
        tmp_exe = Path(scratch) / "sielaff"
        sources = [str(src.resolve())]
        if lib1410:
            deck = Path(scratch) / "sielaff1410.f"
            deck.write_text(_declare_external_sqrt(src.read_text()))
            sources = [str(deck), str(LIB1410_SOURCE)]
        proc = subprocess.run(
            ["gfortran", *flags, "-o", str(tmp_exe), *sources],
            capture_output=True,
            text=True,
            cwd=scratch,
            check=False,
        )
        if proc.returncode != 0:
            raise RuntimeError(
                f"gfortran failed ({proc.returncode}) on {src}:\n{proc.stdout}{proc.stderr}"
            )
        os.replace(tmp_exe, exe)
    return exe


def _declare_external_sqrt(text: str) -> str:
    """The deck with ``EXTERNAL SQRT`` as the first statement of every program unit."""
    out: list[str] = []
    declared = False
    for line in text.splitlines():
        is_comment = line[:1] in ("C", "c", "*")
        if not declared and not is_comment and line.strip():
            # first statement of the main program
            out.append("      EXTERNAL SQRT")
            declared = True
        out.append(line)
        if re.match(r"^\s{6}\s*(FUNCTION|SUBROUTINE)\b", line):
            out.append("      EXTERNAL SQRT")
    return "\n".join(out) + "\n"


def run(exe: str | os.PathLike[str], deck_path: str | os.PathLike[str], timeout: float = 60) -> str:
    """Run the program on a card deck (a text file, one card per line).

    Returns the text written on unit 3 (the printed listing).  Raises
    ``RuntimeError`` if the program ends abnormally (e.g. a short deck makes one of
    the first six READs hit end of file: only the READ at statement 27 has END=).
    """
    with tempfile.TemporaryDirectory(prefix="sielaff-run-") as work:
        shutil.copyfile(deck_path, Path(work) / "fort.1")
        proc = subprocess.run(
            [str(Path(exe).resolve())],
            cwd=work,
            capture_output=True,
            text=True,
            timeout=timeout,
            stdin=subprocess.DEVNULL,
            check=False,
        )
        out = Path(work) / "fort.3"
        text = out.read_text() if out.exists() else ""
    if proc.returncode != 0:
        raise RuntimeError(
            f"program failed ({proc.returncode}):\n{proc.stdout}{proc.stderr}\n"
            f"--- unit 3 ---\n{text}"
        )
    return text


def run_deck_text(exe: str | os.PathLike[str], deck_text: str, timeout: float = 60) -> str:
    """Like :func:`run` but takes the cards as a string."""
    with tempfile.TemporaryDirectory(prefix="sielaff-deck-") as d:
        path = Path(d) / "deck.dat"
        path.write_text(deck_text)
        return run(exe, path, timeout=timeout)


def format_card(*values: float) -> str:
    """One ``4F8.4`` card with explicit decimal points (blank fields read as zero)."""
    if len(values) > 4:
        raise ValueError("a 4F8.4 card holds at most 4 values")
    fields = []
    for v in values:
        s = repr(float(v))
        if len(s) > 8 or "e" in s:
            s = f"{float(v):8.4f}".strip()
        if len(s) > 8:
            raise ValueError(f"{v!r} does not fit an F8.4 field")
        fields.append(s.rjust(8))
    return "".join(fields)


_NUM = re.compile(r"^([-+]?(?:\d+\.?\d*|\.\d+))(?:[EeDd]?\s*([-+ ]\s*\d+))?$")


def parse_number(field: str) -> float:
    """Read one printed E or F field.

    Accepts gfortran's ``0.5456E+03``, the 3-digit-exponent form ``0.5456+103``,
    the 1410's ``.5456E 03`` and ``-.2707E 02``; an all-asterisk field is NaN.
    """
    s = field.strip()
    if s and set(s) == {"*"}:
        return float("nan")
    m = _NUM.match(s)
    if not m:
        raise ValueError(f"not a printed number: {field!r}")
    mant, exp = m.groups()
    if exp is None:
        return float(mant)
    exp = exp.replace(" ", "") or "0"
    if exp[0] not in "+-":
        exp = "+" + exp
    return float(f"{mant}e{exp}")


def _split_fields(body: str) -> list[str]:
    # The 1410 form ".5456E 03" has a blank inside the field: rejoin "E" + exponent.
    body = re.sub(r"([EeDd])\s+(\d)", r"\1+\2", body)
    return body.split()


def parse_listing(text: str) -> list[dict[str, float]]:
    """Parse a listing into one dict per output sheet (keys: :data:`SHEET_KEYS`).

    The first character of every record is carriage control and is skipped.  A
    sheet starts at its ``THETA 2`` heading; values are read from the non-blank
    records that follow each heading.  The crank-rocker rejection message is not a
    sheet: test for it with :func:`not_crank_rocker`.
    """
    sheets: list[dict[str, float]] = []
    current: dict[str, float] | None = None
    pending: list[str] = []
    values: list[float] = []

    def close_block() -> None:
        if current is None or not pending:
            return
        if len(values) != len(pending):
            raise ValueError(
                f"sheet {len(sheets)}: expected {len(pending)} values for {pending}, got {values}"
            )
        current.update(zip(pending, values))

    for record in text.splitlines():
        body = record[1:] if record else ""
        stripped = body.strip()
        if not stripped or NOT_CRANK_ROCKER in stripped:
            continue
        heading = next((h for h in _HEADINGS if stripped.startswith(h)), None)
        if heading is not None:
            close_block()
            if heading == "THETA 2":
                current = {}
                sheets.append(current)
            elif current is None:
                raise ValueError(f"heading {heading!r} before any THETA 2 heading")
            pending = list(_HEADINGS[heading])
            values = []
            continue
        if current is None:
            raise ValueError(f"unexpected record before first sheet: {record!r}")
        values.extend(parse_number(f) for f in _split_fields(body))
    close_block()
    for i, sheet in enumerate(sheets):
        missing = [k for k in SHEET_KEYS if k not in sheet]
        if missing:
            raise ValueError(f"sheet {i} is incomplete, missing {missing}")
    return sheets


def not_crank_rocker(text: str) -> bool:
    """True if the listing contains FORMAT 20's rejection message."""
    return any(line[1:].strip() == NOT_CRANK_ROCKER for line in text.splitlines())
