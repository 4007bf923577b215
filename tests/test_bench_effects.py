"""``sielaff bench --effects`` (tools/bench/effects.py): its error measures can fail, its
hard cases happen as it says, and the command writes its tables and figure."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("scipy")

from sielaff import EXAMPLE  # noqa: E402
from sielaff.dynamics import simulate  # noqa: E402
from sielaff.tools.bench import effects as fx  # noqa: E402


def test_the_energy_error_is_small_for_the_motion_and_large_for_a_wrong_one():
    scene, motor, fw = fx.friction_scene()
    r = simulate(EXAMPLE, motor, flywheel=fw, scene=scene, speed0=50.0, revolutions=0.25,
                 rtol=1e-10, per_revolution=2000)
    assert fx.energy_error(r, scene, fw) < 1e-5
    r["MOTOR"] = r["MOTOR"] * 1.01  # a motor that gave 1% more than the motion took
    assert fx.energy_error(r, scene, fw) > 5e-3


def test_the_friction_error_is_the_tolerances():
    rows = fx.friction_rows((1e-3, 1e-13), 360, 1)
    assert rows[0]["error"] > 1e-5 and rows[1]["error"] < 1e-11
    assert rows[0]["iterations"] < rows[1]["iterations"]


def test_the_hard_cases_happen_as_reported():
    rows = {r["case"]: r["outcome"] for r in fx.hard_cases()}
    assert len(rows) == 4
    assert "positions next to its toggles have no solution of the friction law" \
        in rows["friction near a toggle"]
    assert int(rows["friction near a toggle"].split(": ")[1].split()[0]) > 0
    assert ("does not converge at THETA 2 = " in rows["friction with no solution"]
            or "has no solution at THETA 2 = " in rows["friction with no solution"])
    assert "stalled: the crank stopped" in rows["a motor too weak for the dead point"]
    assert "from rest: 5 revolutions in " in rows["a start from rest"]


def test_bench_effects_writes_its_tables_and_figure(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib")
    from sielaff.cli import main

    def small(quick, progress=print):  # the real study's parts, on the smallest grid
        assert quick
        return {"machine": "m", "quick": True, "revolutions": 0.1,
                "friction": fx.friction_rows((1e-6,), 90, 1),
                "simulate": fx.simulate_rows((1e-6,), ("LSODA",), 1, revolutions=0.1),
                "hard": [{"case": "c", "outcome": "o", "cpu_s": 0.5, "wall_s": 1.0}]}

    monkeypatch.setattr(fx, "effects_study", small)
    out = tmp_path / "r" / "effects.md"
    assert main(["bench", "--effects", "-o", str(out)]) == 0
    stdout, err = capsys.readouterr()
    assert "simulate, decks/friction.toml's scene" in stdout and "LSODA" in stdout
    text = out.read_text()
    assert "| LSODA | 1e-06 |" in text and "![error against CPU time](effects.png)" in text
    assert out.with_suffix(".png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert np.isfinite(float(text.split("| LSODA | 1e-06 | ")[1].split(" | ")[3]))
