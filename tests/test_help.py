"""Help an engineer can use without the README: deck layout, conventions, exit
statuses, --version, and every example in the help runnable as written."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys

import pytest

from conftest import DECKS, GOLDEN, ROOT
from sielaff import __version__
from sielaff.cli import build_parser, main
from sielaff.tools.helptext import EXAMPLE_CARDS, TOPICS


def helps() -> dict[str, str]:
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    return {"": parser.format_help(), **{n: p.format_help() for n, p in sub.choices.items()}}


def test_version(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["--version"])
    assert exit_.value.code == 0
    assert capsys.readouterr().out.strip() == f"sielaff {__version__}"


def test_every_help_states_the_exit_statuses():
    for name, text in helps().items():
        assert "exit status (every command):" in text, name
        for status in ("0 ", "1 ", "2 ", "3 ", "130 "):
            assert re.search(rf"^  {status}", text, re.M), (name, status)


def test_top_level_help_has_conventions_and_topics():
    text = helps()[""]
    assert "CCW" in text and "FA32 is the force of link 3 on link 2" in text
    assert "386.088 in/sec^2" in text and "gravity, crank acceleration and loads are " \
        "modelled when" in " ".join(text.split())
    assert "sielaff help deck" in text
    for topic in TOPICS:
        assert f"  {topic} " in text


def test_help_deck_has_layout_units_and_the_example(capsys):
    assert main(["help", "deck"]) == 0
    text = capsys.readouterr().out
    for name, unit in (("W2", "lb"), ("R1", "in"), ("ADEL2", "deg"), ("RG2", "in"),
                       ("TH2D", "rad/sec"), ("THZERO", "deg")):
        assert re.search(rf"{name} +{re.escape(unit)}", text), name
    assert "in-lb-sec^2" in text and "4 implied decimals" in text
    assert "1-8" in text and "25-32" in text
    # the example shown is the shipped deck, card for card (sequence numbers aside)
    shipped = [line[:32].rstrip() for line in (DECKS / "example.dat").read_text().splitlines()]
    assert EXAMPLE_CARDS.splitlines() == shipped


def test_help_topics_and_an_unknown_one(capsys):
    assert main(["help"]) == 0
    listing = capsys.readouterr().out
    assert all(t in listing for t in TOPICS)
    assert main(["help", "arith"]) == 0
    arith = capsys.readouterr().out
    assert "K significant decimal" in arith and "K = 8" in arith and "3 to 40" in arith
    assert main(["help", "exit"]) == 0 and "130" in capsys.readouterr().out
    assert main(["help", "nope"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no help topic 'nope'" in err


def test_run_accepts_only_kinematics(tmp_path):
    a, b = tmp_path / "a.asa", tmp_path / "b.asa"
    deck = str(DECKS / "example.dat")
    assert main(["run", deck, "--only", "kinematics", "-o", str(a)]) == 0
    assert main(["run", deck, "--kinematics-only", "-o", str(b)]) == 0
    assert a.read_bytes() == b.read_bytes() and b"DRIVING TORQ" not in a.read_bytes()


def _examples() -> list[str]:
    lines = []
    for text in helps().values():
        for block in re.findall(r"^example:\n((?:  .*\n?)+)", text, re.M):
            lines += [line.strip() for line in block.splitlines() if line.strip()]
    return sorted(set(lines))


@pytest.mark.slow
@pytest.mark.parametrize("command", _examples())
def test_every_help_example_runs(tmp_path, command):
    """Each example line, run by the shell in a folder holding the source tree's decks/
    and golden/ (the examples name them), exits 0 with no error line."""
    if command.startswith("sielaff bench") and "--quick" not in command:
        pytest.skip("the full study takes a minute; --quick runs the same code")
    shutil.copytree(DECKS, tmp_path / "decks")
    shutil.copytree(GOLDEN, tmp_path / "golden")
    if "example.asa" in command and not command.startswith("sielaff run"):
        subprocess.run([sys.executable, "-m", "sielaff", "run", "decks/example.dat",
                        "-o", "example.asa"], cwd=tmp_path, check=True)
    shell = command.replace("sielaff ", f"{sys.executable} -m sielaff ").replace(
        "| less", "| cat")
    proc = subprocess.run(["bash", "-o", "pipefail", "-c", shell], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    ok = {0, 1} if " diff " in f" {command} " else {0}  # diff: 1 means the figures differ
    assert proc.returncode in ok, (command, proc.stderr[-2000:])
    assert "Traceback" not in proc.stderr and "Warning" not in proc.stderr


def test_examples_were_found():
    found = _examples()
    assert any(c.startswith("sielaff run") for c in found)
    assert any(c.startswith("sielaff help") for c in found)
    assert len(found) >= 10, found
    assert ROOT.exists()


def test_help_spec_is_made_from_the_readers_tables(capsys):
    """Every key the spec reader takes for the mechanism, the range cards and [deck], and
    each effect's own [scene] lines, appear in ``sielaff help spec``."""
    from sielaff.cli import main
    from sielaff.engine.fourbar import FOURBAR
    from sielaff.tools.spec_fields import OTHER_TABLES, RANGE_KEYS, SPEC_NAMES

    assert main(["help", "spec"]) == 0
    out = capsys.readouterr().out
    for (section, key, _), name in SPEC_NAMES.items():
        assert f"[{section}]" in out and name in out
        assert f"\n{key} = " in out
    for key in RANGE_KEYS:
        assert f"\n{key} = ..." in out
    effects = [e for e in FOURBAR.effects if e.spec is not None]
    assert len(effects) == len(FOURBAR.effects)
    for e in effects:
        assert e.spec.help in out
    for table in OTHER_TABLES:
        assert f"[{table}]" in out or table in out
    assert main(["help"]) == 0 and "spec " in capsys.readouterr().out
