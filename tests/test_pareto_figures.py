"""The Pareto figures (sweep --plot and the synthesis page): titled, each front point
marked and, on a small front, labelled; never a line joining the front's points, which
would suggest designs between them (issue 33, item 4)."""

from __future__ import annotations

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")


def _capture(monkeypatch):
    import matplotlib.pyplot as plt

    kept = []
    monkeypatch.setattr(plt, "close", lambda fig=None: kept.append(fig))
    return kept


def test_the_sweep_pareto_plot(monkeypatch, tmp_path):
    from sielaff.tools.sweep import FRONT_LABELS, _pareto, _plot

    kept = _capture(monkeypatch)
    rng = np.random.default_rng(3)
    x, y = rng.uniform(1, 2, 200), rng.uniform(1, 2, 200)
    designs = np.arange(200) + 1000  # the DESIGN numbers, not the positions
    front = _pareto(x, y)
    assert 2 <= len(front) <= FRONT_LABELS
    _plot(str(tmp_path / "p.png"), x, y, ("TORQ_RMS", "SHAK_PEAK"), "in-lb-sec", 200,
          designs=designs)
    ax = kept[-1].get_axes()[0]
    assert ax.get_title().startswith("Pareto front of TORQ_RMS and SHAK_PEAK: 200 designs")
    lines = [ln for ln in ax.get_lines() if ln.get_label().startswith("Pareto front")]
    assert len(lines) == 1 and lines[0].get_linestyle() in ("None", "none", "")
    assert len(lines[0].get_xdata()) == len(front)
    labels = sorted(int(t.get_text()) for t in ax.texts)
    assert labels == sorted(int(designs[i]) for i in front)


def test_the_synthesis_pareto_figure_marks_and_does_not_join(monkeypatch):
    from sielaff.tools import report

    kept = []
    monkeypatch.setattr(report, "png", lambda fig: kept.append(fig) or b"")
    from conftest import DECKS
    from sielaff.tools.synth import synthesize

    done = synthesize(str(DECKS / "synth.toml"))
    report._pareto_figure(done)
    ax = kept[-1].get_axes()[0]
    assert ax.get_title()
    front = [ln for ln in ax.get_lines() if ln.get_label().startswith("Pareto front")]
    assert len(front) == 1 and front[0].get_linestyle() in ("None", "none", "")
