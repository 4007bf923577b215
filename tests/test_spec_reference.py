"""The spec reference (issue 33, item 2): ``sielaff help spec`` and docs/spec.md are made
from the readers' own declarations, and the readers take exactly what is declared.

* docs/spec.md is the generated page (regenerate: ``python3 -m sielaff.tools.helptext
  spec > docs/spec.md``);
* every table's reader refuses a key it does not declare, naming the declared keys;
* every declared default is the reader's: a table with the key left out reads as the
  declared default (each parsed here as TOML), so the page cannot drift from the code;
* the worked examples under decks/ use only declared keys, and every declared key is on
  the page.
"""

from __future__ import annotations

import re
import tomllib
from decimal import Decimal
from pathlib import Path

import pytest

from conftest import DECKS
from sielaff.tools.helptext import other_tables, spec_markdown, spec_text
from sielaff.tools.spec import PunchError
from sielaff.tools.spec_fields import key_names

ROOT = Path(__file__).resolve().parents[1]


def _readers():
    from sielaff.tools.simulate import motor_of
    from sielaff.tools.spec_sweep import sweep_of
    from sielaff.tools.synth import read_synthesis
    from sielaff.tools.tolerance import read_tolerance

    return {"motor": motor_of, "sweep": sweep_of, "synthesis": read_synthesis,
            "tolerance": read_tolerance}


#: The least table each reader takes (the defaults under test are left out).
MINIMAL = {
    "motor": {"kind": "constant", "torque": Decimal("10")},
    "sweep": {"vary": {"R4": [Decimal("12")]}},
    "synthesis": {"problem": "crank_rocker",
                  "crank_rocker": {"swing": Decimal("45"), "time_ratio": Decimal("1.2"),
                                   "rocker": Decimal("10")}},
    "tolerance": {"deviations": {"R1": Decimal("0.01")}},
}
#: Where each reader's answer holds a key's value, when not under the key's own name.
ANSWER = {("sweep", "pareto"): lambda out: out["pareto"]}


def test_docs_spec_md_is_current():
    assert (ROOT / "docs" / "spec.md").read_text() == spec_markdown()


@pytest.mark.parametrize("table", sorted(MINIMAL))
def test_a_key_not_declared_is_refused_naming_the_declared_ones(table):
    read = _readers()[table]
    spec = {table: dict(MINIMAL[table], volts=Decimal("3"))}
    with pytest.raises(PunchError, match="unknown key 'volts'") as e:
        read(spec, "s.toml")
    listed = re.search(r"\(expected: (.*)\)", str(e.value)).group(1).split(", ")
    declared = key_names(other_tables()[table][1])
    assert set(listed) <= set(declared) and len(listed) >= len(declared) - 7
    read({table: MINIMAL[table]}, "s.toml")  # and the least table itself is read


def _defaults():
    cases = []
    for table, (_, keys) in other_tables().items():
        for k in keys:
            if k.default and not k.default.startswith("["):  # [drive] speed: another key
                cases.append((table, k.name, k.default))
            elif k.default.startswith('["'):
                cases.append((table, k.name, k.default))
    return cases


@pytest.mark.parametrize("table, key, default", _defaults())
def test_every_declared_default_is_the_readers(table, key, default):
    expected = tomllib.loads(f"x = {default}")["x"]
    out = _readers()[table]({table: MINIMAL[table]}, "s.toml")
    got = ANSWER.get((table, key), lambda o: o[key])(out)
    assert got == expected, (table, key, got, expected)


def test_the_defaults_drawn_cover_each_table():
    tables = {t for t, _, _ in _defaults()}
    assert tables == set(MINIMAL) and len(_defaults()) >= 15


def test_the_worked_examples_use_only_declared_keys_and_the_page_has_every_key():
    declared = {t: set(key_names(keys)) for t, (_, keys) in other_tables().items()}
    seen = set()
    for path in DECKS.glob("*.toml"):
        spec = tomllib.loads(path.read_text())
        for table, keys in declared.items():
            if table in spec:
                assert set(spec[table]) <= keys, (path.name, table)
                seen.add(table)
    assert seen == set(declared)
    text = spec_text()
    for table, keys in declared.items():
        assert f"[{table}]" in text
        for k in keys:
            assert f"\n{k} = ..." in text, (table, k)
