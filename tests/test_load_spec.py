"""``sielaff.load_spec``: a spec read in Python as the commands read it; the ``all`` extra;
``.venv`` ignored (issue 33, item 2)."""

from __future__ import annotations

import tomllib

import pytest

import sielaff
from conftest import DECKS, ROOT
from sielaff.tools.common import read_spec_deck


def test_load_spec_gives_what_the_commands_read():
    s = sielaff.load_spec(str(DECKS / "friction.toml"))
    deck, scene = read_spec_deck(str(DECKS / "friction.toml"))
    assert s.mechanism == deck.mechanism and s.scene == scene
    assert s.ranges == ((10.0, 10.0, 360.0),)
    assert s.scene.has_friction and len(s.scene.elements) == 1
    assert s.motor is not None and callable(s.motor["motor"]) and s.motor["revolutions"] == 20
    plain = sielaff.load_spec(str(DECKS / "example.toml"))
    assert plain.motor is None and plain.scene.is_1966


def test_a_spec_that_cannot_be_read_is_one_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text((DECKS / "example.toml").read_text().replace("frame = 12.0", "frame = 'x'"))
    with pytest.raises(ValueError, match="bad.toml") as e:
        sielaff.load_spec(str(bad))
    assert "\n" not in str(e.value)
    with pytest.raises(ValueError, match="no such spec"):
        sielaff.load_spec(str(tmp_path / "none.toml"))


def test_the_all_extra_holds_every_other_extra():
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"]
    named = extras["all"][0].split("[")[1].rstrip("]").split(",")
    assert set(named) == set(extras) - {"all", "test", "browser"}


def test_a_virtual_environment_is_ignored():
    lines = (ROOT / ".gitignore").read_text().splitlines()
    assert ".venv/" in lines


def test_the_subpackages_are_reached_from_the_package():
    """``import sielaff`` then ``sielaff.synthesis.rank`` (as the README writes it) works."""
    import subprocess
    import sys

    code = ("import sielaff; print(callable(sielaff.synthesis.rank), "
            "callable(sielaff.design.flywheel), callable(sielaff.engine.analyze))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=120, env={"PYTHONPATH": str(ROOT / "src"), "PATH": "/usr/bin"})
    assert r.returncode == 0 and r.stdout.split() == ["True"] * 3, r.stderr
