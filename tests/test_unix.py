"""Unix habits (issue 22, item 3): ``-`` reads the input from standard input in every
command that reads one, ``-o -`` writes standard output in every command that writes one
file, the data on stdout and what is said about them on stderr, ``check --format json``.

Most tests call ``sielaff.cli.main`` in this process with ``sys.stdin`` replaced (cheap);
a few run ``sielaff`` as a subprocess where a real file descriptor matters (``/dev/zero``,
an endless pipe, a closed stdin, a reader that goes away).  The command lists below are
counted: :data:`STDIN_COMMANDS` and :data:`STDOUT_COMMANDS` must name every command that
reads an input or writes one file.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from conftest import DECKS, GOLDEN
from procs import run
from sielaff.cli import COMMANDS, main

SIELAFF = [sys.executable, "-m", "sielaff"]

#: The commands that read a deck, a spec or a listing (every command but help and bench).
STDIN_COMMANDS = ("run", "check", "table", "plot", "balance", "sweep", "report", "simulate",
                  "synth", "tolerance", "punch", "diff")
#: The commands that write one file with -o (plot and bench write several: refused).
STDOUT_COMMANDS = ("run", "table", "check", "punch", "balance", "sweep", "simulate",
                   "synth", "tolerance", "report")


def test_the_lists_name_every_command():
    """Every command that reads an input has a stdin test, every command that writes one
    file a -o - test (plot, report and diff have their own below)."""
    assert set(STDIN_COMMANDS) | {"help", "bench"} == set(COMMANDS)
    assert set(STDOUT_COMMANDS) | {"plot", "bench", "diff", "help"} == set(COMMANDS)
    paths = dict.fromkeys(("sweep", "motor", "synth", "tolerance"), Path("x.toml"))
    assert set(stdin_cases(paths)) | {"plot", "report", "diff"} == set(STDIN_COMMANDS)
    assert set(stdout_cases(paths)) | {"report"} == set(STDOUT_COMMANDS)
    assert len(STDIN_COMMANDS) == 12 and len(STDOUT_COMMANDS) == 10


# -- helpers ------------------------------------------------------------------------
@pytest.fixture(scope="module")
def small(tmp_path_factory) -> dict[str, Path]:
    """The decks/ specs made cheap: few designs, few angles, few revolutions."""
    folder = tmp_path_factory.mktemp("specs")
    edits = {
        "sweep": (("n = 61", "n = 2"), ("n = 41", "n = 2"), ("angles = 360", "angles = 36")),
        "tolerance": (("n = 2000", "n = 20"), ("angles = 360", "angles = 36")),
        "synth": (("angles = 360", "angles = 36"),),
        "motor": (("revolutions = 20", "revolutions = 2"),),
    }
    out = {}
    for name, pairs in edits.items():
        text = (DECKS / f"{name}.toml").read_text()
        for old, new in pairs:
            assert old in text
            text = text.replace(old, new)
        out[name] = folder / f"{name}.toml"
        out[name].write_text(text)
    return out


def cli(monkeypatch, argv: list, stdin: bytes | None = None) -> tuple[int, str, str]:
    """(status, stdout, stderr) of ``sielaff argv`` in this process, ``stdin`` its input."""
    if stdin is not None:
        monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(stdin)))
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main([str(a) for a in argv])
    return status, out.getvalue(), err.getvalue()


def named_stdin(text: str, path: Path) -> str:
    """``text`` as if the input at ``path`` had been read from standard input."""
    return text.replace(str(path), "<stdin>")


def listing(monkeypatch) -> bytes:
    status, out, _ = cli(monkeypatch, ["run", DECKS / "example.dat"])
    assert status == 0
    return out.encode()


# -- - reads standard input -----------------------------------------------------------
def stdin_cases(small):
    """(command, input file, argv with INPUT where the input goes)."""
    return {
        "run": (DECKS / "example.dat", ["run", "INPUT", "--max-sheets", "3"]),
        "check": (DECKS / "example.dat", ["check", "INPUT"]),
        "table": (DECKS / "si.toml", ["table", "INPUT", "--only", "kinematics"]),
        "balance": (DECKS / "si.toml", ["balance", "INPUT"]),
        "sweep": (small["sweep"], ["sweep", "INPUT", "--workers", "1"]),
        "simulate": (small["motor"], ["simulate", "INPUT"]),
        "synth": (small["synth"], ["synth", "INPUT"]),
        "tolerance": (small["tolerance"], ["tolerance", "INPUT"]),
        "punch": (DECKS / "example.toml", ["punch", "INPUT"]),
    }


@pytest.mark.parametrize("command", [c for c in STDIN_COMMANDS
                                     if c not in ("plot", "report", "diff")])
def test_dash_reads_stdin_as_the_file_is_read(command, small, monkeypatch):
    """The same output from ``-`` with the file on stdin as from the file, its name
    <stdin>; the deck (run, check) and the spec (the others) told apart by content."""
    if command in ("simulate",):
        pytest.importorskip("scipy")
    path, argv = stdin_cases(small)[command]
    by_file = cli(monkeypatch, [path if a == "INPUT" else a for a in argv])
    by_stdin = cli(monkeypatch, ["-" if a == "INPUT" else a for a in argv],
                   stdin=path.read_bytes())
    assert by_file[0] == 0, by_file[2]
    assert by_stdin[0] == by_file[0], by_stdin[2]
    assert by_stdin[1] == named_stdin(by_file[1], path)
    assert by_stdin[2] == named_stdin(by_file[2], path)
    assert by_stdin[1]  # something was written


@pytest.mark.parametrize("source", ["example.dat", "example.toml"])
def test_check_and_table_tell_a_deck_from_a_spec_on_stdin(source, monkeypatch):
    path = DECKS / source
    outputs = []
    for argv in (["check", "--format", "json"], ["table", "--only", "kinematics"]):
        by_file = cli(monkeypatch, [*argv, path])
        by_stdin = cli(monkeypatch, [*argv, "-"], stdin=path.read_bytes())
        assert by_file[0] == by_stdin[0] == 0
        assert by_stdin[1] == named_stdin(by_file[1], path)
        outputs.append(by_stdin[1])
    data = json.loads(outputs[0])
    assert data["path"] == "<stdin>" and data["kind"] == "crank-rocker"
    # (a spec read as a deck, or a deck as a spec, would have failed at its first line)
    assert data["report"][0] == "sielaff check: <stdin>"


def test_plot_reads_stdin(tmp_path, monkeypatch):
    """plot's figure from stdin is the figure of a file named <stdin> (the name is drawn)."""
    pytest.importorskip("matplotlib")
    monkeypatch.chdir(tmp_path)
    Path("<stdin>").write_bytes((DECKS / "example.dat").read_bytes())
    a = cli(monkeypatch, ["plot", "<stdin>", "-o", "a", "--linkage"])
    b = cli(monkeypatch, ["plot", "-", "-o", "b", "--linkage"],
            stdin=(DECKS / "example.dat").read_bytes())
    assert a[0] == b[0] == 0 and b[1].strip() == os.path.join("b", "linkage.png")
    assert (tmp_path / "a" / "linkage.png").read_bytes() == \
        (tmp_path / "b" / "linkage.png").read_bytes()


def test_report_reads_stdin_and_writes_stdout(tmp_path, monkeypatch):
    """report's plumbing: - in, -o - out, the same page as -o FILE.  The page's body
    (20 s of figures, tests/test_report.py's) is replaced by one naming what it was given."""
    pytest.importorskip("matplotlib")
    import sielaff.tools.report as report

    def page(deck, scene, command, at=None, tolerances=None, motor=None):
        return f"{deck.path} {deck.mechanism} {scene.branch} {at}\n"

    monkeypatch.setattr(report, "report_html", page)
    path = DECKS / "si.toml"
    by_file = cli(monkeypatch, ["report", path, "-o", tmp_path / "r.html"])
    by_stdin = cli(monkeypatch, ["report", "-", "-o", "-"], stdin=path.read_bytes())
    assert by_file[0] == by_stdin[0] == 0
    assert by_stdin[1] == named_stdin((tmp_path / "r.html").read_text(), path)
    assert "units='SI'" in by_stdin[1]  # read as a spec: SI


@pytest.mark.parametrize("side", [0, 1])
def test_diff_reads_either_listing_from_stdin(side, monkeypatch):
    golden = GOLDEN / "figure10.asa"
    data = listing(monkeypatch)
    with_file = Path(os.environ.get("TMPDIR", "/tmp")) / f"sielaff-unix-{os.getpid()}.asa"
    with_file.write_bytes(data)
    try:
        argv = [with_file, golden] if side == 0 else [golden, with_file]
        by_file = cli(monkeypatch, ["diff", *argv])
        argv[side] = "-"
        by_stdin = cli(monkeypatch, ["diff", *argv], stdin=data)
    finally:
        with_file.unlink()
    assert by_file[0] == by_stdin[0] == 1  # the port's listing differs in last digits
    assert by_stdin[1] == by_file[1] and by_stdin[1]


def test_diff_takes_one_listing_from_stdin(monkeypatch):
    status, out, err = cli(monkeypatch, ["diff", "-", "-"], stdin=b"")
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and "standard input" in err


# -- errors name <stdin> --------------------------------------------------------------
def test_a_bad_card_on_stdin_is_named_by_card_and_columns(monkeypatch):
    lines = (DECKS / "example.dat").read_text().splitlines(keepends=True)
    lines[2] = "   XX.0 " + lines[2][8:]
    for command in ("run", "check", "table", "balance"):
        status, _, err = cli(monkeypatch, [command, "-"], stdin="".join(lines).encode())
        assert status == 2, (command, err)
        assert "<stdin>: card 3, columns 1-8" in err, (command, err)


@pytest.mark.parametrize("command", ["sweep", "punch", "table", "check"])
def test_a_bad_spec_on_stdin_is_named(command, monkeypatch):
    text = (DECKS / "sweep.toml").read_text().replace("frame = 12.0", "frame = twelve")
    status, out, err = cli(monkeypatch, [command, "-"], stdin=text.encode())
    assert status == 2 and err.startswith("<stdin>: "), err
    assert err.count("\n") == 1 and "Traceback" not in err


def test_run_on_a_spec_runs_the_deck_it_punches(monkeypatch):
    """``run`` reads a spec as the other commands do (issue 33): the listing of its punched
    deck, byte for byte that of the deck itself; an SI spec, which no deck can carry, is
    one line saying so."""
    status, out, err = cli(monkeypatch, ["run", "-"],
                           stdin=(DECKS / "example.toml").read_bytes())
    assert status == 0, err
    status2, out2, _ = cli(monkeypatch, ["run", str(DECKS / "example.dat")])
    assert status2 == 0 and out == out2
    status, _, err = cli(monkeypatch, ["run", "-"], stdin=(DECKS / "si.toml").read_bytes())
    assert status == 2 and err.startswith("<stdin>: [scene] units = 'SI'")
    assert err.count("\n") == 1


@pytest.mark.parametrize("head, kind", [
    (b"[lengths]\n", "spec"), (b"# a comment\n", "spec"), (b"  \n\n\nunits = 'SI'\n", "spec"),
    (b'"a b" = 1\n', "spec"), (b"     3.0     8.0     6.0\n", "deck"), (b"\n\n  1.0\n", "deck"),
    (b"", "deck"), (b"\0\0\0", "deck"), (b"\n" * 5000, "deck")])
def test_the_rule_that_tells_a_spec_from_a_deck(head, kind, monkeypatch):
    from sielaff.tools import common

    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(head)))

    class Args:
        deck = "-"

    common.take_stdin(Args)
    assert Args.deck == common.STDIN and common.is_stdin(Args.deck)
    assert common.stdin_kind() == kind
    assert common.is_spec(Args.deck) is (kind == "spec")


def test_leading_blank_lines_are_replayed_to_the_deck_reader(monkeypatch):
    """The lines read to tell a deck are cards all the same: a blank first card is card 1."""
    data = b"\n" + (DECKS / "example.dat").read_bytes()
    status, _, err = cli(monkeypatch, ["table", "-"], stdin=data)
    with_file = cli(monkeypatch, ["table", DECKS / "example.dat"])
    assert status == 2 and err.startswith("<stdin>: card")
    assert with_file[0] == 0


# -- bounded reading (real file descriptors) ---------------------------------------------
def run_sielaff(*argv, stdin=None, timeout=120, preexec_fn=None):
    """``sielaff argv`` forked from the worker's zygote (tests/procs.py), or a plain
    subprocess where ``preexec_fn`` must run in it."""
    if preexec_fn is None:
        return run(argv, stdin=stdin, timeout=timeout)
    return subprocess.run([*SIELAFF, *map(str, argv)], stdin=stdin, capture_output=True,
                          timeout=timeout, preexec_fn=preexec_fn)


@pytest.mark.parametrize("command", ["table", "sweep"])
def test_dev_zero_on_stdin_fails_at_once(command):
    with open("/dev/zero", "rb") as zero:
        r = run_sielaff(command, "-", stdin=zero, timeout=60)
    err = r.stderr.decode()
    assert r.returncode == 2 and err.count("\n") == 1 and err.startswith("<stdin>: "), err


def test_an_endless_spec_on_stdin_is_refused_at_its_byte_limit():
    proc = subprocess.Popen([*SIELAFF, "punch", "-"], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)

    def feed():
        with contextlib.suppress(BrokenPipeError, OSError):
            while True:
                proc.stdin.write(b"[a]\nb = 1\n" * 4096)

    threading.Thread(target=feed, daemon=True).start()
    proc.wait(timeout=60)
    err = proc.stderr.read().decode()
    proc.stdout.close()
    proc.stderr.close()
    assert proc.returncode == 2 and "<stdin>: longer than" in err and "not a spec" in err


def test_closed_stdin_is_one_line():
    r = run_sielaff("check", "-", preexec_fn=lambda: os.close(0))
    err = r.stderr.decode()
    assert r.returncode == 2 and err.count("\n") == 1 and "standard input is closed" in err


def test_a_reader_that_goes_away_ends_the_run_quietly(tmp_path):
    """361 sheets (about 430 kB, more than a pipe holds): the reader takes one line."""
    lines = (DECKS / "example.dat").read_text().splitlines(keepends=True)[:6]
    (tmp_path / "long.dat").write_text("".join(lines) + "     0.0     1.0   360.0\n")
    with open(tmp_path / "long.dat", "rb") as deck:
        proc = subprocess.Popen([*SIELAFF, "run", "-", "-o", "-"], stdin=deck,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        proc.stdout.readline()
        proc.stdout.close()
        err = proc.stderr.read().decode()
        proc.wait(timeout=120)
    assert proc.returncode == 0 and "Traceback" not in err and "error" not in err.lower()


# -- -o - writes standard output ---------------------------------------------------------
def stdout_cases(small):
    """(command, argv before -o, the file name -o FILE gets)."""
    return {
        "run": (["run", DECKS / "example.dat", "--max-sheets", "3"], "x.asa"),
        "table": (["table", DECKS / "si.toml", "--format", "json"], "x.json"),
        "check": (["check", DECKS / "double-crank.toml", "--format", "json"], "x.json"),
        "punch": (["punch", DECKS / "example.toml"], "x.dat"),
        "balance": (["balance", DECKS / "example.dat"], "x.dat"),
        "sweep": (["sweep", small["sweep"], "--workers", "1"], "x.csv"),
        "simulate": (["simulate", small["motor"]], "x.csv"),
        "synth": (["synth", small["synth"]], "x.csv"),
        "tolerance": (["tolerance", small["tolerance"]], "x.txt"),
    }


@pytest.mark.parametrize("command", [c for c in STDOUT_COMMANDS if c != "report"])
def test_dash_o_dash_writes_what_dash_o_file_writes(command, small, tmp_path, monkeypatch):
    """Byte for byte (report: test_report_reads_stdin_and_writes_stdout)."""
    if command == "simulate":
        pytest.importorskip("scipy")
    argv, name = stdout_cases(small)[command]
    target = tmp_path / name
    to_file = cli(monkeypatch, [*argv, "-o", target])
    to_stdout = cli(monkeypatch, [*argv, "-o", "-"])
    assert to_file[0] == to_stdout[0] == 0, (to_file[2], to_stdout[2])
    assert to_stdout[1] == target.read_text() and to_stdout[1]
    assert not (tmp_path / "-").exists() and not Path("-").exists()


def test_balance_dash_o_dash_puts_the_design_on_stdout_and_the_report_on_stderr(
        tmp_path, monkeypatch):
    from sielaff.tools.spec import read_spec

    for path, name in ((DECKS / "example.dat", "b.dat"), (DECKS / "si.toml", "b.toml")):
        status, out, err = cli(monkeypatch, ["balance", path, "-o", "-"])
        assert status == 0
        assert "Counterweights" in err and "Counterweights" not in out
        assert "Written to standard output" in err
        (tmp_path / name).write_text(out)
        # what was written reads back as the input's kind
        if name.endswith(".toml"):
            assert read_spec(tmp_path / name)["scene"]["units"] == "SI"
        # and is balanced: check finds a residual shaking force far below the input's
        assert cli(monkeypatch, ["check", tmp_path / name])[0] == 0
    # without -o - the report stays on stdout, as before
    status, out, err = cli(monkeypatch, ["balance", DECKS / "example.dat"])
    assert status == 0 and "Counterweights" in out


def test_sweep_dash_o_dash_csv_on_stdout_status_on_stderr(small, monkeypatch):
    status, out, err = cli(monkeypatch, ["sweep", small["sweep"], "--workers", "1", "-o", "-"])
    assert status == 0
    rows = out.splitlines()
    assert rows[0].startswith("DESIGN,R4[") and len(rows) == 1 + 2 * 2 * 2
    assert err.startswith("sielaff sweep: 8 designs") and "->" not in err


@pytest.mark.parametrize("argv", [
    ["plot", DECKS / "example.dat", "-o", "-"],
    ["bench", "--quick", "-o", "-"],
    ["sweep", DECKS / "si.toml", "--plot", "-"],
    ["simulate", DECKS / "motor.toml", "--plot", "-"],
    ["synth", DECKS / "synth.toml", "--write-best", "-"],
])
def test_several_files_refuse_dash(argv, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status, out, err = cli(monkeypatch, argv)
    assert status == 2 and out == "" and err.count("\n") == 1, err
    assert "-" in err and "standard output" in err
    assert os.listdir(tmp_path) == []  # nothing written, no file named -


@pytest.mark.parametrize("command", ["table", "check", "punch", "balance", "sweep"])
def test_an_output_that_is_the_input_is_still_refused(command, tmp_path, monkeypatch):
    source = DECKS / ("example.toml" if command in ("punch", "sweep") else "example.dat")
    path = tmp_path / source.name
    path.write_bytes(source.read_bytes())
    status, _, err = cli(monkeypatch, [command, path, "-o", path])
    assert status == 2 and "is the input" in err
    assert path.read_bytes() == source.read_bytes()


# -- check --format json ------------------------------------------------------------------
def text_numbers(line: str) -> list[str]:
    return re.findall(r"-?\d+\.\d+|-?\d+", line)


@pytest.mark.parametrize("source", ["example.dat", "si.toml"])
def test_check_json_has_the_text_reports_facts(source, monkeypatch):
    path = DECKS / source
    status, text, _ = cli(monkeypatch, ["check", path])
    status_j, out, _ = cli(monkeypatch, ["check", path, "--format", "json"])
    assert status == status_j == 0
    data = json.loads(out)
    assert data["report"] == text.splitlines() and data["verdict"] == "usable"
    si = data["units"] == "SI"
    assert si is (source == "si.toml")
    force, torque = ("N", "N m") if si else ("lb", "in-lb")
    lines = text.splitlines()
    for name, peak in data["peak_loads"].items():
        line = next(x for x in lines if f"({name}" in x and "direction" in x)
        assert peak["peak"]["unit"] == force and f" {force} at" in line
        assert f"{peak['peak']['value']:9.1f} {force} at THETA 2 = " \
            f"{peak['theta2']['value']:5.1f} deg, direction " \
            f"{peak['direction']['value']:5.1f} deg" in line
    t = data["torque"]
    assert t["max"]["unit"] == torque
    assert f"largest       {t['max']['value']:9.1f} {torque} at THETA 2 = " \
        f"{t['max_at_theta2']['value']:5.1f} deg" in text
    assert data["cycle_work"]["text"] in text
    assert data["cycle_work"]["work"]["unit"] == ("J" if si else "in-lb")
    g = data["transmission_angle"]
    assert f"minimum {g['min']['value']:6.2f} deg" in text
    assert data["grashof"]["margin"]["unit"] == ("m" if si else "in")
    assert f"(margin {data['grashof']['margin']['value']:g}" in text
    pins = [b["pin"] for b in data["bearings"]]
    assert pins == ["O2", "A", "B", "O4"]
    for b in data["bearings"]:
        line = next(x for x in lines if x.strip().startswith(f"pin {b['pin']:2} ("))
        assert f"{b['peak']['value']:9.1f} {force}" in line
        assert len(b["members"]) == 2
    assert data["flywheel"]["inertia"]["unit"] == ("kg m^2" if si else "in-lb-sec^2")
    # every number in the facts carries a unit string
    def walk(x):
        if isinstance(x, dict):
            if "value" in x:
                assert isinstance(x["unit"], str) and x["unit"]
            for v in x.values():
                walk(v)
        elif isinstance(x, list):
            for v in x:
                walk(v)
    walk({k: v for k, v in data.items() if k != "report"})


def test_check_json_for_a_linkage_that_does_not_turn_fully(monkeypatch):
    status, out, _ = cli(monkeypatch, ["check", DECKS / "triple-rocker.dat", "--format",
                                       "json"])
    data = json.loads(out)
    assert status == 0 and data["kind"] == "triple-rocker" and not data["turns_fully"]
    assert len(data["limit_positions"]) == len(data["toggles_deg"]) == 2
    for lp, toggle in zip(data["limit_positions"], data["toggles_deg"]):
        assert lp["THETA 2"]["value"] == toggle and lp["THETA 4"]["unit"] == "deg"
        assert f"limit position at THETA 2 = {toggle:7.2f} deg" in "\n".join(data["report"])
    assert "peak_loads" not in data  # the text has no revolution either


def test_check_json_on_a_bad_deck_keeps_the_status(monkeypatch):
    lines = (DECKS / "example.dat").read_text().splitlines(keepends=True)
    lines[2] = "    12.0     1.0     1.0     1.0\n"  # no crank angle assembles it
    status, out, err = cli(monkeypatch, ["check", "-", "--format", "json"],
                           stdin="".join(lines).encode())
    data = json.loads(out)
    assert status == data["status"] != 0 and data["error"] == err.strip()
    assert data["path"] == "<stdin>"


# -- help --------------------------------------------------------------------------------
@pytest.mark.parametrize("command", STDIN_COMMANDS)
def test_help_says_dash_is_standard_input(command, monkeypatch):
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
        main([command, "--help"])
    text = " ".join(out.getvalue().split())
    assert "- reads" in text and "standard input" in text
    if command in STDOUT_COMMANDS:
        assert re.search(r"- or none: stdout|-: on stdout|- for stdout", text), text


def test_help_io_topic(monkeypatch):
    status, out, _ = cli(monkeypatch, ["help", "io"])
    assert status == 0 and "<stdin>" in out and "-o -" in out
    for command in STDIN_COMMANDS:
        assert command in out
