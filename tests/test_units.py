"""Units from one place (issue 22): every command and every figure on an SI spec prints
and draws SI units, never the report's in, lb, in-lb or in/sec.

Each command runs in a subprocess through ``sielaff.cli.main``; a figure's words are read
from its matplotlib artists (every ``matplotlib.text.Text`` of the figure, found with
``fig.findobj`` just before it is saved), not from the PNG's pixels.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest

from conftest import DECKS, tiered
from sielaff.quantities import KINDS, fmt, unit, unit_of

SI_SPEC = DECKS / "si.toml"

#: A report unit where a unit stands: lb, in-lb..., in/sec..., or "in" after a number
#: or in brackets ("12.0 in", "(in)", "[in]").  "in" the English word is left alone.
REPORT_UNIT = re.compile(r"(?<![A-Za-z])(lb|in-lb\S*|in/sec\S*)(?![A-Za-z])"
                         r"|(?:\d|\))\s+in(?=$|[\s,;.)\]])(?!\s+[a-z])|[\[(]in[\])]")

#: Runs ``sielaff`` with every figure's texts written to a JSON file as it is saved.
DRIVER = """
import json, sys
import matplotlib
matplotlib.use("Agg")
from matplotlib.figure import Figure
from matplotlib.text import Text
texts = []
_save = Figure.savefig
def savefig(self, *args, **kwargs):
    self.canvas.draw()  # tick labels exist once drawn
    texts.append([t.get_text() for t in self.findobj(Text)
                  if t.get_visible() and t.get_text().strip()])
    return _save(self, *args, **kwargs)
Figure.savefig = savefig
from sielaff.cli import main
try:
    status = main(sys.argv[2:])
finally:
    with open(sys.argv[1], "w") as f:
        json.dump(texts, f)
sys.exit(status)
"""


def test_the_regex_finds_report_units():
    """The detector itself: it finds each report unit and passes SI text and English."""
    for bad in ("R1 = 12.0 in", "peak 87.5 lb at", "TORQ (in-lb)", "speed (in/sec)",
                "TORQ[in-lb]", "0.4 in-lb-sec^2", "R4[in]", "force magnitude in lb",
                "margin 4.0 in)", "= 12 in, crank"):
        assert REPORT_UNIT.search(bad), bad
    for good in ("R1 = 0.3 m", "87.5 N", "TORQ (N m)", "quirks this deck triggers in sielaff",
                 "in degrees", "speed (m/s)", "(0 in the 1966 program)", "drawn in SI", "R4[m]"):
        assert not REPORT_UNIT.search(good), good


def test_fmt_and_unit_of_agree_with_the_catalogue():
    assert fmt(12.0, "length", "SI") == "12 m"
    assert fmt(12.0, "length") == "12 in"
    assert fmt(3.25, "TORQ", "SI", ".2f") == "3.25 N m"
    for name, kind in (("R1", "length"), ("FA32", "force"), ("TORQ", "torque"),
                       ("VA", "speed"), ("AA", "acceleration"), ("ZI3", "inertia"),
                       ("W2", "weight"), ("TH3D", "rate")):
        for system in ("in-lb-sec", "SI"):
            assert unit(name, system) == unit_of(kind, system) == unit_of(name, system)
    assert unit_of("work", "SI") == "J" and unit_of("power", "SI") == "W"
    assert set(KINDS) >= {"length", "force", "torque", "work", "power", "speed", "inertia"}
    with pytest.raises(ValueError):
        unit_of("length", "cgs")


def _run(tmp_path, *argv: str) -> tuple[subprocess.CompletedProcess, list[list[str]]]:
    driver = tmp_path / "driver.py"
    driver.write_text(DRIVER)
    texts = tmp_path / "texts.json"
    proc = subprocess.run([sys.executable, str(driver), str(texts), *argv],
                          capture_output=True, text=True, timeout=600, cwd=tmp_path)
    return proc, json.loads(texts.read_text()) if texts.exists() else []


COMMANDS = {
    "check": ["check", str(SI_SPEC)],
    "table": ["table", str(SI_SPEC)],
    "table-json": ["table", str(SI_SPEC), "--format", "json"],
    "table-kinematics": ["table", str(SI_SPEC), "--only", "kinematics"],
    "balance": ["balance", str(SI_SPEC), "-o", "balanced.toml"],
    "sweep": ["sweep", str(SI_SPEC), "-o", "sweep.csv", "--plot", "pareto.png"],
    "plot": ["plot", str(SI_SPEC), "-o", "figs"],
    "plot-kinematics": ["plot", str(SI_SPEC), "-o", "figs", "--only", "kinematics"],
    "plot-linkage": ["plot", str(SI_SPEC), "-o", "figs", "--linkage", "--at", "40,200"],
    "plot-bearings": ["plot", str(SI_SPEC), "-o", "figs", "--bearings"],
}
FIGURES = {"sweep": 1, "plot": 6, "plot-kinematics": 5, "plot-linkage": 1,
           "plot-bearings": 1}


#: The commands the default tier runs (one of each kind of output: a report, JSON, a
#: spec written, a figure); the rest of the matrix runs in the slow tier.
DEFAULT_COMMANDS = ("check", "table-json", "balance", "plot-bearings")


@pytest.mark.parametrize("command", tiered(COMMANDS, DEFAULT_COMMANDS))
def test_si_spec_reads_in_si_everywhere(tmp_path, command):
    proc, figures = _run(tmp_path, *COMMANDS[command])
    assert proc.returncode == 0, proc.stderr
    outputs = {"stdout": proc.stdout, "stderr": proc.stderr}
    for path in tmp_path.glob("*.*"):
        if path.suffix in (".csv", ".toml"):
            outputs[path.name] = path.read_text()
    for where, text in outputs.items():
        for line in text.splitlines():
            if line.lstrip().startswith("#"):
                continue  # a spec's comments are the user's own words
            assert not REPORT_UNIT.search(line), f"{command} {where}: {line}"
    assert len(figures) == FIGURES.get(command, 0)
    for texts in figures:
        assert texts, "a figure with no text"
        for text in texts:
            assert not REPORT_UNIT.search(text), f"{command} figure: {text!r}"
    # and the SI units are there: a report in SI names them
    words = proc.stdout + " ".join(" ".join(t) for t in figures)
    if command in ("check", "balance", "plot", "plot-bearings"):
        assert re.search(r"\d N\b", words) or "(N)" in words or ", N" in words, command
    if command == "check":
        for u in ("m", "N m", "J", "W", "kg", "kg m^2", "rad/s"):
            assert re.search(rf"\d {re.escape(u)}\b", words), u


@pytest.mark.slow
def test_the_same_figures_in_the_report_units(tmp_path):
    """The detector would catch a figure in the report's units: the example's fig 12 says
    in-lb (so the SI test above is not passing for want of text)."""
    proc, figures = _run(tmp_path, "plot", str(DECKS / "example.toml"), "-o", "figs")
    assert proc.returncode == 0, proc.stderr
    assert any(REPORT_UNIT.search(t) for texts in figures for t in texts)


def test_balance_keeps_a_spec_s_precision_and_names_the_weight(tmp_path):
    """An SI spec balanced to a spec keeps every digit (no F8.4 rounding: ZI2 0.0075251
    stays), and with gravity on the links' weight is not called a rounding residual."""
    import tomllib

    proc, _ = _run(tmp_path, "balance", str(SI_SPEC), "-o", "out.toml")
    assert proc.returncode == 0, proc.stderr
    spec = tomllib.loads((tmp_path / "out.toml").read_text())
    assert spec["inertia"]["coupler"] == 0.056
    # the merged values are full floats, not 4-decimal roundings
    crank = spec["inertia"]["crank"]
    assert crank != round(crank, 4)
    assert "rounding to F8.4" not in proc.stdout.split("Written to")[1]
    # the residual is named as the scene's gravity (its own words), not rounding
    assert "the rest is the scene's forces (gravity)" in proc.stdout
    assert "not a rounding residual" in proc.stdout


def test_standard_gravity_is_the_definition_in_each_system():
    """g_n = 9.80665 m/s^2 exactly (the 3rd CGPM, 1901, the value SI defines); the
    report's system takes g_n / (0.0254 m/in) = 386.0886 in/sec^2 to the listing's
    G = 386.0880 (its own card, truncated).  The engine's "down" gravity is that value in
    each system: a crank alone (links 3 and 4 massless), held against its weight, takes
    the drive torque m g_n RG2 cos THETA 2, computed here from the definition."""
    import numpy as np

    from sielaff import EXAMPLE, Scene, analyze
    from sielaff.mechanism import MASS_DIVISOR, STANDARD_GRAVITY

    assert STANDARD_GRAVITY["SI"] == 9.80665
    assert abs(STANDARD_GRAVITY["in-lb-sec"] - 9.80665 / 0.0254) < 1e-3
    assert MASS_DIVISOR == {"in-lb-sec": STANDARD_GRAVITY["in-lb-sec"], "SI": 1.0}
    th = np.arange(0.0, 360.0, 15.0)
    for system, mass, rg2, g in (("SI", 2.0, 0.1, 9.80665),
                                 ("in-lb-sec", 2.0 * 386.088, 4.0, 386.088)):
        m = EXAMPLE.replace(units=system, W2=mass, W3=0.0, W4=0.0, ZI3=0.0, ZI4=0.0,
                            RG2=rg2, ADEL2=0.0)
        r = analyze(m, th, ["TORQ_GRAVITY"], scene=Scene(gravity="down"))
        weight = mass * g / MASS_DIVISOR[system]  # N, or lb (W is a weight in lb there)
        np.testing.assert_allclose(r["TORQ_GRAVITY"], weight * rg2 * np.cos(np.radians(th)),
                                   rtol=0, atol=1e-12 * weight * rg2)


def test_check_in_si_calls_the_w_fields_masses():
    """In SI the W fields hold masses (kg): check says "mass of link 2", not "weight"."""
    from sielaff.tools.check import check_deck
    from sielaff.tools.common import read_spec_deck

    deck, scene = read_spec_deck(str(SI_SPEC))
    lines = [x for x in check_deck(deck, scene=scene).lines if " W2 " in x or " W3 " in x]
    assert len(lines) == 2 and all(" kg " in x and "mass of link" in x for x in lines)
    assert not any("weight" in x for x in lines)
