"""What ``sielaff``'s start-up depends on: numpy's BLAS asked for one thread before numpy
loads (sielaff calls no BLAS routine; the pool's threads are start-up cost), and a user's
own setting kept."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from sielaff import cli

ROOT = Path(__file__).resolve().parents[1]


def _python(code: str, env: dict[str, str]) -> str:
    env = dict(env, PYTHONPATH=str(ROOT / "src"))
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                          text=True, check=True, timeout=120).stdout.strip()


def _clean_env() -> dict[str, str]:
    return {k: v for k, v in os.environ.items() if k not in cli.BLAS_THREAD_VARIABLES}


def test_importing_the_command_line_does_not_load_numpy():
    """The entry points set the variables after ``import sielaff.cli``: too late if that
    import had loaded numpy."""
    assert _python("import sys, sielaff.cli; print('numpy' in sys.modules)",
                   _clean_env()) == "False"


def test_set_when_absent_kept_when_the_user_set_it(monkeypatch):
    for name in cli.BLAS_THREAD_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("MKL_NUM_THREADS", "3")
    cli.one_blas_thread()
    assert os.environ["OPENBLAS_NUM_THREADS"] == "1"
    assert os.environ["VECLIB_MAXIMUM_THREADS"] == "1"
    assert os.environ["MKL_NUM_THREADS"] == "3"


RUN_MAIN = """
import os, runpy, sys
sys.argv = ["sielaff", "run", {deck!r}, "-o", os.devnull]
try:
    runpy.run_module("sielaff", run_name="__main__")
except SystemExit as exc:
    assert exc.code == 0, exc.code
import numpy
print(os.environ.get("OPENBLAS_NUM_THREADS"), len(os.listdir("/proc/self/task")))
"""


@pytest.mark.skipif(not os.path.isdir("/proc/self/task"), reason="threads counted in /proc")
@pytest.mark.parametrize("user", [None, "2"])
def test_python_m_sielaff_runs_with_one_blas_thread(user):
    """``python -m sielaff run``: one thread in the process after the run (numpy loaded),
    unless the user asked for more (then OpenBLAS starts its pool, on more than one core)."""
    env = _clean_env()
    if user:
        env["OPENBLAS_NUM_THREADS"] = user
    out = _python(RUN_MAIN.format(deck=str(ROOT / "decks" / "example.dat")), env)
    setting, threads = out.split()
    assert setting == (user or "1")
    if user is None:
        assert threads == "1"
    elif (os.cpu_count() or 1) > 1 and "openblas" in _python(
            "import numpy; numpy.show_config()", env).lower():
        assert int(threads) > 1  # the same count would pass without the setting
