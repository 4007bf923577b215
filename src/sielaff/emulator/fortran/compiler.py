"""FORTRAN statements and expressions turned into Python code objects, for one
arithmetic: constants converted by the model, FORTRAN's precedence, mixed mode."""

from __future__ import annotations

import re
from decimal import Decimal

from sielaff.emulator.arithmetic import ArithmeticError1410
from sielaff.emulator.fortran.source import (
    INTEGER_DIGITS,
    INTEGER_FUNCTIONS,
    LIBRARY,
    FortranError,
    Statement,
    Unit,
    _statements,
    implicit_type,
)
from sielaff.emulator.printer import Format, FormatError

# -- expressions: FORTRAN text to Python source ---------------------------------

_SMALLEST, _OVERFLOW = Decimal("1E-100"), Decimal("1E99")  # the card reader's range

_TOKEN = re.compile(r"""
    (?P<real>(\d+\.\d*|\.\d+)(E[+-]?\d+)?|\d+E[+-]?\d+)
  | (?P<int>\d+)
  | (?P<op>\.(GT|GE|LT|LE|EQ|NE|AND|OR|NOT)\.)
  | (?P<name>[A-Z][A-Z0-9]*)
  | (?P<pow>\*\*)
  | (?P<sym>[-+*/(),=])
""", re.X)


def _tokens(st: Statement, start: int, end: int) -> list[tuple[str, str, int]]:
    out, i, s = [], start, st.text
    while i < end:
        m = _TOKEN.match(s, i, end)
        if not m:
            raise FortranError(f"{st.where(i)}: cannot read {s[i:end]!r}")
        kind, text = m.lastgroup, m.group()
        if kind == "real" and text.endswith(".") and re.match(
                r"(GT|GE|LT|LE|EQ|NE|AND|OR|NOT)\.", s[m.end():end]):
            kind, text = "int", text[:-1]  # "1.EQ." is 1 then .EQ.
        out.append((kind, text, i))
        i += len(text)
    return out


class _Expr:
    """Recursive descent over tokens, giving (Python source, type I/R/L)."""

    def __init__(self, compiler: _Compiler, st: Statement, toks) -> None:
        self.c, self.st, self.toks, self.i = compiler, st, toks, 0

    def peek(self, text: str | None = None):
        if self.i >= len(self.toks):
            return None
        t = self.toks[self.i]
        return t if text is None or t[1] == text else None

    def take(self, text: str) -> None:
        if not self.peek(text):
            at = self.toks[self.i][2] if self.i < len(self.toks) else len(self.st.text)
            raise FortranError(f"{self.st.where(at)}: expected {text!r}")
        self.i += 1

    def parse(self) -> tuple[str, str]:
        src, typ = self.lor()
        if self.i != len(self.toks):
            raise FortranError(f"{self.st.where(self.toks[self.i][2])}: unexpected "
                               f"{self.toks[self.i][1]!r}")
        return src, typ

    def at(self) -> int:
        """Position in the statement of the next token (or its end)."""
        return self.toks[self.i][2] if self.i < len(self.toks) else len(self.st.text)

    def logical(self, parse, what: str):
        """An operand of .AND. .OR. .NOT.: a relation or a logical expression."""
        at = self.at()
        a, t = parse()
        if t != "L":
            side = "after it" if what == ".NOT." else "on each side"
            raise FortranError(f"{self.st.where(at)}: {what} needs a relation (.GT. .LT. "
                               f"...) {side}")
        return a

    def value(self, parse):
        """An arithmetic operand: a relation has no value (FORTRAN II has no logical
        values)."""
        at = self.at()
        a, t = parse()
        self.no_relation(t, at)
        return a, t

    def no_relation(self, t: str, at: int) -> None:
        if t == "L":
            raise FortranError(f"{self.st.where(at)}: a relation is not a value (FORTRAN II "
                               "has no logical values; a logical IF tests one)")

    def lor(self):
        a, t = self.land()
        while self.peek(".OR."):
            if t != "L":
                raise FortranError(f"{self.st.where(self.at())}: .OR. needs a relation "
                                   "(.GT. .LT. ...) on each side")
            self.i += 1
            b = self.logical(self.land, ".OR.")
            a, t = f"({a} or {b})", "L"
        return a, t

    def land(self):
        a, t = self.lnot()
        while self.peek(".AND."):
            if t != "L":
                raise FortranError(f"{self.st.where(self.at())}: .AND. needs a relation "
                                   "(.GT. .LT. ...) on each side")
            self.i += 1
            b = self.logical(self.lnot, ".AND.")
            a, t = f"({a} and {b})", "L"
        return a, t

    def lnot(self):
        if self.peek(".NOT."):
            self.i += 1
            a = self.logical(self.lnot, ".NOT.")
            return f"(not {a})", "L"
        return self.rel()

    RELOPS = {".GT.": ">", ".GE.": ">=", ".LT.": "<", ".LE.": "<=", ".EQ.": "==", ".NE.": "!="}

    def rel(self):
        a, ta = self.arith()
        t = self.peek()
        if t and t[1] in self.RELOPS:
            if ta == "L":
                raise FortranError(f"{self.st.where(t[2])}: {t[1]} compares two values, "
                                   "not relations")
            self.i += 1
            b, tb = self.value(self.arith)
            a, b = self.c.mix(a, ta, b, tb)
            return f"({a} {self.RELOPS[t[1]]} {b})", "L"
        return a, ta

    def arith(self):
        start = self.at()
        sign = None
        if self.peek("-") or self.peek("+"):
            sign = self.toks[self.i][1]
            self.i += 1
        a, ta = self.value(self.term) if sign else self.term()
        if sign == "-":
            a = f"(-{a})"
        while self.peek("+") or self.peek("-"):
            self.no_relation(ta, start)
            op = self.toks[self.i][1]
            self.i += 1
            b, tb = self.value(self.term)
            a, ta = self.c.binary(a, ta, op, b, tb)
        return a, ta

    def term(self):
        start = self.at()
        a, ta = self.factor()
        while self.peek("*") or self.peek("/"):
            self.no_relation(ta, start)
            op = self.toks[self.i][1]
            self.i += 1
            b, tb = self.value(self.factor)
            a, ta = self.c.binary(a, ta, op, b, tb)
        return a, ta

    def factor(self):
        start = self.at()
        a, ta = self.primary()
        if self.peek("**"):
            at = self.toks[self.i][2]
            self.no_relation(ta, start)
            self.i += 1
            b, tb = self.value(self.factor)
            if tb != "I":
                raise FortranError(f"{self.st.where(at)}: ** with a real exponent needs EXP "
                                   "and ALOG, which the 1410 library as modelled does not have")
            return f"_pow({a}, {b})", ta
        return a, ta

    def primary(self):
        t = self.peek()
        if t is None:
            raise FortranError(f"{self.st.where(len(self.st.text))}: expression ends early")
        kind, text, at = t
        self.i += 1
        if kind == "real":
            return self.c.constant(self.st, at, text), "R"
        if kind == "int":
            return self.c.integer(self.st, at, text), "I"  # "01" is 1
        if text == "(":
            a, ta = self.lor()
            self.take(")")
            return f"({a})", ta
        if text == "-":  # -X after an operator (an extension the 1410 may not have had)
            a, ta = self.value(self.factor)
            return f"(-{a})", ta
        if kind == "name":
            if self.peek("("):
                self.i += 1
                args = []
                if not self.peek(")"):
                    args.append(self.value(self.lor))
                    while self.peek(","):
                        self.i += 1
                        args.append(self.value(self.lor))
                self.take(")")
                return self.c.call(self.st, at, text, args)
            return self.c.variable(text), implicit_type(text)
        raise FortranError(f"{self.st.where(at)}: unexpected {text!r}")


# -- statements ------------------------------------------------------------------

#: FORTRAN statements outside the subset, named when met (blanks are gone: DO10I=1,5).
KNOWN = ("DIMENSION", "DOUBLEPRECISION", "DO", "COMMON", "EQUIVALENCE", "DATA", "REAL",
         "INTEGER", "LOGICAL", "EXTERNAL", "ASSIGN", "PRINT", "PUNCH", "BACKSPACE", "REWIND",
         "ENDFILE", "FREQUENCY", "READ", "WRITE", "IF", "GOTO", "CALL")
_ASSIGN = re.compile(r"([A-Z][A-Z0-9]*)=")
_GOTO = re.compile(r"GOTO(\d+)$")
_CGOTO = re.compile(r"GOTO\(([\d,]+)\),?([A-Z][A-Z0-9]*)$")
_ARITH_IF = re.compile(r"(\d+),(\d+),(\d+)$")
_IO = re.compile(r"(READ|WRITE)\((\d+),(\d+)(,END=(\d+))?\)")
_HEAD = re.compile(r"(FUNCTION|SUBROUTINE)([A-Z][A-Z0-9]*)(\(([A-Z0-9,]*)\))?$")
_CALL = re.compile(r"CALL([A-Z][A-Z0-9]*)(\((.*)\))?$")


def numpy_quiet(ar):
    """numpy's floating-point warnings off for float32 (numpy scalars): an overflow is an
    inf that stops the run where it is printed, as in float64, never a warning line."""
    import contextlib

    if getattr(ar, "name", "") != "float32":
        return contextlib.nullcontext()
    import numpy as np

    return np.errstate(all="ignore")


def _code(st: Statement, src: str, mode: str):
    """``src`` compiled; what Python cannot compile is a statement the subset cannot hold."""
    try:
        return compile(src, f"card {st.card}", mode)
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        raise FortranError(f"{st.where()}: cannot compile this statement") from None


def _close(st: Statement, start: int) -> int:
    """Index of the parenthesis closing the one at ``start``."""
    depth = 0
    for i in range(start, len(st.text)):
        depth += {"(": 1, ")": -1}.get(st.text[i], 0)
        if depth == 0:
            return i
    raise FortranError(f"{st.where(start)}: unbalanced parenthesis")


def _top_level(st: Statement, char: str, start: int = 0) -> int:
    depth = 0
    for i in range(start, len(st.text)):
        c = st.text[i]
        depth += {"(": 1, ")": -1}.get(c, 0)
        if depth == 0 and c == char:
            return i
    return -1


class _Compiler:
    """Turns a unit's statements into Python code objects run by :class:`Program`."""

    def __init__(self, ar, units: dict[str, Unit]) -> None:
        self.ar, self.units = ar, units
        self.consts: dict[str, object] = {}   # name in the code -> the model's value
        self.names: dict[str, str] = {}       # constant's text -> its name
        # float32 divides by zero quietly (inf): the interpreter stops as float64 does
        self.rdiv = getattr(ar, "name", "") == "float32"

    def constant(self, st: Statement, at: int, text: str) -> str:
        """A real constant's name in the code; its value is the model's (``ar.num`` of the
        text), which must lie in the 1410's range, as a card's value must."""
        name = self.names.get(text)
        if name is None:
            try:
                exact = Decimal(text)
                if exact and not _SMALLEST <= abs(exact) < _OVERFLOW:
                    raise ArithmeticError
                with numpy_quiet(self.ar):  # float32: past its range is inf, as on a card
                    value = self.ar.num(text)
            except (ArithmeticError, ArithmeticError1410, ValueError):
                raise FortranError(f"{st.where(at)}: constant {text} is past the IBM 1410's "
                                   "range (1E-100 <= |x| < 1E99, or 0)") from None
            name = self.names[text] = f"_k{len(self.consts)}"
            self.consts[name] = value
        return name

    def integer(self, st: Statement, at: int, text: str) -> str:
        digits = text.lstrip("0")
        if len(digits) > INTEGER_DIGITS:
            raise FortranError(f"{st.where(at)}: integer constant {text} has more than "
                               f"{INTEGER_DIGITS} digits (the interpreter's integer size)")
        return str(int(digits or "0"))

    def variable(self, name: str) -> str:
        return f"V_{name}"

    def mix(self, a, ta, b, tb):
        if ta == "I" and tb == "R":
            a = f"_num({a})"
        elif ta == "R" and tb == "I":
            b = f"_num({b})"
        return a, b

    def binary(self, a, ta, op, b, tb):
        if ta == tb == "I":  # + - * checked: an integer holds INTEGER_DIGITS digits
            return (f"_idiv({a}, {b})" if op == "/" else f"_ichk({a} {op} {b})"), "I"
        a, b = self.mix(a, ta, b, tb)
        if op == "/" and self.rdiv:
            return f"_rdiv({a}, {b})", "R"
        return f"({a} {op} {b})", "R"

    def call(self, st, at, name, args):
        srcs = [a for a, _ in args]
        if name in LIBRARY and name not in self.units:
            if len(args) != 1:
                raise FortranError(f"{st.where(at)}: {name} takes one argument")
            a, t = args[0]
            return f"_lib_{name}({a if t == 'R' else f'_num({a})'})", "R"
        if name in INTEGER_FUNCTIONS and name not in self.units:
            n = 2 if name == "MOD" else 1
            if len(args) != n:
                raise FortranError(f"{st.where(at)}: {name} takes {n} argument(s)")
            return f"_{name}({', '.join(srcs)})", "R" if name == "FLOAT" else "I"
        unit = self.units.get(name)
        if unit is None or unit.kind != "FUNCTION":
            raise FortranError(f"{st.where(at)}: {name}(...) is neither a FUNCTION of this "
                               "deck nor in the library (SIN COS ATAN SQRT ABS FLOAT IFIX INT "
                               "IABS MOD); arrays are not in the subset")
        if len(args) != len(unit.args):
            raise FortranError(f"{st.where(at)}: {name} has {len(unit.args)} argument(s), "
                               f"called with {len(args)}")
        refs = [f"'{a[2:]}'" if re.fullmatch(r"V_[A-Z][A-Z0-9]*", a) else "None" for a in srcs]
        return (f"_call('{name}', ({', '.join(srcs)}{',' if srcs else ''}), "
                f"({', '.join(refs)}{',' if refs else ''}))"), implicit_type(name)

    def expr(self, st: Statement, start: int, end: int, want: str | None = None) -> str:
        src, typ = _Expr(self, st, _tokens(st, start, end)).parse()
        if want == "R" and typ == "I":
            return f"_num({src})"
        if want == "I" and typ == "R":
            return f"_IFIX({src})"
        if want == "L" and typ != "L":
            raise FortranError(f"{st.where(start)}: a logical IF needs a relation "
                               "(.GT. .LT. ...)")
        if want != "L" and typ == "L":
            raise FortranError(f"{st.where(start)}: a relation is not a value (FORTRAN II "
                               "has no logical values to store or compute with; a logical "
                               "IF tests one)")
        return src

    def compile(self, unit: Unit) -> None:
        for index, st in enumerate(unit.statements):
            if st.label is not None:
                if st.label in unit.labels:
                    raise FortranError(f"{st.where()}: statement number {st.label} is used "
                                       "twice")
                unit.labels[st.label] = index
        for st in unit.statements:
            try:
                self.statement(unit, st)
            except RecursionError:
                raise FortranError(f"{st.where()}: an expression nested too deeply to "
                                   "compile") from None
            unit.code.append(st)
        for st in unit.statements:  # every GO TO (and END=) goes somewhere
            for target in _jumps(st):
                if target not in unit.labels:
                    raise FortranError(f"{st.where()}: GO TO {target}: there is no "
                                       f"statement {target} in this program unit")

    def statement(self, unit: Unit, st: Statement, inner: bool = False) -> None:
        s = st.text
        if st.kind == "FORMAT":
            if st.label is None:
                raise FortranError(f"{st.where()}: a FORMAT needs a statement number")
            try:
                unit.formats[st.label] = Format(st.text[len("FORMAT"):].strip())
            except FormatError as exc:
                raise FortranError(f"{st.where()}: {exc}") from None
            st.data = ()
            return
        eq = _top_level(st, "=")
        m = _ASSIGN.match(s)
        if eq > 0 and m and m.end() == eq + 1 and _top_level(st, ",", eq) < 0:
            name = m.group(1)
            st.kind = "SET"
            st.data = (name, _code(st, f"V_{name} = "
                                   f"{self.expr(st, eq + 1, len(s), implicit_type(name))}", "exec"))
            return
        if s.startswith("IF("):
            close = _close(st, 2)
            rest = s[close + 1:]
            m = _ARITH_IF.match(rest)
            if m:
                st.kind = "AIF"
                st.data = (_code(st, self.expr(st, 3, close), "eval"),
                           tuple(int(g) for g in m.groups()))
                return
            if inner or not rest:
                raise FortranError(f"{st.where(close + 1)}: IF(...) needs three statement "
                                   "numbers or one statement")
            cond = _code(st, self.expr(st, 3, close, "L"), "eval")
            sub = Statement(st.card, None, rest, st.cols[close + 1:])
            self.statement(unit, sub, inner=True)
            if sub.kind in ("FORMAT", "END"):
                raise FortranError(f"{st.where(close + 1)}: not a statement a logical IF "
                                   "can hold")
            st.kind, st.data = "LIF", (cond, sub)
            if sub.kind in ("GOTO", "CGOTO", "AIF"):
                st.data = (cond, sub, sub.data[1])
            return
        m = _GOTO.match(s)
        if m:
            st.kind, st.data = "GOTO", (None, (int(m.group(1)),))
            return
        m = _CGOTO.match(s)
        if m:
            if implicit_type(m.group(2)) != "I":
                raise FortranError(f"{st.where(m.start(2))}: computed GO TO needs an integer "
                                   f"variable (I-N), not {m.group(2)}")
            targets = tuple(int(x) for x in m.group(1).split(",") if x)
            st.kind, st.data = "CGOTO", (_code(st, f"V_{m.group(2)}", "eval"), targets)
            return
        if s in ("CONTINUE", "STOP", "PAUSE", "RETURN", "END") or re.fullmatch(
                r"(STOP|PAUSE)\d*", s):
            st.kind = re.sub(r"\d+$", "", s)
            if st.kind == "RETURN" and unit.kind == "MAIN":
                raise FortranError(f"{st.where()}: RETURN in the main program")
            return
        m = _IO.match(s)
        if m:
            verb, device, fmt, _, end = m.groups()
            device, fmt = int(device), int(fmt)
            if (verb, device) not in (("READ", 1), ("WRITE", 3)):
                raise FortranError(f"{st.where()}: {verb} on unit {device}: the card reader "
                                   "is unit 1 (READ), the printer unit 3 (WRITE)")
            if end and verb == "WRITE":
                raise FortranError(f"{st.where()}: END= belongs to READ")
            items = s[m.end():]
            names = [x for x in items.split(",")] if items else []
            for k, x in enumerate(names):
                if not re.fullmatch(r"[A-Z][A-Z0-9]*", x):
                    raise FortranError(f"{st.where(m.end())}: the list holds variables only "
                                       f"(item {k + 1}: {x!r})")
            st.kind = verb
            st.data = (fmt, (int(end),) if end else (), names)
            return
        m = _CALL.match(s)
        if m:
            name = m.group(1)
            target = self.units.get(name)
            if target is None or target.kind != "SUBROUTINE":
                raise FortranError(f"{st.where()}: CALL {name}: no SUBROUTINE {name} in "
                                   "this deck")
            args = []
            if m.group(3):
                start = len("CALL") + len(name) + 1
                pos = start
                while pos <= len(s) - 1:
                    comma = _top_level(st, ",", pos)
                    stop = comma if 0 <= comma < len(s) - 1 else len(s) - 1
                    args.append((_code(st, self.expr(st, pos, stop), "eval"),
                                 s[pos:stop] if re.fullmatch(r"[A-Z][A-Z0-9]*", s[pos:stop])
                                 else None))
                    pos = stop + 1
            if len(args) != len(target.args):
                raise FortranError(f"{st.where()}: {name} has {len(target.args)} argument(s), "
                                   f"called with {len(args)}")
            st.kind, st.data = "CALL", (name, args)
            return
        word = next((k for k in KNOWN if s.startswith(k)), None) or s[:12]
        raise FortranError(f"{st.where()}: not in the subset the interpreter knows: "
                           f"{word!r}... (docs/interpreter.md)")


def _jumps(st: Statement) -> tuple[int, ...]:
    """The statement numbers ``st`` may go to."""
    if st.kind in ("GOTO", "CGOTO", "AIF", "READ"):
        return st.data[1]
    if st.kind == "LIF":
        return _jumps(st.data[1])
    return ()


def compile_source(text: str, ar, path: str = "<program>") -> dict[str, Unit]:
    """The program units of a source deck, compiled for the arithmetic ``ar``."""
    statements = _statements(text, path)
    units: dict[str, Unit] = {}
    current = Unit("MAIN", "MAIN", [])
    heads = []
    for st in statements:
        m = _HEAD.match(st.text) if st.kind != "FORMAT" else None
        if m and not current.statements or (m and current.statements
                                            and current.statements[-1].text == "END"):
            if current.statements:
                _add_unit(units, current, path)
            args = [a for a in (m.group(4) or "").split(",") if a]
            current = Unit(m.group(1), m.group(2), args)
            current.head = st
            heads.append(st)
            continue
        if current.statements and current.statements[-1].text == "END":
            raise FortranError(f"{path}: {st.where()}: a statement after the END on card "
                               f"{current.statements[-1].card}, in no program unit (a "
                               "FUNCTION or SUBROUTINE card begins the next one)")
        current.statements.append(st)
    if current.statements:
        _add_unit(units, current, path)
    if "MAIN" not in units:
        raise FortranError(f"{path}: no main program")
    for unit in units.values():
        if not unit.statements or unit.statements[-1].text != "END":
            last = unit.statements[-1] if unit.statements else heads[-1]
            raise FortranError(f"{path}: {last.where()}: {unit.name} has no END card")
    compiler = _Compiler(ar, units)
    try:
        for unit in units.values():
            compiler.compile(unit)
    except FortranError as exc:
        raise FortranError(f"{path}: {exc}") from None
    except RecursionError:
        raise FortranError(f"{path}: an expression nested too deeply to compile") from None
    for unit in units.values():
        unit.consts = compiler.consts
    return units


def _add_unit(units: dict[str, Unit], unit: Unit, path: str) -> None:
    """``unit`` added to ``units``: a name used twice (or a subprogram called MAIN, the
    main program's name here) is refused on the later unit's first card."""
    head = unit.head
    where = head.where() if head is not None else unit.statements[0].where()
    if unit.kind != "MAIN" and unit.name == "MAIN":
        raise FortranError(f"{path}: {where}: {unit.kind} MAIN: MAIN names the main program "
                           "here; choose another name")
    if unit.name in units:
        first = units[unit.name].head
        raise FortranError(f"{path}: {where}: {unit.kind} {unit.name}: {unit.name} is "
                           "defined twice" + (f" (first on card {first.card})"
                                              if first is not None else ""))
    units[unit.name] = unit


