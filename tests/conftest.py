"""Shared fixtures: paths, the example deck, and the listing it prints."""

from __future__ import annotations

import io
import shutil
from pathlib import Path

import pytest
from hypothesis import settings

# CI machines are shared and noisy: time bounds belong in benchmarks, not in
# hypothesis's per-example deadline.
settings.register_profile("sielaff", deadline=None)
settings.load_profile("sielaff")

ROOT = Path(__file__).resolve().parents[1]
DECKS = ROOT / "decks"
GOLDEN = ROOT / "golden"


def tiered(values, default) -> list:
    """pytest parameters of ``values``, each marked slow unless the default tier runs it:
    ``default`` is the values it runs, or a predicate on a value.  A tuple value gives
    one argument per name of a multi-name parametrize ("kind, branch")."""
    runs = default if callable(default) else default.__contains__
    return [pytest.param(*(v if isinstance(v, tuple) else (v,)),
                         marks=() if runs(v) else pytest.mark.slow) for v in values]


def split_sheets(text: str) -> list[list[str]]:
    """Records of an ASA listing grouped into sheets, each ending with its '1' record."""
    sheets, current = [], []
    for record in text.splitlines():
        current.append(record)
        if record == "1":
            sheets.append(current)
            current = []
    assert not current, "listing does not end with a page eject"
    return sheets


@pytest.fixture(scope="session")
def example_deck():
    from sielaff.emulator.cards import read_deck

    return read_deck(DECKS / "example.dat")


@pytest.fixture(scope="session")
def example_listing(example_deck) -> str:
    from sielaff.emulator.run import run

    buf = io.StringIO()
    run(example_deck, buf)
    return buf.getvalue()


def pytest_configure(config):
    """SIELAFF_ULP_NUDGE=+1/-1: run as if on a CPU whose libm differs by an ulp.

    Where PYTHONDONTWRITEBYTECODE is set (this machine kind sets it), every command a test
    runs as a child process, and each xdist worker, would compile sielaff's modules and
    the test files from source again: 0.2-0.3 s a process, a third of a plain ``sielaff
    check``.  The children and the workers (started after this hook) keep their bytecode
    as Python does by default, in ``__pycache__`` beside each source (ignored by git, so
    ``git status`` stays clean).  Not PYTHONPYCACHEPREFIX: with a prefix Python would also
    pass over the installed libraries' bytecode and compile numpy and matplotlib again."""
    import os

    os.environ.pop("PYTHONDONTWRITEBYTECODE", None)

    nudge = os.environ.get("SIELAFF_ULP_NUDGE")
    if nudge:
        import ulp_nudge

        ulp_nudge.install(float(nudge))


#: The default tier's longest files, longest first (per-file sums of ``--durations=0``
#: on this machine kind).  ``--dist loadfile`` hands files to the two workers in
#: collection order, so these go first and the short ones fill in at the end: the
#: workers finish together instead of one waiting on a long file handed out last.
#: Only the order changes; a file not listed keeps its place after these.
LONGEST_FIRST = ("test_compiled.py", "test_ibm1410.py", "test_report.py", "test_simulate.py",
                 "test_fortran.py", "test_procs.py", "test_synthesis.py", "test_units.py",
                 "test_spec_sweep_and_output_failures.py", "test_unix.py", "test_scene.py",
                 "test_punch.py", "test_effects.py", "test_classify.py",
                 "test_simulate_friction.py", "test_interpreter_and_reader_limits.py",
                 "test_design_answers_in_the_tools.py", "test_run_failures.py",
                 "test_effect_declarations.py", "test_spec_names.py",
                 "test_friction_solutions.py", "test_steady_state.py")


def pytest_collection_modifyitems(session, config, items):
    rank = {name: k for k, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))  # stable: files stay whole


#: Debian's chromium, for the report's browser tests, and the flags that keep it offline.
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]


@pytest.fixture(scope="module")
def browser():
    """Headless Chromium through Playwright (the ``browser`` extra), one per test module;
    skipped, saying why, where either is missing."""
    if CHROMIUM is None:
        pytest.skip("no chromium here (Debian's package: apt-get install chromium)")
    sync_api = pytest.importorskip("playwright.sync_api",
                                   reason="the browser extra: pip install -e '.[browser]'")
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        yield b
        b.close()
