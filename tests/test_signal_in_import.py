"""A signal that lands while a C extension loads (numpy importing ``datetime``) comes back
as that extension's ImportError; the command still reports the signal in one line, with
its status, and no traceback (found by test_robust3_tools' SIGTERM trials under load)."""

from __future__ import annotations

import signal

import pytest

from conftest import DECKS


def _swallowing(signum):
    from sielaff.tools.common import SIGNAL_STATE

    def command(args):
        SIGNAL_STATE["raised"] = signum  # what _raise_terminated records before raising
        raise ImportError("PyCapsule_Import could not import module \"datetime\"")
    return lambda name: command


@pytest.mark.parametrize("signum, status, words", [
    (signal.SIGTERM, 143, "terminated by SIGTERM"),
    (signal.SIGHUP, 129, "terminated by SIGHUP"),
    (signal.SIGINT, 130, "interrupted"),
])
def test_a_signal_swallowed_by_an_import_is_still_the_signal(monkeypatch, capsys, signum,
                                                             status, words):
    from sielaff import cli

    monkeypatch.setattr(cli, "_command", _swallowing(signum))
    assert cli.main(["check", str(DECKS / "example.dat")]) == status
    err = capsys.readouterr().err
    assert err.startswith(f"sielaff: {words}; ") and err.count("\n") == 1, err


def test_an_import_error_without_a_signal_is_not_dressed_as_one(monkeypatch):
    from sielaff import cli

    def command(args):
        raise ImportError("a real one")
    monkeypatch.setattr(cli, "_command", lambda name: command)
    with pytest.raises(ImportError, match="a real one"):
        cli.main(["check", str(DECKS / "example.dat")])
