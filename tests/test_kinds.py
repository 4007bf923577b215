"""Every kind, both branches, every command (issue 22 item 2): a double crank, a Grashof
double rocker and a triple rocker, as decks and specs, through check, table, plot,
balance and sweep on the open and the crossed branch."""

from __future__ import annotations

import math

import pytest

from conftest import DECKS, tiered
from procs import run
from sielaff.emulator.cards import read_deck
from sielaff.engine.classify import linkage_class

KINDS = ("double-crank", "double-rocker", "triple-rocker")
BRANCHES = ("open", "crossed")


def sielaff(*argv, cwd=None):
    """``python -m sielaff argv`` (forked from the worker's zygote: tests/procs.py)."""
    return run(argv, cwd=cwd, timeout=600, text=True)


@pytest.mark.parametrize("kind", KINDS)
def test_the_decks_are_the_kinds_they_are_named(kind):
    for ext in ("dat", "toml"):
        from sielaff.tools.common import read_spec_deck

        deck = (read_deck(DECKS / f"{kind}.dat") if ext == "dat"
                else read_spec_deck(str(DECKS / f"{kind}.toml"))[0])
        assert linkage_class(deck.mechanism).kind == kind


@pytest.mark.parametrize("branch", BRANCHES)
@pytest.mark.parametrize("ext", ("dat", "toml"))
@pytest.mark.parametrize("kind", KINDS)
def test_check_reports_the_kind_and_exits_0(kind, ext, branch):
    r = sielaff("check", DECKS / f"{kind}.{ext}", "--branch", branch)
    assert r.returncode == 0, r.stderr
    assert f"kind: {kind}" in r.stdout
    assert f"Verdict: usable as a {kind}" in r.stdout
    if kind != "double-crank":
        assert "limit position at THETA 2" in r.stdout and f"the {branch} branch" in r.stdout
    else:
        assert "peak bearing loads" in r.stdout
    # an explicit requirement keeps the 1966 program's verdict
    r = sielaff("check", DECKS / f"{kind}.{ext}", "--crank-rocker")
    assert r.returncode == 3 and "NOT A CRANK ROCKER" in r.stderr


@pytest.mark.parametrize("ext", ("dat", "toml"))
@pytest.mark.parametrize("kind", KINDS)
def test_table_rows_only_where_it_assembles_on_both_branches(kind, ext):
    tables = {}
    for branch in BRANCHES:
        r = sielaff("table", DECKS / f"{kind}.{ext}", "--branch", branch)
        assert r.returncode == 0, r.stderr
        assert f"a {kind}, not a crank-rocker" in r.stderr
        lines = r.stdout.splitlines()
        head, rows = lines[0].split(","), [line.split(",") for line in lines[1:]]
        assert rows
        for row in rows:
            assert all(math.isfinite(float(v)) for v in row), row
        tables[branch] = {float(row[1]): float(row[head.index("ATH4[deg]")]) for row in rows}
    m = read_deck(DECKS / f"{kind}.dat").mechanism
    c = linkage_class(m)
    if not c.turns_fully:
        assert "left out, where the linkage does not assemble" in r.stderr
        assert len(tables["open"]) < 36
    # the two branches are two assemblies: THETA 4 differs away from the toggles
    common = set(tables["open"]) & set(tables["crossed"])
    assert any(abs(tables["open"][t] - tables["crossed"][t]) > 1.0 for t in common)


@pytest.mark.parametrize("kind, branch", tiered(
    [(k, b) for k in KINDS for b in BRANCHES],
    {(KINDS[0], BRANCHES[0])}))  # the default suite draws one; `-m slow` the rest
def test_plot_balance_sweep_on_every_kind(tmp_path, kind, branch):
    spec = DECKS / f"{kind}.toml"
    r = sielaff("plot", spec, "--branch", branch, "-o", tmp_path / "figs")
    assert r.returncode == 0, r.stderr
    assert len(list((tmp_path / "figs").glob("*.png"))) == 6
    r = sielaff("plot", DECKS / f"{kind}.dat", "--branch", branch, "-o", tmp_path / "k",
                "--only", "kinematics")
    assert r.returncode == 0, r.stderr
    for source in (spec, DECKS / f"{kind}.dat"):
        r = sielaff("balance", source, "--branch", branch)
        assert r.returncode == 0, r.stderr
        assert "nan" not in r.stdout.lower()
        assert "Counterweights" in r.stdout
    r = sielaff("sweep", spec, "--branch", branch, "-o", tmp_path / "s.csv")
    assert r.returncode == 0, r.stderr
    rows = (tmp_path / "s.csv").read_text().splitlines()
    assert "nan" not in "".join(rows[1:]).lower()  # never a NaN row (issue 22)
    if kind == "double-crank":
        assert len(rows) == 4 and all(row.endswith(kind) for row in rows[1:])
    else:  # no whole revolution: no row, and stderr counts them
        assert len(rows) == 1
        assert "3 of 3 designs left out (no row)" in r.stderr and f"3 {kind}" in r.stderr
