"""A signal the interrupted code swallows is still the signal: one that lands while a C
extension loads (numpy importing ``datetime``) comes back as that extension's ImportError;
one whose handler runs in a weakref callback (matplotlib's transforms) is sent again a
moment later, and the figure it cut short may fail first with an error of its own
("Invalid bounding box").  The command reports the signal in one line, with its status, and
no traceback (both found by test_spec_sweep_and_output_failures' SIGTERM trials: under load,
and on CI).  One that lands inside an extension's initialisation leaves a half-made module
that aborts the interpreter as it finalises; the process ends without finalising (found on
CI the same way)."""

from __future__ import annotations

import signal

import pytest

from conftest import DECKS

#: What the interrupted code raised instead of the signal.
AFTERMATHS = {
    "import": ImportError("PyCapsule_Import could not import module \"datetime\""),
    "figure": ValueError("Invalid bounding box"),
    "file": OSError(5, "Input/output error", "p/kin-link-angles.png"),
}


def _swallowing(signum, aftermath):
    from sielaff.tools.common import SIGNAL_STATE

    def command(args):
        SIGNAL_STATE["raised"] = signum  # what _raise_terminated records before raising
        raise AFTERMATHS[aftermath]
    return lambda name: command


@pytest.mark.parametrize("aftermath", sorted(AFTERMATHS))
@pytest.mark.parametrize("signum, status, words", [
    (signal.SIGTERM, 143, "terminated by SIGTERM"),
    (signal.SIGHUP, 129, "terminated by SIGHUP"),
    (signal.SIGINT, 130, "interrupted"),
])
def test_a_signal_swallowed_is_still_the_signal(monkeypatch, capsys, signum, status, words,
                                                aftermath):
    from sielaff import cli

    monkeypatch.setattr(cli, "_command", _swallowing(signum, aftermath))
    assert cli.main(["check", str(DECKS / "example.dat")]) == status
    err = capsys.readouterr().err
    assert err.startswith(f"sielaff: {words}; ") and err.count("\n") == 1, err


@pytest.mark.parametrize("aftermath, status", [("figure", 2), ("file", 2)])
def test_an_error_without_a_signal_is_not_dressed_as_one(monkeypatch, capsys, aftermath,
                                                         status):
    from sielaff import cli

    def command(args):
        raise AFTERMATHS[aftermath]
    monkeypatch.setattr(cli, "_command", lambda name: command)
    assert cli.main(["check", str(DECKS / "example.dat")]) == status
    err = capsys.readouterr().err
    assert "terminated" not in err and err.count("\n") == 1, err
    assert str(AFTERMATHS[aftermath].args[-1]) in err, err


def test_an_import_error_without_a_signal_is_not_dressed_as_one(monkeypatch):
    from sielaff import cli

    def command(args):
        raise ImportError("a real one")
    monkeypatch.setattr(cli, "_command", lambda name: command)
    with pytest.raises(ImportError, match="a real one"):
        cli.main(["check", str(DECKS / "example.dat")])


DEL_SCRIPT = """
import os, signal, time
from sielaff.tools import common
common.install_signal_handlers(process=True)
class Finalised:
    def __del__(self):  # as matplotlib's transforms' weakref callbacks run
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.05)  # the handler runs here, inside __del__
try:
    Finalised()
    for _ in range(300):
        time.sleep(0.01)
    print("not terminated")
except common.Terminated as exc:
    print("terminated", exc.status)
"""


def test_a_signal_inside_a_finaliser_still_unwinds_the_command():
    """A SIGTERM whose handler runs inside a ``__del__`` or a weakref callback cannot
    unwind from there (Python prints it as "Exception ignored" with a traceback and goes
    on); the process sends it again, and the command unwinds in one piece."""
    import subprocess
    import sys

    r = subprocess.run([sys.executable, "-c", DEL_SCRIPT], capture_output=True, text=True,
                       timeout=60)
    assert r.stdout.split() == ["terminated", "143"], r.stdout + r.stderr
    assert r.stderr == "", r.stderr


FT2FONT_SCRIPT = """
import os, signal, sys
state = {"loading": False, "sent": False}
def audit(event, args):
    if event == "import" and args[0] == "matplotlib.ft2font":
        state["loading"] = True
sys.addaudithook(audit)
def profile(frame, event, arg):
    # the first Python function ft2font's initialisation calls (pybind11's enums)
    if (event == "call" and state["loading"] and not state["sent"]
            and not frame.f_code.co_filename.startswith("<") and frame.f_back is not None
            and frame.f_back.f_code.co_name == "_call_with_frames_removed"):
        state["sent"] = True
        sys.setprofile(None)
        os.write(1, b"sent inside ft2font's initialisation\\n")
        os.kill(os.getpid(), signal.SIGTERM)
sys.setprofile(profile)
from sielaff.cli import entry
sys.argv = ["sielaff", *sys.argv[1:]]
entry()
"""


def test_a_signal_inside_an_extensions_initialisation_ends_with_its_status(tmp_path):
    """SIGTERM sent while matplotlib's ft2font initialises (its pybind11 enums run Python
    code, where the handler raises): the import fails, the command says so in one line and
    ends with 143; finalising the half-made module would abort the interpreter after the
    message ("Fatal Python error: PyThreadState_Get", status -6), so the process does not
    finalise."""
    import subprocess
    import sys

    pytest.importorskip("matplotlib")
    r = subprocess.run([sys.executable, "-c", FT2FONT_SCRIPT, "plot", str(DECKS / "example.dat"),
                        "-o", str(tmp_path), "--only", "kinematics"], capture_output=True,
                       text=True, timeout=120)
    assert r.stdout == "sent inside ft2font's initialisation\n", r.stdout + r.stderr  # drawn
    assert r.stderr == "sielaff: terminated by SIGTERM; no output file was changed\n", r.stderr
    assert r.returncode == 143
    assert list(tmp_path.iterdir()) == []
