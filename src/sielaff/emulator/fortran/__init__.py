"""The program deck itself, read as the 1410 compiler read it and run on a chosen arithmetic.

In:  a FORTRAN source deck (``decks/sielaff.f``, or an edit of it), a data deck (read by
     ``emulator.cards``), an arithmetic model (``float64``, ``float32``, ``ibm1410[:K]``).
Out: the listing, through the same printer as the port; a runtime failure is one
     :class:`FortranError` naming the statement number and card.

Reading the source, as the 1410 compiler did (docs/interpreter.md):

* Columns 1-5 hold the statement number, column 6 a continuation mark (not blank or 0),
  and columns 7-72 the statement.  Columns 73-80 are ignored.  C in column 1 is a
  comment.
* Blanks are insignificant outside a FORMAT's Hollerith text, so ``CALLVECTOR(`` and
  ``GOTO54`` parse.
* Implicit typing: names starting I-N are integers, the rest real.

The subset is what the report's program and its plausible edits use:

* assignment, arithmetic IF and logical IF, GO TO and computed GO TO, CONTINUE, STOP,
  PAUSE, END;
* READ and WRITE with a FORMAT (unit 1 the card reader, unit 3 the printer), and FORMAT;
* FUNCTION, SUBROUTINE, CALL, RETURN;
* SIN, COS, ATAN, SQRT, ABS from the arithmetic's library, with FLOAT, IFIX, INT, IABS
  and MOD;
* real and integer arithmetic, ``**`` with an integer exponent (repeated
  multiplication), relational and logical operators.

Anything outside the subset is one :class:`FortranError` naming the card and column,
never a traceback.

Evaluation follows FORTRAN's precedence, left to right within a level.  A constant is
converted by the model (``ar.num`` of its text: the 1410 truncates to K digits), as the
port converts its literals.  Arguments are passed by reference (copy in, copy out).  A
subprogram's variables keep their values between calls, as they did on the 1410.
Integers hold 20 decimal digits (the 1410's integer size is not documented in the
sources at hand: this is the interpreter's own, docs/interpreter.md).  A relation is not a
value (FORTRAN II has no logical values); a computed GO TO takes an integer variable.

The run has a budget (``source``: statements, integer size, sheets and lines, the source's
size; ``printer.RECORD_LIMIT``: a FORMAT's record); past it, one FortranError
(docs/robustness.md).
"""

from __future__ import annotations

from sielaff.emulator.fortran.compiler import compile_source
from sielaff.emulator.fortran.machine import PageLimit, Program, run_program
from sielaff.emulator.fortran.source import FortranError

__all__ = ["FortranError", "PageLimit", "Program", "compile_source", "run_program"]
