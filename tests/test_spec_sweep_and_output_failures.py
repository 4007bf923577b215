"""Robust, round three (issue 21): specs, sweeps and outputs.

One test (or one parametrized family) per finding 12, 13, 15-21 and 24 and the "Also"
line.  Each reproduction runs ``sielaff`` as a subprocess under a memory limit
(``RLIMIT_AS``, :data:`MEMORY`) and a timeout, and checks the promise: one line naming
the field, the axis or the file, the shared exit status, no traceback, no Python or numpy
warning, and every output (every set of outputs) replaced whole or not at all, with an
exit message that is true.
"""

from __future__ import annotations

import os
import random
import resource
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from conftest import DECKS
from procs import run

SIELAFF = [sys.executable, "-m", "sielaff"]
#: Address space a child may use (numpy, matplotlib and dask need about 0.5 GiB of it).
MEMORY = 1 << 30
#: Words of numpy's and the engine's own warnings, never shown to a user.
API_WORDS = ("encountered", "RuntimeWarning", "ASSEMBLED", "All-NaN", "Traceback",
             "sielaff.Scene")
EXAMPLE_SPEC = (DECKS / "example.toml").read_text()
SWEEP_SPEC = (DECKS / "sweep.toml").read_text()


def _limits() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def sielaff(*argv: str, timeout: float = 120, env: dict | None = None,
            limit=_limits) -> tuple[int, str, str, float]:
    """(status, stdout, stderr, seconds) of ``sielaff argv`` under the memory limit:
    forked from the worker's zygote (tests/procs.py; seconds are the command's, without
    Python's start-up), or a plain subprocess for another ``limit``."""
    env = {**os.environ, **(env or {})}
    if limit is _limits:
        proc = run(argv, timeout=timeout, env=env, rlimit_as=MEMORY, text=True)
        return proc.returncode, proc.stdout, proc.stderr, proc.wall
    start = time.monotonic()
    proc = subprocess.run([*SIELAFF, *map(str, argv)], capture_output=True, text=True,
                          timeout=timeout, preexec_fn=limit, env=env)
    return proc.returncode, proc.stdout, proc.stderr, time.monotonic() - start


def one_line(err: str) -> str:
    """The only line of stderr, checked: no traceback, no API words."""
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert not any(w in err for w in API_WORDS), err
    return lines[0]


def no_warning(err: str) -> None:
    assert not any(w in err for w in API_WORDS), err
    assert "warning" not in err, err


def spec_with(tmp_path: Path, old: str, new: str, base: str = EXAMPLE_SPEC,
              name: str = "spec.toml") -> Path:
    assert old in base
    path = tmp_path / name
    path.write_text(base.replace(old, new, 1))
    return path


def sweep_with(tmp_path: Path, vary: str) -> Path:
    """decks/sweep.toml with its [sweep.vary] table replaced."""
    head = SWEEP_SPEC.split("[sweep.vary]")[0]
    path = tmp_path / "sweep.toml"
    path.write_text(head + "[sweep.vary]\n" + vary + "\n")
    return path


# 12. numbers past what a decimal holds -------------------------------------------------------
@pytest.mark.parametrize("value, words", [
    ("12.00000000000000000000000000001", "31 significant digits"),
    ("1e999999999", "out of range"), ("1e-999999999", "out of range"),
    ("1" + "0" * 4400, "not valid TOML"), ("1" + "0" * 200, "out of range"),
    ("inf", "not a finite number"), ("nan", "not a finite number")])
@pytest.mark.parametrize("command", ["punch", "table", "check", "sweep", "balance"])
def test_12_spec_numbers_are_bounded_before_any_arithmetic(tmp_path, value, words, command):
    base = SWEEP_SPEC if command == "sweep" else EXAMPLE_SPEC
    spec = spec_with(tmp_path, "frame = 12.0", f"frame = {value}", base)
    status, out, err, _ = sielaff(command, spec, timeout=60)
    line = one_line(err)
    assert status == 2 and out == ""
    assert words in line and line.startswith(str(spec)), line
    if words != "not valid TOML":
        assert "[lengths] frame" in line


def test_12_the_bound_is_one_function_for_every_table(tmp_path):
    """The same check for a range card, a [scene] value and a [sweep] setting."""
    from sielaff.tools.spec import PunchError, spec_number

    for value in ("1e99", "-1e99", "1e-100", "1.00000000000000000000000000001"):
        with pytest.raises(PunchError, match="where = "):
            spec_number("where", __import__("decimal").Decimal(value))
    assert spec_number("w", __import__("decimal").Decimal("9.9e98")) == \
        __import__("decimal").Decimal("9.9e98")
    for old, new in (("start = 10.0", "start = 1e999"), ("[drive]", "[scene]\ntex = 1e999\n"
                                                            "[drive]")):
        spec = spec_with(tmp_path, old, new)
        status, _, err, _ = sielaff("table", spec, timeout=60)
        assert status == 2 and "out of range" in one_line(err)
    spec = spec_with(tmp_path, "cf = 0.05 ", "cf = 1e-999999 ", SWEEP_SPEC)
    status, _, err, _ = sielaff("sweep", spec, timeout=60)
    assert status == 2 and "[sweep] cf = 1E-999999: out of range" in one_line(err)


# 13. a spec that never ends ----------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("source", ["/dev/zero", "/dev/urandom", "link", "big"])
@pytest.mark.parametrize("command", ["punch", "table", "check", "sweep", "balance"])
def test_13_every_reader_of_a_spec_is_bounded(tmp_path, source, command):
    if source == "link":
        path = tmp_path / "spec.toml"
        path.symlink_to("/dev/zero")
    elif source == "big":  # valid TOML, past the limit: a comment of 2 MiB
        path = tmp_path / "spec.toml"
        path.write_text(EXAMPLE_SPEC + "#" + "x" * (2 << 20) + "\n")
    else:
        path = Path(source)
    status, _, err, seconds = sielaff(command, path, timeout=60)
    line = one_line(err)
    assert status == 2 and seconds < 30 and line.startswith(f"{path}: ")
    if source in ("link", "big") or command == "punch":  # read as a spec
        assert "longer than 1,048,576 bytes: not a spec" in line, line


# 15. the grid's size from the axes' lengths, before any axis is built -----------------------
@pytest.mark.parametrize("axes", [2, 5, 17])
def test_15_a_huge_grid_is_refused_before_anything_is_built(tmp_path, axes):
    names = ["R1", "R2", "R3", "R4", "W2", "W3", "W4", "ZI2", "ZI3", "ZI4", "ADEL2", "ADEL3",
             "ADEL4", "RG2", "RG3", "RG4", "TH2D"][:axes]
    spec = sweep_with(tmp_path, "\n".join(f"{n} = {{ from = 1.0, to = 2.0, n = 100000000 }}"
                                          for n in names))
    status, _, err, seconds = sielaff("sweep", spec, timeout=60)
    line = one_line(err)
    assert status == 2 and "more than 100,000,000" in line and seconds < 30
    assert f"{' x '.join(['100000000'] * axes)} designs" in line


def test_15_one_axis_past_the_limit_names_it(tmp_path):
    spec = sweep_with(tmp_path, "R4 = { from = 1.0, to = 2.0, n = 100000001 }")
    status, _, err, _ = sielaff("sweep", spec, timeout=60)
    assert status == 2 and "[sweep.vary] R4 n = 100000001: more than" in one_line(err)


# 16 and 17. sweep values: finite, in range, possible; no numpy warning -----------------------
@pytest.mark.parametrize("vary, words", [
    ("R4 = { from = 9.0, to = inf, n = 3 }", "[sweep.vary] R4 to = Infinity: Infinity is "
     "not a finite number"),
    ("R4 = { from = nan, to = 9.0, n = 3 }", "[sweep.vary] R4 from = NaN"),
    ("TEX = [1e300]", "[sweep.vary] TEX = 1E+300: out of range"),
    ("R4 = [-5.0, 0.0, 12.0]", "[sweep.vary] R4 = -5: a link length must be > 0"),
    ("R1 = { from = -1.0, to = 1.0, n = 3 }", "[sweep.vary] R1 = -1: a link length must"),
    ("W3 = [1.0, -1.0]", "[sweep.vary] W3 = -1: weights and moments of inertia cannot"),
    ("ZI4 = [-0.5]", "[sweep.vary] ZI4 = -0.5"),
    ("CW_R2 = [0.0]", "[sweep.vary] CW_R2 = 0: a counterweight's radius must be > 0"),
    ("BALANCE = [2]", "[sweep.vary] BALANCE = 2: 0 (as designed) or 1"),
    ("R4 = [12.0, true]", "[sweep.vary] R4 = True: not a number")])
def test_17_sweep_values_are_checked_per_axis(tmp_path, vary, words):
    status, out, err, _ = sielaff("sweep", sweep_with(tmp_path, vary), "--workers", "1",
                                  timeout=60)
    assert status == 2 and out == "" and words in one_line(err)


@pytest.mark.parametrize("vary", ["TH2D = [0, 50]", "R1 = [30, 40]", "TEX = [-1e98, 1e98]"])
def test_16_sweeps_print_no_numpy_warning(tmp_path, vary):
    """TH2D = 0 (no flywheel: NaN), designs that are not crank-rockers (an all-NaN Pareto
    plot) and torques near the 1410's limit: rows, and not one warning."""
    pytest.importorskip("matplotlib")
    status, _, err, _ = sielaff("sweep", sweep_with(tmp_path, vary), "--workers", "1",
                                "-o", tmp_path / "s.csv", "--plot", tmp_path / "s.png")
    assert status == 0 and err.startswith("sielaff sweep: 2 designs"), err
    no_warning(err)
    rows = (tmp_path / "s.csv").read_text().splitlines()
    # designs with no whole revolution have no row (issue 22), and stderr counts them
    whole = 1 if vary.startswith("R1") else 3
    assert len(rows) == whole and (tmp_path / "s.png").stat().st_size > 1000
    assert ("2 of 2 designs left out" in err) == (whole == 1)
    if vary.startswith("TH2D"):
        assert rows[1].split(",")[4] == "nan"  # FLYWHEEL_I: none at TH2D = 0


def test_16_check_on_a_crank_that_does_not_turn(tmp_path):
    spec = spec_with(tmp_path, "speed = 50.0", "speed = 0.0")
    status, out, err, _ = sielaff("check", spec)
    no_warning(err)
    assert status == 0 and "flywheel: not sized (TH2D = 0: the crank does not turn)" in out
    assert " nan " not in out


@pytest.mark.parametrize("radius, field", [("1e300", "ZI2"), ("1e-300", "W2")])
def test_16_balance_past_the_1410s_range_is_one_line(tmp_path, radius, field):
    status, out, err, _ = sielaff("balance", DECKS / "example.dat", "--radius2", radius)
    line = one_line(err)
    assert status == 2 and out == ""
    assert f"--radius2 {float(radius):g}: the balanced design's {field} would be" in line


@pytest.mark.slow
def test_16_plot_linkage_speaks_of_crank_angles(tmp_path):
    pytest.importorskip("matplotlib")
    deck = tmp_path / "deck.dat"
    lines = (DECKS / "example.dat").read_text().splitlines()
    lines[2] = "    12.0    10.0    16.0    12.0"  # a triple-rocker: no position at 0 deg
    deck.write_text("\n".join(lines) + "\n")
    status, out, err, _ = sielaff("plot", deck, "--linkage", "--at", "0,90", "-o",
                                  tmp_path / "p")
    assert status == 0 and out.strip().endswith("linkage.png")
    assert one_line(err) == (f"sielaff: warning: {deck}: --at 0: the linkage cannot be put "
                             "together at this crank angle (link 3 does not reach link 4 "
                             "there); the drawing leaves it out")
    lines[2] = "    40.0     4.0    16.0    12.0"  # never closes
    deck.write_text("\n".join(lines) + "\n")
    status, _, err, _ = sielaff("plot", deck, "--linkage", "--animate", "-o", tmp_path / "q")
    assert status == 2 and "there is no cycle to show" in err.splitlines()[-1]
    assert not any(w in err for w in API_WORDS)


# 18. the distributed path --------------------------------------------------------------------
class _Server:
    """A TCP server on 127.0.0.1 that accepts and then says nothing (``http=False``) or
    answers every request as a web server would."""

    def __init__(self, http: bool) -> None:
        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(8)
        self.sock.settimeout(0.2)
        self.port = self.sock.getsockname()[1]
        self.http, self.stop, self.conns = http, threading.Event(), []
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:
        while not self.stop.is_set():
            try:
                conn, _ = self.sock.accept()
            except OSError:
                continue
            self.conns.append(conn)
            if self.http:
                conn.settimeout(1.0)
                try:
                    conn.recv(65536)
                    conn.sendall(b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n")
                except OSError:
                    pass

    def close(self) -> None:
        self.stop.set()
        self.thread.join(5)
        for c in self.conns:
            c.close()
        self.sock.close()


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["silent", "http", "refused", "empty"])
def test_18_scheduler_that_is_not_one_is_one_line_in_bounded_time(tmp_path, kind):
    pytest.importorskip("distributed")
    from sielaff.tools.sweep import CONNECT_SECONDS, HANDSHAKE_SECONDS

    server = _Server(http=kind == "http") if kind in ("silent", "http") else None
    try:
        if kind == "refused":
            with socket.socket() as s:  # a port nobody listens on
                s.bind(("127.0.0.1", 0))
                address = f"tcp://127.0.0.1:{s.getsockname()[1]}"
        else:
            address = "" if kind == "empty" else f"tcp://127.0.0.1:{server.port}"
        out = tmp_path / "s.csv"
        out.write_text("precious\n")
        status, _, err, seconds = sielaff("sweep", DECKS / "sweep.toml", "-o", out,
                                          "--scheduler", address, timeout=90)
    finally:
        if server is not None:
            server.close()
    line = one_line(err)
    assert status == 2 and line.startswith(f"--scheduler {address}")
    assert seconds < CONNECT_SECONDS + HANDSHAKE_SECONDS + 30
    assert out.read_text() == "precious\n"
    assert {"silent": "says nothing within 10 s", "http": "says nothing within 10 s",
            "refused": "cannot reach it (Connection refused)",
            "empty": "an empty address"}[kind] in line


_CLUSTER = """
import time
from distributed import LocalCluster
cluster = LocalCluster(n_workers=0, processes=True, host="127.0.0.1",
                       dashboard_address=None, silence_logs=50)
print(cluster.scheduler_address, flush=True)
time.sleep(600)
"""


@pytest.mark.slow
@pytest.mark.parametrize("lose", ["scheduler", "worker"])
def test_18_a_cluster_lost_mid_sweep_is_one_line(tmp_path, lose):
    """A LocalCluster (scheduler in one process, its only worker in another, on
    127.0.0.1): kill one mid-sweep; the sweep ends in one line within the stated time and
    the -o file is untouched."""
    pytest.importorskip("distributed")
    from sielaff.design.sweep import NO_WORKER_SECONDS

    spec = tmp_path / "big.toml"
    spec.write_text(SWEEP_SPEC.replace("n = 61", "n = 800"))
    cluster = subprocess.Popen([sys.executable, "-c", _CLUSTER], stdout=subprocess.PIPE,
                               stderr=subprocess.DEVNULL, text=True)
    worker = None
    try:
        address = cluster.stdout.readline().strip()
        # the cluster's only worker, without a nanny (one would start another)
        worker = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker",
                                   address, "--no-nanny", "--nthreads", "1", "--host",
                                   "127.0.0.1", "--no-dashboard"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        out = tmp_path / "s.csv"
        out.write_text("precious\n")
        sweep = subprocess.Popen([*SIELAFF, "sweep", str(spec), "-o", str(out),
                                  "--scheduler", address], stderr=subprocess.PIPE,
                                 text=True, preexec_fn=_limits)
        deadline = time.monotonic() + 90
        while not [p for p in tmp_path.iterdir() if ".tmp" in p.name]:  # connected: the
            assert sweep.poll() is None and time.monotonic() < deadline  # -o file is open
            time.sleep(0.1)
        time.sleep(3)  # computing
        assert sweep.poll() is None
        killed = time.monotonic()
        (cluster if lose == "scheduler" else worker).kill()
        _, err = sweep.communicate(timeout=NO_WORKER_SECONDS + 60)
        seconds = time.monotonic() - killed
    finally:
        for proc in (cluster, worker, locals().get("sweep")):
            if proc is not None and proc.poll() is None:
                proc.kill()
            if proc is not None:
                proc.wait()
    line = one_line(err)
    assert sweep.returncode == 2 and line.startswith(f"--scheduler {address}: ")
    assert seconds < NO_WORKER_SECONDS + 30
    assert ("the scheduler was lost or stopped mid-sweep" in line if lose == "scheduler"
            else f"no worker for {NO_WORKER_SECONDS:g} s" in line), line
    assert out.read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.toml", "s.csv"]


# 19 and 21. a folder in the way, two outputs with one name ------------------------------------
def test_19_plot_with_a_folder_in_the_way_changes_nothing(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "plots"
    out.mkdir()
    (out / "fig12-driving-torque.png").write_text("old\n")
    (out / "fig16-shaking-force.png").mkdir()  # a folder where a figure goes
    status, stdout, err, _ = sielaff("plot", DECKS / "example.dat", "-o", out)
    line = one_line(err)
    assert status == 2 and stdout == ""
    assert line == (f"sielaff: {out / 'fig16-shaking-force.png'}: is a folder: name a file "
                    "to write (nothing was written)")
    assert (out / "fig12-driving-torque.png").read_text() == "old\n"
    assert sorted(p.name for p in out.iterdir()) == ["fig12-driving-torque.png",
                                                     "fig16-shaking-force.png"]


@pytest.mark.parametrize("case", ["figure is a folder", "same name", "report is a folder"])
def test_19_21_bench_refuses_before_the_study(tmp_path, case):
    pytest.importorskip("mpmath")
    pytest.importorskip("matplotlib")
    folder = tmp_path / "r"
    target = {"figure is a folder": folder / "acc.md", "same name": folder / "acc.png",
              "report is a folder": folder / "acc.md"}[case]
    if case == "figure is a folder":
        (folder / "acc.png").mkdir(parents=True)
    if case == "report is a folder":
        target.mkdir(parents=True)
    status, stdout, err, seconds = sielaff("bench", "--quick", "-o", target, timeout=60)
    line = one_line(err)
    assert status == 2 and stdout == "" and seconds < 20  # the study takes far longer
    assert {"figure is a folder": f"{folder / 'acc.png'}: is a folder",
            "same name": "the report and its figure would both be",
            "report is a folder": "is a folder; -o names the report"}[case] in line
    assert not [p for p in tmp_path.rglob("*") if p.is_file()]


def test_19_sweep_outputs_with_one_name_are_refused(tmp_path):
    out = tmp_path / "s.csv"
    status, _, err, _ = sielaff("sweep", DECKS / "sweep.toml", "-o", out, "--plot", out)
    assert status == 2 and "two outputs cannot share a name" in one_line(err)
    assert list(tmp_path.iterdir()) == []


# 20. a set of outputs all or none, and the exit message true --------------------------------
def test_20_a_signal_during_the_renames_waits_for_them(tmp_path, monkeypatch):
    """Deterministic: SIGTERM arrives inside the first rename of a set of two.  The set
    is completed, then the signal acts, and the message names the files written."""
    from sielaff.tools import output
    from sielaff.tools.common import Terminated, install_signal_handlers

    old = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)
    install_signal_handlers()
    output.committed.clear()
    real = os.replace
    calls = []

    def replace(src, dst):
        calls.append(dst)
        if len(calls) == 1:
            signal.raise_signal(signal.SIGTERM)
        real(src, dst)

    monkeypatch.setattr(output.os, "replace", replace)
    paths = [str(tmp_path / "a.csv"), str(tmp_path / "b.png")]
    for p in paths:
        Path(p).write_text("old\n")
    try:
        with pytest.raises(Terminated):
            with output.atomic_files(paths) as temps:
                for t in temps:
                    Path(t).write_text("new\n")
    finally:
        signal.signal(signal.SIGTERM, old[0])
        signal.signal(signal.SIGINT, old[1])
    assert len(calls) == 2
    assert [Path(p).read_text() for p in paths] == ["new\n", "new\n"]
    assert output.changed_note() == f"{paths[0]}, {paths[1]} were written whole before it " \
        "arrived; no other file was changed"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "b.png"]
    output.committed.clear()
    assert output.changed_note() == "no output file was changed"


def test_20_a_failed_rename_puts_the_first_file_back(tmp_path, monkeypatch):
    from sielaff.tools import output

    real = os.replace
    calls = []

    def replace(src, dst):
        calls.append(dst)
        if len(calls) == 2 and str(dst).endswith("b.png"):
            raise PermissionError(13, "Permission denied")
        real(src, dst)

    monkeypatch.setattr(output.os, "replace", replace)
    paths = [str(tmp_path / "a.csv"), str(tmp_path / "b.png")]
    for p in paths:
        Path(p).write_text("old\n")
    output.committed.clear()
    with pytest.raises(OSError, match="Permission denied") as info:
        with output.atomic_files(paths) as temps:
            for t in temps:
                Path(t).write_text("new\n")
    assert info.value.filename == paths[1]
    assert [Path(p).read_text() for p in paths] == ["old\n", "old\n"]
    assert output.committed == []
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "b.png"]


def _trial(argv: list[str], outputs: list[Path], delay: float) -> tuple[int, str]:
    """Run ``sielaff argv``, SIGTERM it after ``delay`` s; check the outputs against the
    message.  Returns (status, what happened) for the tally."""
    for p in outputs:
        p.write_bytes(b"old\n")
    proc = subprocess.Popen([*SIELAFF, *argv], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, preexec_fn=_limits)
    time.sleep(delay)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    new = [p.read_bytes() != b"old\n" for p in outputs]
    assert "Traceback" not in err, err
    assert all(new) or not any(new), (new, err)  # a set: all or none
    if proc.returncode == 0:
        assert all(new), err
        return 0, "finished"
    if proc.returncode == -signal.SIGTERM:  # before Python let sielaff set its handlers
        assert err == "" and not any(new), err
        return -15, "before the handlers"
    assert proc.returncode == 143, err
    if "no output file was changed" in err:
        assert not any(new), err
        return 143, "unchanged"
    assert "written whole before it arrived" in err and all(new), err
    names = err.split("terminated by SIGTERM; ", 1)[1]
    assert all(str(p) in names for p in outputs), err
    return 143, "written"


@pytest.mark.slow
@pytest.mark.parametrize("command", ["table", "plot", "sweep"])
def test_20_sigterm_at_any_moment_leaves_a_true_message(tmp_path, command):
    """SIGTERM at times spread over the whole run (and just past its end): every trial's
    message is true, and a set is replaced all together or not at all."""
    if command != "table":
        pytest.importorskip("matplotlib")
    if command == "table":
        outputs = [tmp_path / "t.csv"]
        argv = ["table", str(DECKS / "example.dat"), "-o", str(outputs[0])]
    elif command == "plot":
        argv = ["plot", str(DECKS / "example.dat"), "-o", str(tmp_path / "p"), "--only",
                "kinematics"]
        (tmp_path / "p").mkdir()
        outputs = [tmp_path / "p" / f"{n}.png" for n in (
            "kin-link-angles", "kin-angular-velocity", "kin-angular-acceleration",
            "kin-pin-velocity", "kin-pin-acceleration")]
    else:
        spec = sweep_with(tmp_path, "R4 = { from = 10.0, to = 14.0, n = 30 }")
        outputs = [tmp_path / "s.csv", tmp_path / "s.png"]
        argv = ["sweep", str(spec), "--workers", "1", "-o", str(outputs[0]), "--plot",
                str(outputs[1])]
    start = time.monotonic()
    status = subprocess.run([*SIELAFF, *argv], capture_output=True, preexec_fn=_limits,
                            timeout=300).returncode
    whole = time.monotonic() - start
    assert status == 0
    rng = random.Random(21)
    seen = {}
    for _ in range(12):
        what = _trial(argv, outputs, rng.uniform(0.0, 1.2 * whole))
        seen[what] = seen.get(what, 0) + 1
        left = [p.name for p in tmp_path.rglob("*") if ".tmp" in p.name or ".old" in p.name]
        assert not left, left
    assert sum(seen.values()) == 12
    print(command, seen)  # the interleavings drawn (pytest -s shows them)


# 24. balance's outputs -----------------------------------------------------------------------
def test_24_balance_huge_counterweight_to_a_deck_is_one_line(tmp_path):
    status, _, err, _ = sielaff("balance", DECKS / "example.dat", "--radius2", "1e-300",
                                "-o", tmp_path / "b.dat")
    assert status == 2 and "past the IBM 1410's range (1E99)" in one_line(err)
    assert list(tmp_path.iterdir()) == []


def test_24_a_balanced_spec_keeps_its_precision_and_table_reads_it(tmp_path):
    import tomllib
    from decimal import Decimal

    out = tmp_path / "x.toml"
    status, text, err, _ = sielaff("balance", DECKS / "example.toml", "--radius2", "1e-5",
                                   "-o", out)
    assert status == 0 and err == "" and "every value as computed" in text
    spec = tomllib.loads(out.read_text(), parse_float=Decimal)
    rg2 = spec["mass_centres"]["crank"]["distance"]
    assert 0 < rg2 < Decimal("0.0001")  # F8.4 would have made it 0
    assert float(rg2) == float(repr(float(rg2)))
    status, table, err, _ = sielaff("table", out)
    assert status == 0 and err == "" and len(table.splitlines()) == 37
    residual = float(text.split("residual peak shaking force ")[1].split()[0])
    assert residual < 1e-6  # every digit kept: the balance is exact to roundoff
    status, _, err, _ = sielaff("balance", DECKS / "example.toml", "--radius2", "1e-5",
                                "-o", tmp_path / "x.dat")
    assert status == 0 and err == ""  # a deck: rounded to what F8.4 holds


# Also: full disk, ulimit -f, symbolic links --------------------------------------------------
def test_also_a_full_device_names_the_file(tmp_path):
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    status, _, err, _ = sielaff("table", DECKS / "example.dat", "-o", "/dev/full")
    assert status == 2
    assert one_line(err) == "sielaff: /dev/full: cannot write (No space left on device)"


@pytest.mark.parametrize("command", ["table", "punch", "sweep"])
def test_also_ulimit_f_names_the_file_and_keeps_the_old_one(tmp_path, command):
    def small_files() -> None:
        _limits()
        resource.setrlimit(resource.RLIMIT_FSIZE, (2000, 2000))

    out = tmp_path / "out.txt"
    out.write_text("precious\n")
    source = {"table": DECKS / "example.dat", "punch": DECKS / "example.toml",
              "sweep": DECKS / "sweep.toml"}[command]
    if command == "punch":  # a deck is 648 bytes: a smaller limit
        def small_files() -> None:  # noqa: F811
            _limits()
            resource.setrlimit(resource.RLIMIT_FSIZE, (100, 100))
    extra = ["--workers", "1"] if command == "sweep" else []
    status, _, err, _ = sielaff(command, source, "-o", out, *extra, limit=small_files)
    assert status == 2
    assert one_line(err) == (f"sielaff: {out}: cannot write (File too large); the file was "
                             "not changed")
    assert out.read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.txt"]


@pytest.mark.parametrize("command", ["table", "punch", "sweep", "plot", "balance"])
def test_also_every_output_writes_through_a_symbolic_link(tmp_path, command):
    """One policy: -o follows a link and replaces the file it names; the link stays."""
    if command == "plot":
        pytest.importorskip("matplotlib")
    real = tmp_path / "real"
    real.mkdir()
    name = {"table": "t.csv", "punch": "d.dat", "sweep": "s.csv", "balance": "b.dat",
            "plot": "kin-link-angles.png"}[command]
    (real / name).write_text("old\n")
    if command == "plot":
        out = tmp_path / "p"
        out.mkdir()
        (out / name).symlink_to(real / name)
        link = out / name
        argv = ["plot", DECKS / "example.dat", "-o", out, "--only", "kinematics"]
    else:
        link = tmp_path / name
        link.symlink_to(real / name)
        source = {"table": DECKS / "example.dat", "punch": DECKS / "example.toml",
                  "sweep": sweep_with(tmp_path, "R4 = [11.0, 12.0]"),
                  "balance": DECKS / "example.dat"}[command]
        argv = [command, source, "-o", link]
    status, _, err, _ = sielaff(*argv)
    assert status == 0, err
    assert link.is_symlink() and os.readlink(link) == str(real / name)
    assert (real / name).read_bytes() != b"old\n"
