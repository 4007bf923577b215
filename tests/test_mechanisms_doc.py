"""docs/mechanisms.md's worked examples are what docs/make_mechanisms.py prints today.

The block is regenerated and compared with the committed one: the words exactly, each
number within its last printed digit (5 significant digits; a roundoff-sized value is
printed as a bound, so no number depends on which side of a digit an ulp falls).
"""

from __future__ import annotations

import importlib.util

from conftest import ROOT
from test_synthesis_doc import NUMBER, close


def load_script():
    spec = importlib.util.spec_from_file_location("make_mechanisms",
                                                  ROOT / "docs" / "make_mechanisms.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_worked_examples_are_current():
    mod = load_script()
    doc = (ROOT / "docs" / "mechanisms.md").read_text()
    old = doc.split(mod.BEGIN, 1)[1].split(mod.END, 1)[0].lstrip("\n")
    new = mod.block()
    assert NUMBER.sub("#", old) == NUMBER.sub("#", new), "the words differ"
    a, b = NUMBER.findall(old), NUMBER.findall(new)
    assert len(a) == len(b) > 150
    bad = [(x, y) for x, y in zip(a, b) if not close(x, y)]
    assert not bad, bad[:5]


def test_every_kind_has_its_example():
    """The block covers each kind the engine names (a new kind needs its example)."""
    from sielaff.tools.kinds import other_kinds

    mod = load_script()
    specs = {spec for _, _, spec, _, _ in mod.KINDS}
    assert specs == {f"{k}.toml" for k in other_kinds()}
