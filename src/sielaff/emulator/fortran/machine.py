"""Running compiled program units: the statements in order, GO TO by statement number,
calls by reference, READ through the card reader, WRITE through the 1410 printer."""

from __future__ import annotations

import math
from collections.abc import Callable

from sielaff.emulator.arithmetic import ArithmeticError1410
from sielaff.emulator.fortran.compiler import compile_source, numpy_quiet
from sielaff.emulator.fortran.source import (
    INTEGER_DIGITS,
    INTEGER_LIMIT,
    LIBRARY,
    RECORDS_PER_SHEET,
    SHEETS_PER_DECK_SHEET,
    STATEMENT_BUDGET,
    STATEMENTS_PER_SHEET,
    FortranError,
    Statement,
    Unit,
    implicit_type,
)
from sielaff.emulator.printer import Format, FormatError, Unprintable, _strict_value
from sielaff.emulator.program import NotCrankRocker

#: The record FORMAT 20 of the 1966 program prints before it stops.
NOT_CRANK_ROCKER = " THIS IS NOT A CRANK ROCKER MECHANISM"

# -- running -----------------------------------------------------------------------

class PageLimit(Exception):
    """``max_pages`` sheets (page ejects, carriage control 1) were printed and the program
    would print more; ``args[0]`` is the count."""


#: An output argument the caller has not set yet (VECTOR's VECT and DIRECT).
_UNSET = object()


class _Return(Exception):
    pass


class _Stop(Exception):
    pass


class Program:
    """A compiled deck on one arithmetic, reading ``cards`` (lists of values, one per card)
    and writing records through ``emit``.

    The budget (docs/interpreter.md): ``max_pages`` (``--max-sheets``) stops the run
    quietly (:class:`PageLimit`); without it the run may print ``SHEETS_PER_DECK_SHEET``
    times ``sheets + 1`` sheets, ``sheets`` being what the deck's range cards ask for.
    Every sheet holds at most ``RECORDS_PER_SHEET`` records, and the run executes at most
    ``STATEMENTS_PER_SHEET`` statements per sheet (``sheets`` or ``max_pages``, plus one)
    and ``STATEMENT_BUDGET`` without a line printed.  Past any of them: one FortranError.
    """

    def __init__(self, units: dict[str, Unit], ar, cards, emit: Callable[[str], None],
                 path: str = "<program>", max_pages: int | None = None,
                 sheets: int = 0) -> None:
        self.units, self.ar, self.cards, self.emit, self.path = units, ar, cards, emit, path
        self.max_pages, self.pages, self.records = max_pages, 0, 0
        self.sheets = max_pages if max_pages is not None else sheets
        self.page_ceiling = (None if max_pages is not None
                             else SHEETS_PER_DECK_SHEET * (self.sheets + 1))
        self.statement_ceiling = STATEMENTS_PER_SHEET * (self.sheets + 1)
        self.active: set[str] = set()
        self.card = 0
        self.quiet = 0  # statements since the last line printed
        self.executed = 0  # statements in all
        self.not_crank_rocker = False  # the program printed FORMAT 20's message
        self.st: Statement | None = None  # the statement running (for _pow's errors)
        self.env = {unit.name: self._environment(unit) for unit in units.values()}

    def _environment(self, unit: Unit) -> dict:
        ar = self.ar
        env = dict(unit.consts)
        env.update({"_num": ar.num, "_idiv": _idiv, "_pow": self._pow, "_FLOAT": ar.num,
                    "_IFIX": _ifix, "_INT": _ifix, "_IABS": abs, "_MOD": _mod,
                    "_ichk": _ichk, "_rdiv": _rdiv})
        # a FUNCTION reference in this unit's code copies its results out into this unit
        env["_call"] = lambda name, values, refs: self._function(name, values, refs, env)
        for name in LIBRARY:
            env[f"_lib_{name}"] = getattr(ar, name)
        return env

    def run(self) -> None:
        """Run the main program; raises NotCrankRocker after it if the program printed the
        1966 message (as the port does)."""
        with numpy_quiet(self.ar):  # float32: a division by zero stops as float64 (_rdiv)
            try:
                self._execute(self.units["MAIN"])
            except _Stop:
                pass
        if self.not_crank_rocker:
            raise NotCrankRocker("the program printed THIS IS NOT A CRANK ROCKER MECHANISM")

    def _pow(self, a, n: int):
        """``a**n`` by repeated multiplication, each one counted in the statement budget
        (an integer's size checked at each)."""
        if n < 0:
            one = a * 0 + 1
            inverse = self._pow(a, -n)
            return _idiv(one, inverse) if isinstance(a, int) else _rdiv(one, inverse)
        self.quiet += n
        self.executed += n
        if self.quiet > STATEMENT_BUDGET or self.executed > self.statement_ceiling:
            raise ArithmeticError(f"**{n}: {n:,} multiplications, past the interpreter's "
                                  "budget of statements (docs/interpreter.md)")
        result = None
        check = isinstance(a, int)
        for _ in range(n):
            result = a if result is None else result * a
            if check:
                _ichk(result)
        return a * 0 + 1 if result is None else result

    def _enter(self, target: Unit, values, refs, caller_env: dict) -> dict:
        """Call ``target``: copy in (``_UNSET`` for an output argument the caller has not
        set), run, copy out into the caller's variables named by ``refs`` (by reference).
        Returns the target's variables."""
        tenv = self.env[target.name]
        for dummy, value in zip(target.args, values):
            if value is _UNSET:
                tenv.pop(f"V_{dummy}", None)
            else:
                tenv[f"V_{dummy}"] = value
        self._execute(target)
        for dummy, ref in zip(target.args, refs):
            if ref is not None and f"V_{dummy}" in tenv:
                caller_env[f"V_{ref}"] = tenv[f"V_{dummy}"]
        return tenv

    def _function(self, name, values, refs, caller_env: dict):
        unit = self.units[name]
        tenv = self._enter(unit, values, refs, caller_env)
        try:
            return tenv[f"V_{name}"]
        except KeyError:
            raise self._error(unit.statements[-1], f"FUNCTION {name} returns without "
                              "setting its value") from None

    def _error(self, st: Statement, text: str) -> FortranError:
        label = f"statement {st.label}" if st.label is not None else "the statement"
        return FortranError(f"{self.path}: {label} at card {st.card}: {text}")

    def _execute(self, unit: Unit) -> None:
        if unit.name in self.active:  # the 1410's subprograms had one return address
            st = unit.statements[0]
            raise self._error(st, f"{unit.name} is called while it is running (a subprogram "
                              "cannot call itself)")
        self.active.add(unit.name)
        try:
            self._execute_unit(unit)
        finally:
            self.active.discard(unit.name)

    def _execute_unit(self, unit: Unit) -> None:
        env = self.env[unit.name]
        code, labels = unit.code, unit.labels
        pc = 0
        while True:
            st = code[pc]
            pc += 1
            self.quiet += 1
            self.executed += 1
            if self.quiet > STATEMENT_BUDGET:
                raise self._error(st, f"{STATEMENT_BUDGET:,} statements without a line "
                                  "printed: a loop that never ends?")
            if self.executed > self.statement_ceiling:
                raise self._error(st, f"{self.statement_ceiling:,} statements executed "
                                  f"({STATEMENTS_PER_SHEET:,} for each of the {self.sheets:,} "
                                  "sheets and one more): a loop that never ends?")
            try:
                jump = self._one(unit, env, st)
            except _Return:
                return
            except (_Stop, FortranError, PageLimit, NotCrankRocker):
                raise
            except NameError as exc:
                name = str(exc).split("'")[1][2:] if "'" in str(exc) else "?"
                raise self._error(st, f"{name} is used before it is given a value") from None
            except ZeroDivisionError:
                raise self._error(st, "division by zero") from None
            except ArithmeticError1410 as exc:  # the 1410 stops; one line, as float64
                text = "division by zero" if "division by zero" in str(exc) else str(exc)
                raise self._error(st, text) from None
            except (ArithmeticError, ValueError, TypeError) as exc:
                raise self._error(st, f"{exc}") from None
            if jump is not None:
                if jump not in labels:  # compile_source checks every jump; a guard
                    raise self._error(st, f"no statement {jump} in this program unit")
                pc = labels[jump]

    def _one(self, unit: Unit, env: dict, st: Statement):
        kind = st.kind
        if kind == "SET":
            exec(st.data[1], env)  # noqa: S102 (code compiled from the deck above)
            return None
        if kind == "LIF":
            if eval(st.data[0], env):  # noqa: S307
                return self._one(unit, env, st.data[1])
            return None
        if kind == "AIF":
            value = eval(st.data[0], env)  # noqa: S307
            minus, zero, plus = st.data[1]
            return minus if value < 0 else zero if value == 0 else plus
        if kind == "GOTO":
            return st.data[1][0]
        if kind == "CGOTO":
            k = eval(st.data[0], env)  # noqa: S307
            targets = st.data[1]
            return targets[k - 1] if 1 <= k <= len(targets) else None
        if kind in ("CONTINUE", "FORMAT", "PAUSE"):
            return None
        if kind == "STOP":
            raise _Stop
        if kind in ("RETURN", "END"):
            if unit.kind == "MAIN":
                raise _Stop
            raise _Return
        if kind == "READ":
            return self._read(unit, env, st)
        if kind == "WRITE":
            return self._write(unit, env, st)
        if kind == "CALL":
            name, args = st.data
            values = [_UNSET if ref is not None and f"V_{ref}" not in env
                      else eval(code, env) for code, ref in args]  # noqa: S307
            self._enter(self.units[name], values, [ref for _, ref in args], env)
            return None
        raise self._error(st, f"cannot run {kind}")

    def _format(self, unit: Unit, st: Statement, label: int) -> Format:
        fmt = unit.formats.get(label)
        if fmt is None:
            raise self._error(st, f"FORMAT {label} is not in this program unit")
        return fmt

    def _read(self, unit: Unit, env: dict, st: Statement):
        fmt_label, end, names = st.data
        fmt = self._format(unit, st, fmt_label)
        try:
            values = self.cards[self.card]
        except IndexError:
            if end:
                return end[0]
            raise self._error(st, "READ past the last card (no END=)") from None
        self.card += 1
        if len(names) > min(len(values), fmt.n_edits):
            raise self._error(st, f"READ of {len(names)} values from a card of "
                              f"{len(values)} fields")
        for name, value in zip(names, values):
            env[f"V_{name}"] = (_ichk(int(value)) if implicit_type(name) == "I"
                                else self.ar.num(value))
        return None

    def _write(self, unit: Unit, env: dict, st: Statement):
        fmt_label, _, names = st.data
        fmt = self._format(unit, st, fmt_label)
        try:
            values = [env[f"V_{n}"] for n in names]
        except KeyError as exc:
            raise self._error(st, f"{str(exc)[3:-1]} is printed before it is given a value"
                              ) from None
        for name, value in zip(names, values):
            try:
                _strict_value(value)
            except Unprintable:
                raise self._error(st, f"{name} = {float(value):.4E} cannot be printed: past "
                                  "the IBM 1410's range (|x| < 1E99)") from None
        try:
            text = fmt.text_function(len(values), strict=True)(*values)
        except FormatError as exc:
            raise self._error(st, str(exc)) from None
        self._print(st, text)
        return None

    def _print(self, st: Statement, text: str) -> None:
        """Emit the records of one WRITE, those before a limit of the budget if one is
        reached (then PageLimit, or one FortranError)."""
        records = text.split("\n")[:-1]
        for k, record in enumerate(records):
            stop = None
            if record.startswith("1"):
                if self.max_pages is not None and self.pages >= self.max_pages:
                    stop = PageLimit(self.pages)
                elif self.page_ceiling is not None and self.pages >= self.page_ceiling:
                    stop = self._error(st, f"{self.pages:,} sheets printed, the most for a "
                                       f"deck whose range cards ask for {self.sheets:,} "
                                       f"({SHEETS_PER_DECK_SHEET} a sheet, and "
                                       f"{SHEETS_PER_DECK_SHEET} more): a loop that never "
                                       "ends? (--max-sheets N prints the first N)")
                else:
                    self.pages += 1
                    self.records = 0
            elif self.records >= RECORDS_PER_SHEET:
                stop = self._error(st, f"{RECORDS_PER_SHEET:,} lines printed with no page "
                                   "eject: a loop that never ends?")
            else:
                self.records += 1
                if record == NOT_CRANK_ROCKER:
                    self.not_crank_rocker = True
            if stop is not None:
                if k:
                    self.emit("".join(r + "\n" for r in records[:k]))
                raise stop
        self.emit(text)
        self.quiet = 0


def _ichk(n: int) -> int:
    """``n``, an integer result, if the interpreter's integers hold it."""
    if -INTEGER_LIMIT < n < INTEGER_LIMIT:
        return n
    raise ArithmeticError(f"integer overflow: a result of more than {INTEGER_DIGITS} digits "
                          "(the interpreter's integer size; docs/interpreter.md)")


def _rdiv(a, b):
    """A real division that stops on a zero divisor in every model (float32 would give
    inf quietly; float64 raises ZeroDivisionError)."""
    if b == 0:
        raise ZeroDivisionError
    return a / b


def _idiv(a: int, b: int) -> int:
    if b == 0:
        raise ZeroDivisionError
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b >= 0) else -q


def _mod(a: int, b: int) -> int:
    return a - _idiv(a, b) * b


def _ifix(x) -> int:
    value = float(x)
    if not math.isfinite(value):
        raise ArithmeticError(f"{value} has no integer value (IFIX, or an assignment to an "
                              "integer)")
    return _ichk(int(value))  # truncation toward zero


def deck_cards(deck) -> list:
    """The data deck's cards as the card reader gave their values (card by card)."""
    from sielaff.emulator.cards import PARAMETER_CARDS

    cards = []
    m = deck.mechanism
    for names in PARAMETER_CARDS:
        cards.append([getattr(m, n) for n in names])

    class Cards(list):
        def __getitem__(self, i):
            if i < len(cards):
                return cards[i]
            return list(deck.ranges[i - len(cards)])

        def __len__(self):
            return len(cards) + len(deck.ranges)

    return Cards()


def deck_sheets(deck, arithmetic="float64") -> int:
    """The sheets the deck's range cards ask for (what the port prints), at most
    ``ranges.MAX_SHEETS``: a range that never ends counts as that many."""
    from sielaff.emulator.ranges import MAX_SHEETS, sheet_count

    total = 0
    for thzero, delta, thmax in deck.ranges:
        n = sheet_count(thzero, delta, thmax, arithmetic)
        total += MAX_SHEETS if n is None else n
        if total >= MAX_SHEETS:
            return MAX_SHEETS
    return total


def run_program(source: str, deck, out, arithmetic: str = "float64",
                path: str = "<program>", notice=None, max_pages: int | None = None) -> None:
    """Run the program deck ``source`` on the data ``deck``, the listing on ``out``; with
    ``max_pages`` stop (PageLimit) before the page eject past that many sheets.  Raises
    FortranError (one line) for a deck it cannot compile or run, or past its budget (see
    :class:`Program`), and NotCrankRocker after a program that printed the 1966 message."""
    from sielaff.emulator.arithmetic import get_arithmetic

    notice = notice or (lambda kind, text: None)
    ar = get_arithmetic(arithmetic, on_error=lambda text: notice("library", text))
    units = compile_source(source, ar, path)
    sheets = deck_sheets(deck, arithmetic) if max_pages is None else max_pages
    Program(units, ar, deck_cards(deck), out.write, path, max_pages, sheets).run()
