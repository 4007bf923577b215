"""The zygote (tests/procs.py) gives a command what a fresh ``python -m sielaff`` has.

Each comparison runs the same request twice: forked from the zygote and as a plain
``subprocess.run`` (procs._plain, the fallback), and wants the same status, stdout and
stderr; the probe (``python -m procs``) compares what a program can see of its process.
"""

from __future__ import annotations

import json
import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import procs
from conftest import DECKS, tiered

TESTS = Path(__file__).resolve().parent
EXAMPLE = DECKS / "example.dat"
MEMORY = 1 << 30


def both(argv, **kw):
    """(forked, plain) results of one request; the first is checked to be a fork."""
    text = kw.pop("text", True)
    forked = procs.run(argv, text=text, **kw)
    assert forked.forked, procs.STATS
    env = dict(os.environ if kw.get("env") is None else kw["env"])
    cwd = os.fspath(kw.get("cwd") or os.getcwd())
    if hasattr(kw.get("stdin"), "seek"):
        kw["stdin"].seek(0)  # the fork read the same open file
    plain = procs._plain([str(a) for a in argv], cwd, env, kw.get("stdin"), kw.get("input"),
                         kw.get("rlimit_as"), kw.get("timeout"), kw.get("module", "sielaff"))
    if text:
        plain.stdout, plain.stderr = procs._decode(plain.stdout), procs._decode(plain.stderr)
    return forked, plain


def same(argv, **kw) -> subprocess.CompletedProcess:
    forked, plain = both(argv, **kw)
    assert (forked.returncode, forked.stdout, forked.stderr) == (
        plain.returncode, plain.stdout, plain.stderr)
    return forked


def probe(*words, **kw) -> tuple[dict, dict, subprocess.CompletedProcess]:
    """The probe forked and fresh, with one BLAS thread as the CLI asks (else the fresh
    one's numpy starts a thread per core, which the zygote's did not)."""
    kw.setdefault("cwd", TESTS)
    kw["env"] = {"OPENBLAS_NUM_THREADS": "1", **(kw.get("env") or os.environ)}
    forked, plain = both(words, module="procs", **kw)
    assert forked.returncode == plain.returncode == 0, (forked.stderr, plain.stderr)
    return json.loads(forked.stdout), json.loads(plain.stdout), forked


def bad_deck(tmp_path: Path) -> Path:
    lines = EXAMPLE.read_text().splitlines()
    lines[0] = "    4.x " + lines[0][8:]
    path = tmp_path / "bad.dat"
    path.write_text("\n".join(lines) + "\n")
    return path


CASES = {
    "run the example deck": lambda tmp: (["run", EXAMPLE], {}),
    "run to a file": lambda tmp: (["run", EXAMPLE, "-o", tmp / "x.asa"], {}),
    "check": lambda tmp: (["check", EXAMPLE], {}),
    "check json of a spec": lambda tmp: (["check", DECKS / "example.toml", "--format",
                                          "json"], {}),
    "a bad deck's one line and status 2": lambda tmp: (["run", bad_deck(tmp)], {}),
    "the same with --debug: a traceback": lambda tmp: (["--debug", "run", bad_deck(tmp)], {}),
    "a warning (--max-sheets)": lambda tmp: (["run", EXAMPLE, "--max-sheets", "2"], {}),
    "not a crank-rocker: status 3": lambda tmp: (["check", "--crank-rocker",
                                                  DECKS / "double-crank.dat"], {}),
    "stdin -": lambda tmp: (["table", "-"], {"input": EXAMPLE.read_bytes()}),
    "stdin - from a file": lambda tmp: (["check", "-"], {"stdin": open(EXAMPLE, "rb")}),  # noqa: SIM115
    "a bad card on stdin": lambda tmp: (["run", "-"], {"input": bad_deck(tmp).read_bytes()}),
    "memory-limited run": lambda tmp: (["run", EXAMPLE, "--arith", "ibm1410"],
                                       {"rlimit_as": MEMORY}),
    "a usage error (argparse, status 2)": lambda tmp: (["run"], {}),
    "help": lambda tmp: (["help", "exit"], {}),
    "a relative path in another cwd": lambda tmp: (["check", "example.dat"], {"cwd": DECKS}),
    "an environment of its own (SIELAFF_KERNEL_DIR)": lambda tmp: (
        ["table", DECKS / "example.toml"],
        {"env": {**os.environ, "SIELAFF_KERNEL_DIR": str(tmp / "k")}}),
}


#: The cases the default tier compares (each one also runs a fresh interpreter); the
#: others run in the slow tier.
DEFAULT_CASES = ("run the example deck", "a bad deck's one line and status 2",
                 "the same with --debug: a traceback", "a warning (--max-sheets)", "stdin -",
                 "memory-limited run")


@pytest.mark.parametrize("case", tiered(CASES, DEFAULT_CASES))
def test_a_command_forked_is_the_command_run(tmp_path, case):
    argv, kw = CASES[case](tmp_path)
    try:
        result = same(argv, **kw)
    finally:
        if hasattr(kw.get("stdin"), "close"):
            kw["stdin"].close()
    if case.startswith("a bad"):
        assert result.returncode == 2 and result.stderr.count("\n") == 1, result.stderr
    if "warning" in case:
        assert "sielaff: warning: " in result.stderr
    if "traceback" in case:
        assert "Traceback" in result.stderr
    if "status 3" in case:
        assert result.returncode == 3


def test_bytes_stdout_is_the_same(tmp_path):
    forked = same(["run", EXAMPLE, "--render"], text=False)
    assert isinstance(forked.stdout, bytes) and b"\f" in forked.stdout


def test_the_probe_sees_a_fresh_process():
    forked, plain, result = probe("numpy", "read", input=b"some input\n")
    assert forked["ppid"] in procs.zygote_pids() and plain["ppid"] == os.getpid()
    assert result.pid == forked["pid"]
    for key in ("pid", "ppid", "random"):
        assert forked.pop(key) != plain.pop(key), key
    # the string hash seed is the zygote's, not the fresh one each process would draw
    seeded = os.environ.get("PYTHONHASHSEED", "random") != "random"
    assert (forked.pop("hash") == plain.pop("hash")) == seeded
    assert forked == plain
    assert forked["stdin"] == "some input\n" and forked["argv0_is_file"]
    # Python's own start-up ignores SIGPIPE; the fork has it so too
    assert plain["signals"][str(int(signal.SIGPIPE))] == "<Handlers.SIG_IGN: 1>"


def test_the_parent_is_the_zygote_and_each_request_forks():
    before = procs.STATS["forked"]
    seen, randoms, hashes = set(), set(), set()
    for _ in range(3):
        result = procs.run(["numpy"], module="procs", cwd=TESTS, text=True)
        assert result.returncode == 0 and result.forked, result.stderr
        info = json.loads(result.stdout)
        seen.add(info["pid"])
        randoms.add(info["random"])
        hashes.add(info["hash"])
        assert info["ppid"] in procs.zygote_pids()
        assert info["threads"] == [1, 1]
    assert procs.STATS["forked"] == before + 3
    assert len(seen) == 3 and len(randoms) == 3  # new processes, reseeded
    assert len(hashes) == 1  # the one difference kept: the zygote's string hash seed


def test_the_zygote_is_single_threaded_and_loaded_everything():
    procs.run(["help"])
    info = next(z.info for z in procs._ZYGOTES.values() if z is not None)
    assert info["threads"] == (1, 1)
    assert "sielaff.tools.report" in info["loaded"] and "matplotlib.pyplot" in info["loaded"]


def test_python_warnings_exit_codes_and_uncaught_exceptions():
    for words in (("warn",), ("exit", "5"), ("raise",)):
        forked, plain = both(words, module="procs", cwd=TESTS, text=True)
        assert (forked.returncode, forked.stderr) == (plain.returncode, plain.stderr), words
    assert forked.returncode == 1 and "ValueError: a probe error" in forked.stderr


@pytest.mark.slow  # the harness's failure paths: a zygote killed, a timeout
def test_a_python_warning_from_a_command_under_pythonwarnings(tmp_path):
    """Another start-up environment (PYTHONWARNINGS) gets its own zygote, started with it."""
    env = dict(os.environ, PYTHONWARNINGS="error")
    try:
        forked, plain, _ = probe("numpy", env=env)
        assert forked["filters"] == plain["filters"]
        assert any(f.startswith("('error'") for f in forked["filters"])
        assert len(procs.zygote_pids()) >= 2
    finally:
        procs.release(env)


@pytest.mark.slow  # the harness's failure paths: a zygote killed, a timeout
def test_a_dead_zygote_is_a_counted_fallback(monkeypatch):
    """A zygote of its own (another start-up environment), killed: the command still runs,
    as a subprocess, and the fallback is counted and warned about."""
    monkeypatch.setattr(procs, "MAX_ZYGOTES", 99)
    env = dict(os.environ, LC_PROCS_TEST="1")
    first = procs.run(["check", EXAMPLE], env=env, text=True)
    assert first.forked
    zygote = procs._ZYGOTES[procs.startup_key(env)]
    zygote.proc.kill()
    zygote.proc.wait()
    died = procs.STATS["fallback: zygote died"]
    with pytest.warns(procs.ZygoteFallback, match="the zygote died"):
        second = procs.run(["check", EXAMPLE], env=env, text=True)
    assert not second.forked and procs.STATS["fallback: zygote died"] == died + 1
    assert (second.returncode, second.stdout, second.stderr) == (
        first.returncode, first.stdout, first.stderr)
    later = procs.STATS["fallback: its zygote died or did not start"]
    assert not procs.run(["help"], env=env).forked
    assert procs.STATS["fallback: its zygote died or did not start"] == later + 1
    procs.release(env)


def test_memory_limit_is_applied():
    forked, plain, _ = probe(rlimit_as=MEMORY)
    assert forked["rlimit_as"] == plain["rlimit_as"] == MEMORY
    result = procs.run(["check", EXAMPLE], rlimit_as=50 << 20, text=True)
    assert result.forked and result.returncode != 0  # numpy's arrays cannot be had


@pytest.mark.slow  # the harness's failure paths: a zygote killed, a timeout
def test_a_timeout_kills_the_command():
    r, w = os.pipe()  # stdin that never ends: the command waits for its deck
    try:
        start = time.monotonic()
        with pytest.raises(subprocess.TimeoutExpired):
            procs.run(["check", "-"], stdin=r, timeout=2)
        assert time.monotonic() - start < 30
    finally:
        os.close(r)
        os.close(w)
    assert procs.run(["help"]).forked  # the zygote still serves


def test_cpu_and_wall_are_the_commands():
    """The CPU seconds a run reports are the command's own (the forked child's), not the
    test process's: this process only waits meanwhile."""
    procs.run(["help"])  # the zygote started (its start-up is this process's work)
    before = resource.getrusage(resource.RUSAGE_SELF)
    result = procs.run(["run", EXAMPLE, "--arith", "ibm1410"])
    after = resource.getrusage(resource.RUSAGE_SELF)
    assert result.forked and 0 < result.cpu <= result.wall + 0.5
    own = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    assert own < 0.5 * result.cpu, (own, result.cpu)


@pytest.mark.slow  # the harness's failure paths: a zygote killed, a timeout
def test_the_fallback_is_counted_and_gives_the_same(monkeypatch):
    monkeypatch.setenv("SIELAFF_TEST_ZYGOTE", "0")
    before = procs.STATS["fallback: off"]
    result = procs.run(["check", EXAMPLE], text=True)
    assert not result.forked and procs.STATS["fallback: off"] == before + 1
    monkeypatch.delenv("SIELAFF_TEST_ZYGOTE")
    assert procs.run(["check", EXAMPLE], text=True).stdout == result.stdout


@pytest.mark.slow  # the harness's failure paths: a zygote killed, a timeout
def test_no_zygote_outlives_its_worker():
    """A separate interpreter uses procs and exits: its zygote is gone after it."""
    code = ("import sys; sys.path[:0] = [sys.argv[1]]; import procs; "
            "r = procs.run(['help']); print(r.forked, procs.zygote_pids()[0])")
    out = subprocess.run([sys.executable, "-c", code, str(TESTS)], capture_output=True,
                         text=True, timeout=120, check=True).stdout.split()
    assert out[0] == "True"
    pid = int(out[1])
    deadline = time.monotonic() + 10
    while Path(f"/proc/{pid}").exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    status = Path(f"/proc/{pid}/stat")
    assert not status.exists() or status.read_text().split()[2] == "Z"
