"""``sielaff table``: the engine's results for a deck, as CSV or JSON."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import re
from pathlib import Path
from unittest import mock

import numpy as np
import pytest

from conftest import DECKS
from sielaff import engine
from sielaff.cli import main
from sielaff.emulator.cards import Range, parse_deck, read_deck
from sielaff.engine import analyze
from sielaff.tools import table

EXAMPLE_CARDS = (DECKS / "example.dat").read_text().splitlines()


def deck_text(*ranges: str, lengths: str | None = None) -> str:
    """The example deck with the given range cards (and optionally card 3 replaced)."""
    cards = EXAMPLE_CARDS[:6]
    if lengths is not None:
        cards[2] = lengths
    return "".join(c + "\n" for c in (*cards, *ranges))


def card(*values: str) -> str:
    return "".join(v.rjust(8) for v in values)


def cli(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(list(argv))
    return status, out.getvalue(), err.getvalue()


def table_of(tmp_path: Path, text: str, *extra: str) -> tuple[int, str, str]:
    path = tmp_path / "deck.dat"
    path.write_text(text)
    return cli("table", str(path), *extra)


def read_csv(text: str) -> tuple[list[str], list[list[float]]]:
    """Header names (units stripped) and rows."""
    rows = list(csv.reader(io.StringIO(text)))
    return [h.split("[")[0] for h in rows[0]], [[float(v) for v in row] for row in rows[1:]]


# --------------------------------------------------------------------------
# Content
# --------------------------------------------------------------------------


def test_example_deck_csv_is_the_engine_bit_for_bit():
    status, out, err = cli("table", str(DECKS / "example.dat"))
    assert status == 0 and err == ""
    assert out.endswith("\n") and "\r" not in out
    header, rows = read_csv(out)
    assert header == ["CARD", *engine.RESULTS]
    assert len(rows) == 36  # 10, 20, ..., 360: no sheet past THMAX
    values = np.array(rows)
    assert np.all(values[:, 0] == 7)
    np.testing.assert_array_equal(values[:, 1], np.arange(10.0, 361.0, 10.0))
    ref = analyze(read_deck(DECKS / "example.dat").mechanism, values[:, 1])
    for j, name in enumerate(engine.RESULTS):
        # repr round-trips: the text is the engine's double exactly
        np.testing.assert_array_equal(values[:, j + 1], ref[name], err_msg=name)
    assert out.splitlines()[1].startswith("7,10.0,")


def test_json_holds_the_same_numbers():
    _, out_csv, _ = cli("table", str(DECKS / "example.dat"))
    status, out, err = cli("table", str(DECKS / "example.dat"), "--format", "json")
    assert status == 0 and err == ""
    doc = json.loads(out)
    assert set(doc) == {"columns", "units", "descriptions", "rows"}
    header, rows = read_csv(out_csv)
    assert doc["columns"] == header
    assert doc["rows"] == rows
    assert all(isinstance(r[0], int) for r in doc["rows"])


def test_units_in_csv_header_and_json():
    """Every column carries its unit: NAME[unit] in the CSV header, 'units' and
    'descriptions' beside 'columns' in JSON; --header names gives bare names."""
    _, out, _ = cli("table", str(DECKS / "example.dat"))
    head = out.splitlines()[0].split(",")
    assert head[0] == "CARD" and "TORQ[in-lb]" in head and "ATH3[deg]" in head
    assert "FA32X[lb]" in head and "TH4DD[rad/sec^2]" in head and "VB[in/sec]" in head
    assert all(re.fullmatch(r"[A-Z0-9]+\[[a-z0-9/^-]+\]", h) for h in head[1:])
    # what pandas.read_csv does with the header: plain strings, no MultiIndex
    assert len(set(head)) == len(head) and all("," not in h and '"' not in h for h in head)
    _, plain, _ = cli("table", str(DECKS / "example.dat"), "--header", "names")
    assert plain.splitlines()[0] == ",".join(table.columns())
    assert plain.splitlines()[1:] == out.splitlines()[1:]
    _, js, _ = cli("table", str(DECKS / "example.dat"), "--format", "json")
    doc = json.loads(js)
    assert len(doc["units"]) == len(doc["descriptions"]) == len(doc["columns"])
    units = dict(zip(doc["columns"], doc["units"]))
    assert units["TORQ"] == "in-lb" and units["GAMMA"] == "deg" and units["AG3"] == "in/sec^2"
    described = dict(zip(doc["columns"], doc["descriptions"]))
    assert "link 3 on link 2" in described["FA32"] and "CCW" in described["TORQ"]


def test_columns_are_documented_in_order():
    documented = re.search(r"Columns\n(.*?)\n\n    With", table.__doc__, re.S).group(1)
    words = [w for w in documented.split("::")[1].split()]
    assert tuple(words) == table.columns()


def test_positions_thzero_to_thmax_inclusive(tmp_path):
    status, out, err = table_of(tmp_path, deck_text(card("0.0", "0.1", "1.0"),
                                                    card("45.0", "1.0", "45.0")))
    assert status == 0 and err == ""
    _, rows = read_csv(out)
    ath2 = [r[1] for r in rows]
    # exact decimals THZERO + k DELTA, each rounded once: 0.3, not 0.30000000000000004
    assert ath2 == [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 45.0]
    assert "0.30000000000000004" not in out
    assert [r[0] for r in rows] == [7] * 11 + [8]


def test_deck_built_in_code_reads_its_floats_as_decimals():
    deck = read_deck(DECKS / "example.dat")
    deck.exact_ranges = []
    deck.ranges = [Range(0.0, 0.1, 1.0)]
    buf = io.StringIO()
    assert table.write_table(deck, buf) == 11  # not 10: 0.1 means one tenth


def test_thzero_past_thmax_gives_no_rows_and_a_warning(tmp_path):
    status, out, err = table_of(tmp_path, deck_text(card("20.0", "10.0", "10.0"),
                                                    card("30.0", "-5.0", "0.0")))
    assert status == 0
    assert out == table.header(table.columns()) + "\n"
    lines = err.splitlines()
    assert len(lines) == 2 and all(x.startswith("sielaff: warning: ") for x in lines)
    assert "card 7: THZERO = 20 > THMAX = 10: no positions" in lines[0]
    assert "card 8:" in lines[1]
    status, out, err = table_of(tmp_path, deck_text(card("20.0", "10.0", "10.0")),
                                "--format", "json")
    doc = json.loads(out)
    assert doc["columns"] == list(table.columns()) and doc["rows"] == []


@pytest.mark.parametrize("delta", ["0.0", "-1.0"])
def test_endless_range_is_refused(tmp_path, delta):
    out_path = tmp_path / "t.csv"
    out_path.write_text("old\n")
    status, out, err = table_of(tmp_path, deck_text(card("10.0", "10.0", "20.0"),
                                                    card("10.0", delta, "360.0")),
                                "-o", str(out_path))
    assert status == 2 and out == ""
    assert err.count("\n") == 1
    assert "card 8, columns 9-16: DELTA" in err and "never end" in err
    assert out_path.read_text() == "old\n"


def test_not_a_crank_rocker_exits_3_naming_card_3(tmp_path):
    out_path = tmp_path / "t.csv"
    status, out, err = table_of(tmp_path, deck_text(card("0.0", "10.0", "350.0"),
                                                    lengths=card("12.0", "4.0", "3.0", "12.0")),
                                "-o", str(out_path))
    # any four-bar: rows only where it assembles, its kind on stderr (issue 22)
    assert status == 0 and out == "" and "double-rocker" in err
    rows = out_path.read_text().splitlines()[1:]
    assert rows and not any("nan" in r.lower() for r in rows)


def test_results_past_the_1410_range_are_refused_like_run(tmp_path):
    """TH2D = 1E98: accelerations ~1E198; run stops there (exit 2), and so does table."""
    text = deck_text(card("10.0", "10.0", "30.0")).replace(EXAMPLE_CARDS[5], card("1.0E98"))
    status, out, err = table_of(tmp_path, text, "--format", "json")
    assert (status, out) == (2, "") and err.count("\n") == 1
    assert "card 6: TH2D = 1e+98 rad/sec" in err and "past the IBM 1410's range" in err
    path = tmp_path / "deck.dat"
    assert cli("run", str(path))[0] == cli("check", str(path))[0] == 2


def test_non_finite_values_are_null_in_json_and_warned():
    """The writer itself (for decks built in code): null in JSON, nan/inf in CSV, a warning."""
    import dataclasses
    import io

    deck = read_deck(DECKS / "example.dat")
    deck = dataclasses.replace(deck, mechanism=deck.mechanism.replace(TH2D=1e160),
                               ranges=[(10.0, 10.0, 30.0)], exact_ranges=[])
    warnings_ = []
    out = io.StringIO()
    table.write_table(deck, out, "json", warn=warnings_.append)
    doc = json.loads(out.getvalue())
    assert any(v is None for row in doc["rows"] for v in row)
    assert len(warnings_) == 1 and "3 of 3 positions" in warnings_[0]
    out = io.StringIO()
    table.write_table(deck, out, "csv")
    assert "inf" in out.getvalue() or "nan" in out.getvalue()


def test_output_file_is_written_atomically(tmp_path):
    out_path = tmp_path / "t.csv"
    status, out, err = cli("table", str(DECKS / "example.dat"), "-o", str(out_path))
    assert status == 0 and out == "" and err == ""
    assert out_path.read_text() == cli("table", str(DECKS / "example.dat"))[1]
    with mock.patch.object(table, "_lines", side_effect=RuntimeError("disk on fire")), \
            pytest.raises(RuntimeError):
        cli("table", str(DECKS / "example.dat"), "-o", str(out_path), "--format", "json")
    assert out_path.read_text().startswith("CARD,ATH2[deg],")  # the old file survived
    assert [p.name for p in tmp_path.iterdir()] == ["t.csv"]


@pytest.mark.parametrize("fmt", ["csv", "json"])
def test_blocks_and_chunks_do_not_change_the_text(tmp_path, fmt):
    text = deck_text(card("0.0", "7.0", "360.0"), card("-30.0", "2.5", "30.0"))
    path = tmp_path / "deck.dat"
    path.write_text(text)
    _, whole, _ = cli("table", str(path), "--format", fmt)
    with mock.patch.object(table, "BLOCK", 7), mock.patch.object(table, "CHUNK", 3):
        _, pieces, _ = cli("table", str(path), "--format", fmt)
    assert pieces == whole
    if fmt == "json":
        assert len(json.loads(whole)["rows"]) == 52 + 25


# --------------------------------------------------------------------------
# "Only what you ask": --only kinematics never runs the force code
# --------------------------------------------------------------------------

FORCE_STEPS = ("_force_link4", "_force_link3", "_force_link2")


@contextlib.contextmanager
def forbid_forces():
    """The default model replaced (through the model, not the modules) by one whose force
    steps raise; yields it, so its step counts can be read."""
    def refuse(name):
        def step(*args):
            raise AssertionError(f"{name} ran")
        return step

    model = engine.FOURBAR.replacing(**{name: refuse(name) for name in FORCE_STEPS})
    with mock.patch.object(engine.analysis, "MODELS", [model]):  # what model_for finds
        yield model


def test_only_kinematics_never_runs_the_force_code(tmp_path):
    with forbid_forces() as model:
        status, out, err = cli("table", str(DECKS / "example.dat"), "--only", "kinematics")
    assert status == 0 and err == ""
    header, rows = read_csv(out)
    assert header == ["CARD", *engine.KINEMATIC_OUTPUTS]
    assert "TORQ" not in header and "FA32" not in header and "TEX" not in header
    assert len(rows) == 36
    ran = set(model.calls)
    assert ran and not any(s.startswith(("_force", "_inertia", "_total", "_external"))
                           for s in ran), ran
    # the same values as the full table's columns
    full_header, full_rows = read_csv(cli("table", str(DECKS / "example.dat"))[1])
    for j, name in enumerate(header):
        k = full_header.index(name)
        assert [r[j] for r in rows] == [r[k] for r in full_rows], name


def test_the_force_guard_does_bite():
    """Without --only the same patches make the table fail: the guard is live."""
    with forbid_forces(), pytest.raises(AssertionError, match="ran"):
        table.write_table(parse_deck(deck_text(card("10.0", "10.0", "20.0"))), io.StringIO())


def test_more_positions_than_doubles_can_tell_apart_is_refused(tmp_path):
    status, out, err = table_of(tmp_path, deck_text(card("0.0", "1.0E-50", "360.0")))
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and "card 7, columns 1-24:" in err
    assert "3.60E52 sheets, past the ceiling of 10,000,000" in err
