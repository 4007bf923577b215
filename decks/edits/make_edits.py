"""Make the report's three edits of the program deck from decks/sielaff.f, card by card.

    python decks/edits/make_edits.py        # rewrites the three decks beside this file

The report tells its readers to change the program ("AN EXAMPLE PROBLEM"; "THE PROGRAM AND
ITS USE"); each edit here is the smallest change of cards that does what it says:

* tex-constant.f  statement 74 ``TEX=0.0`` punched as ``TEX=150.0`` ("In other uses this
                  could be TEX = CONSTANT"): a constant torque of 150 in-lb on the rocker.
* tex-theta4.f    statement 74 as ``TEX=50.0*SIN(TH4)`` ("or TEX = f(theta 4)"): TH4 is
                  in radians in the program.
* kinematics.f    "A kinematic analysis alone is achieved by removing all the cards
                  related to forces and torques (statement numbers 133-202), and their
                  corresponding WRITE statements": the cards from 00133 to 00202 and the
                  eight WRITEs of FORMATs 15, 2 (the forces), 3, 16, 6, 4, 17 and 5 (TORQ).

Each deck starts with comment cards saying what changed; tests/test_fortran.py checks that
this script reproduces the decks and runs them.
"""

from __future__ import annotations

from pathlib import Path

HERE = Path(__file__).resolve().parent
SOURCE = HERE.parent / "sielaff.f"
FORCE_WRITES = ("      WRITE(3,15)", "      WRITE(3,2)FA32,FB34,FOA,FOB",
                "      WRITE(3,3)DFA32,DFB34,DFOA,DFOB", "      WRITE(3,16)",
                "      WRITE(3,6)SHAK,SHAKX,SHAKY", "      WRITE(3,4)DSHAK",
                "      WRITE(3,17)", "      WRITE(3,5)TORQ")


def _comments(*lines: str) -> list[str]:
    return [f"C     {line}" for line in lines]


def tex_constant(cards: list[str]) -> list[str]:
    out = [c.replace("00074 TEX=0.0", "00074 TEX=150.0") for c in cards]
    assert out != cards
    return _comments("EDIT: statement 74 punched as TEX=150.0, a constant torque on the",
                     "rocker (in-lb, counter-clockwise +), as the report suggests.") + out


def tex_theta4(cards: list[str]) -> list[str]:
    out = [c.replace("00074 TEX=0.0", "00074 TEX=50.0*SIN(TH4)") for c in cards]
    assert out != cards
    return _comments("EDIT: statement 74 punched as TEX=50.0*SIN(TH4), a torque on the",
                     "rocker that depends on its angle (TH4 in radians).") + out


def kinematics(cards: list[str]) -> list[str]:
    first = next(i for i, c in enumerate(cards) if c.startswith("00133"))
    last = next(i for i, c in enumerate(cards) if c.startswith("00202"))
    out = cards[:first] + cards[last + 1:]
    kept = [c for c in out if c not in FORCE_WRITES]
    assert len(out) - len(kept) == len(FORCE_WRITES)
    return _comments("EDIT: a kinematic analysis alone: the cards of statements 133-202",
                     "(forces and torques) and their eight WRITE statements removed.") + kept


EDITS = {"tex-constant.f": tex_constant, "tex-theta4.f": tex_theta4,
         "kinematics.f": kinematics}


def decks() -> dict[str, str]:
    cards = SOURCE.read_text().splitlines()
    return {name: "\n".join(edit(cards)) + "\n" for name, edit in EDITS.items()}


if __name__ == "__main__":
    for name, text in decks().items():
        (HERE / name).write_text(text)
        print(HERE / name)
