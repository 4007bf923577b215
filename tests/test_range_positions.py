"""The positions of a range card (tools/kinds.py): counted exactly from the card's
decimals, each angle the exact decimal rounded once."""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction as F

import pytest

from sielaff.tools import kinds


def test_count_is_exact():
    assert kinds.count(F(0), F("0.0004"), F(400)) == 1_000_001
    assert kinds.count(F(0), F("0.0003"), F(1)) == 3334
    assert kinds.count(F(10), F(10), F(360)) == 36
    assert kinds.count(F(5), F(1), F(5)) == 1
    assert kinds.count(F(6), F(1), F(5)) == 0
    assert kinds.count(F(6), F(-1), F(5)) == 0
    with pytest.raises(ValueError):
        kinds.count(F(5), F(0), F(5))


def test_angles_are_correctly_rounded():
    a = kinds.angles(F("0.0004"), F("0.0004"), 0, 1000)
    assert a.tolist() == [float(Decimal(k + 1) * Decimal("0.0004"))
                          for k in range(1000)]
    # no short decimal grid (a deck built from binary fractions): plain doubles
    third = F(1, 3)
    assert kinds.angles(F(0), third, 0, 4).tolist() == [0.0, 1 / 3, 2 / 3, 1.0]
