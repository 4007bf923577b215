"""Run ``python -m sielaff ...`` for a test, forked from a pre-imported process (a zygote).

A test helper, not production code.  About 300 tests of the default tier need "a real
sielaff process" (status, stdout and stderr of the command, real file descriptors, a
memory limit) but nothing about how the process starts.  Each such command used to pay
Python's start-up and the imports of numpy, sielaff and matplotlib (about 1 s on a
shared core).  :func:`run` instead asks a zygote to fork: a ``python3 -c`` child of
the pytest worker (not a fork of the worker, which has threads, capture fds and
pytest's warning machinery) that imported all of that once, single-threaded.  The
forked child rebuilds what a fresh process would have (cwd, environment, RLIMIT_AS,
fds 0-2 and fresh ``sys.std*`` wrappers on them, the signal dispositions and warning
filters the zygote found at its start, ``sys.path[0]``, ``sys.argv``, a fresh
``__main__``, reseeded random generators) and runs the CLI exactly as ``python -m
sielaff`` does (runpy's ``_run_module_as_main``, so ``entry`` sets the exit status,
the signal handling and the warnings policy), then ends as the interpreter would
(thread shutdown, atexit, flushing stdout: 120 if that fails) with ``os._exit``.

What a fork cannot give a command (see ``test_procs.py``, which checks the rest):

- Python's start-up settings are the zygote's: ``PYTHON*``, locale and BLAS variables,
  and the variables matplotlib reads as it loads (:data:`STARTUP`).  A request whose
  environment differs there gets its own zygote (at most :data:`MAX_ZYGOTES` a worker),
  else a plain subprocess.
- The string hash seed is the zygote's (PYTHONHASHSEED): every command forked from one
  zygote iterates a set of strings in the same order, where fresh processes differ.
- Modules are already imported (numpy, matplotlib with Agg, every command module) and
  numpy's four import-time warning filters are in place; the address space is about
  40 MB larger than a fresh ``check``'s at the start, so RLIMIT_AS leaves that much less.
- CPU and wall seconds are the command's alone, without the start-up (about 1 s less).

If the zygote cannot start, dies, or is not single-threaded when asked to fork,
:func:`run` falls back to ``subprocess.run`` and counts it in :data:`STATS` (and warns
once per worker with :class:`ZygoteFallback`), so a test never depends on the zygote for
its verdict and an always-used fallback shows.  ``SIELAFF_TEST_ZYGOTE=0`` turns the
zygote off; ``SIELAFF_TEST_ZYGOTE_STATS=1`` prints :data:`STATS` as each worker exits.
Each worker's zygotes end when the worker exits (atexit): no process or
file is left behind.
"""

from __future__ import annotations

import atexit
import collections
import errno
import locale
import os
import pickle
import resource
import selectors
import signal
import socket
import subprocess
import sys
import time
import warnings
from pathlib import Path

#: What happened to each request: "forked", or "fallback" plus the reason.
STATS: collections.Counter = collections.Counter()
#: Distinct start-up environments served by zygotes in one worker; more run as subprocesses.
MAX_ZYGOTES = 3
#: Variables a fresh interpreter (or numpy, OpenBLAS, matplotlib as they load) reads at
#: start-up: a request must agree with its zygote on these.
STARTUP = ("LANG", "LANGUAGE", "TZ", "HOME", "MPLBACKEND", "MPLCONFIGDIR", "XDG_CONFIG_HOME",
           "XDG_CACHE_HOME")
STARTUP_PREFIXES = ("PYTHON", "LC_", "NPY_", "NUMPY_", "OPENBLAS_", "OMP_", "MKL_",
                    "VECLIB_", "GOTO", "MALLOC_")
#: The CLI asks for these as one_blas_thread does (setdefault to "1") before numpy loads.
BLAS = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "VECLIB_MAXIMUM_THREADS")
SRC = Path(__file__).resolve().parents[1] / "src"
_MAX_MESSAGE = 1 << 20


class ZygoteFallback(UserWarning):
    """A command ran as a plain subprocess because the zygote could not serve it."""


def startup_key(env: dict) -> tuple:
    """The part of ``env`` fixed when an interpreter starts (BLAS variables as the CLI
    sets them)."""
    items = {k: v for k, v in env.items() if k in STARTUP or k.startswith(STARTUP_PREFIXES)}
    for name in BLAS:
        items.setdefault(name, "1")
    return tuple(sorted(items.items()))


# ---------------------------------------------------------------------------- client side
class _Zygote:
    def __init__(self, env: dict) -> None:
        parent, child = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        env = dict(env)
        for name in BLAS:
            env.setdefault(name, "1")
        code = ("import sys; sys.path.insert(0, sys.argv[1]); import procs; "
                "del sys.path[0]; procs._serve(int(sys.argv[2]))")
        try:
            self.proc = subprocess.Popen(
                [sys.executable, "-c", code, str(Path(__file__).parent), str(child.fileno())],
                stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, env=env,
                pass_fds=(child.fileno(),))
        finally:
            child.close()
        self.sock = parent
        self.pid = self.proc.pid
        parent.settimeout(120)  # the imports: about 2 s on a quiet core
        ready = pickle.loads(parent.recv(_MAX_MESSAGE))
        parent.settimeout(None)
        if ready.get("error"):
            raise RuntimeError(ready["error"])
        self.info = ready

    def close(self) -> None:
        self.sock.close()  # the zygote reads EOF and exits
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()


_ZYGOTES: dict[tuple, _Zygote | None] = {}
_warned: set[str] = set()


def _zygote(env: dict) -> _Zygote | None:
    key = startup_key(env)
    if key in _ZYGOTES:
        return _ZYGOTES[key]
    if len(_ZYGOTES) >= MAX_ZYGOTES:
        return None
    try:
        z = _Zygote(env)
    except Exception as exc:  # noqa: BLE001 (any failure: run without it)
        _fallback_warning(f"the zygote did not start: {exc!r}")
        z = None
    _ZYGOTES[key] = z
    return z


def _fallback_warning(why: str) -> None:
    if why not in _warned:
        _warned.add(why)
        warnings.warn(f"procs: {why}; commands run as plain subprocesses", ZygoteFallback,
                      stacklevel=4)


@atexit.register
def shutdown() -> None:
    """End every zygote of this process (its children have all been waited for)."""
    for z in _ZYGOTES.values():
        if z is not None:
            z.close()
    _ZYGOTES.clear()
    if os.environ.get("SIELAFF_TEST_ZYGOTE_STATS") and STATS:
        print(f"procs (pid {os.getpid()}): {dict(STATS)}", file=sys.stderr)


def release(env: dict) -> None:
    """End the zygote that serves ``env`` (the next request starts another)."""
    z = _ZYGOTES.pop(startup_key(env), None)
    if z is not None:
        z.close()


def zygote_pids() -> list[int]:
    """The pids of this worker's running zygotes."""
    return [z.pid for z in _ZYGOTES.values() if z is not None]


def run(argv, *, cwd=None, env: dict | None = None, stdin=None, input=None,  # noqa: A002
        rlimit_as: int | None = None, timeout: float | None = None, text: bool = False,
        module: str = "sielaff") -> subprocess.CompletedProcess:
    """``subprocess.run([python, -m, module, *argv], capture_output=True, ...)``, forked
    from a zygote where it can be.

    Parameters
    ----------
    argv : sequence
        The command's arguments (str() of each) [-].
    cwd : path, optional
        Its working directory (default: this process's) [-].
    env : dict, optional
        Its whole environment (default: ``os.environ``) [-].
    stdin : file or int, optional
        Its standard input (default: this process's fd 0); ``input`` instead sends
        bytes (or str) through a pipe [-].
    rlimit_as : int, optional
        RLIMIT_AS for the command [bytes].
    timeout : float, optional
        Kill it after this long and raise ``subprocess.TimeoutExpired`` [s].
    text : bool
        Decode stdout and stderr as ``subprocess.run(text=True)`` does [-].

    Returns
    -------
    subprocess.CompletedProcess
        With ``cpu`` (the command's user + system CPU) [s], ``wall`` [s] and ``forked``
        (True when it came from a zygote) set on it.
    """
    argv = [str(a) for a in argv]
    env = dict(os.environ if env is None else env)
    cwd = os.path.abspath(os.fspath(cwd)) if cwd is not None else os.getcwd()
    if isinstance(input, str):
        input = input.encode(locale.getpreferredencoding(False))  # noqa: A001
    result = None
    z = None if os.environ.get("SIELAFF_TEST_ZYGOTE") == "0" else _zygote(env)
    if z is None:
        STATS["fallback: off" if os.environ.get("SIELAFF_TEST_ZYGOTE") == "0"
              else "fallback: its zygote died or did not start" if startup_key(env) in _ZYGOTES
              else "fallback: no zygote for this start-up environment"] += 1
    else:
        try:
            result = _forked(z, argv, cwd, env, stdin, input, rlimit_as, timeout, module)
        except subprocess.TimeoutExpired:
            raise
        except _Refused as exc:
            STATS["fallback: refused"] += 1
            _fallback_warning(f"the zygote refused to fork ({exc})")
        except (OSError, EOFError, pickle.PickleError, ConnectionError) as exc:
            STATS["fallback: zygote died"] += 1
            _fallback_warning(f"the zygote died: {exc!r}")
            _drop(env, z)
        except BaseException:  # Ctrl-C mid-request: its answer would reach the next one
            _drop(env, z)
            raise
    if result is None:
        result = _plain(argv, cwd, env, stdin, input, rlimit_as, timeout, module)
    else:
        STATS["forked"] += 1
    if text:
        result.stdout, result.stderr = _decode(result.stdout), _decode(result.stderr)
    return result


def _drop(env: dict, z: _Zygote) -> None:
    """This zygote serves no more requests (later ones run as subprocesses)."""
    _ZYGOTES[startup_key(env)] = None
    z.proc.kill()
    z.close()


def _decode(data: bytes) -> str:
    """As ``subprocess.run(text=True)``: the locale's encoding, universal newlines."""
    return data.decode(locale.getpreferredencoding(False)).replace("\r\n", "\n").replace(
        "\r", "\n")


def _plain(argv, cwd, env, stdin, input, rlimit_as, timeout, module):  # noqa: A002
    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (rlimit_as, rlimit_as))

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    proc = subprocess.run([sys.executable, "-m", module, *argv], cwd=cwd, env=env,
                          stdin=stdin if input is None else None, input=input,
                          capture_output=True, timeout=timeout,
                          preexec_fn=limit if rlimit_as is not None else None, check=False)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc.wall = time.monotonic() - start
    proc.cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    proc.forked = False
    return proc


class _Refused(Exception):
    pass


def _forked(z, argv, cwd, env, stdin, input, rlimit_as, timeout, module):  # noqa: A002
    """Send the request and the child's three fds; pump the pipes; read the verdict."""
    own: list[int] = []  # fds of ours the child gets (closed once sent)
    mine: dict[int, str] = {}
    try:
        if input is not None:
            r, w = os.pipe()
            own.append(r)
            mine[w] = "stdin"
            child_in = r
        elif stdin is None:
            child_in = 0
        else:
            child_in = stdin if isinstance(stdin, int) else stdin.fileno()
        r_out, w_out = os.pipe()
        mine[r_out] = "stdout"
        own.append(w_out)
        r_err, w_err = os.pipe()
        mine[r_err] = "stderr"
        own.append(w_err)
        request = {"argv": argv, "cwd": cwd, "env": env, "rlimit_as": rlimit_as,
                   "timeout": timeout, "module": module}
        socket.send_fds(z.sock, [pickle.dumps(request)], [child_in, w_out, w_err])
    except BaseException:
        for fd in (*own, *mine):
            os.close(fd)
        raise
    for fd in own:
        os.close(fd)
    chunks: dict[str, list[bytes]] = {"stdout": [], "stderr": []}
    view = memoryview(input or b"")
    with selectors.DefaultSelector() as sel:
        for fd, name in mine.items():
            if name == "stdin":
                os.set_blocking(fd, False)
                sel.register(fd, selectors.EVENT_WRITE, name)
            else:
                sel.register(fd, selectors.EVENT_READ, name)
        # The zygote kills the command at its timeout; this bound is for a lost zygote.
        deadline = None if timeout is None else time.monotonic() + timeout + 60
        try:
            while sel.get_map():
                wait = None if deadline is None else deadline - time.monotonic()
                if wait is not None and wait <= 0:
                    raise OSError(errno.ETIMEDOUT, "no answer from the zygote")
                for key, _ in sel.select(wait):
                    fd, name = key.fd, key.data
                    if name == "stdin":
                        try:
                            n = os.write(fd, view[:65536])
                        except BrokenPipeError:
                            n = len(view)
                        view = view[n:]
                        if not view:
                            sel.unregister(fd)
                            os.close(fd)
                            del mine[fd]
                        continue
                    data = os.read(fd, 65536)
                    if data:
                        chunks[name].append(data)
                    else:
                        sel.unregister(fd)
                        os.close(fd)
                        del mine[fd]
        finally:
            for fd in mine:
                os.close(fd)
    z.sock.settimeout(None if timeout is None else timeout + 60)
    message = z.sock.recv(_MAX_MESSAGE)
    z.sock.settimeout(None)
    if not message:
        raise EOFError("the zygote closed its socket")
    verdict = pickle.loads(message)
    if verdict.get("refused"):
        raise _Refused(verdict["refused"])
    out, err = b"".join(chunks["stdout"]), b"".join(chunks["stderr"])
    args = [sys.executable, "-m", module, *argv]
    if verdict["timed_out"]:
        raise subprocess.TimeoutExpired(args, timeout, output=out, stderr=err)
    proc = subprocess.CompletedProcess(args, verdict["status"], out, err)
    proc.cpu, proc.wall, proc.forked = verdict["cpu"], verdict["wall"], True
    proc.pid = verdict["pid"]
    return proc


# ---------------------------------------------------------------------------- zygote side
#: Filled in by _serve: what a fresh interpreter had before the imports.
_FRESH: dict = {}


def _preimport() -> list[str]:
    """Everything ``python -m sielaff`` may load, loaded once; what it loaded."""
    import importlib

    import matplotlib
    import numpy  # noqa: F401

    matplotlib.use("Agg")  # as every plotting command does before it draws
    import matplotlib.pyplot  # noqa: F401

    import sielaff.cli

    loaded = ["numpy", "matplotlib", "matplotlib.pyplot", "sielaff.cli"]
    for target in sielaff.cli.COMMANDS.values():
        name = target.partition(":")[0]
        importlib.import_module(name)
        loaded.append(name)
    return loaded


def _threads() -> tuple[int, int]:
    import threading

    return threading.active_count(), len(os.listdir("/proc/self/task"))


def _serve(fd: int) -> None:
    """The zygote: import, then fork one child per request until the socket closes."""
    sock = socket.socket(fileno=fd)
    _FRESH["signals"] = {s: signal.getsignal(s) for s in signal.valid_signals()
                         if s not in (signal.SIGKILL, signal.SIGSTOP)}
    _FRESH["mask"] = signal.pthread_sigmask(signal.SIG_BLOCK, ())
    _FRESH["filters"] = list(warnings.filters)
    try:
        # Not catch_warnings: it would also take away the filters numpy adds as it loads.
        seen: list = []
        shown, warnings.showwarning = warnings.showwarning, lambda *a, **k: seen.append(a[0])
        try:
            loaded = _preimport()
        finally:
            warnings.showwarning = shown
        if seen:
            raise RuntimeError(f"the imports warned: {[str(w) for w in seen]}")
        unexpected = [m for m in ("numba", "dask", "distributed", "scipy", "mpmath",
                                  "pandas") if m in sys.modules]
        if unexpected:
            raise RuntimeError(f"the imports loaded {unexpected}: not pure import cost")
        _FRESH["after_imports"] = list(warnings.filters)
        ready = {"loaded": loaded, "threads": _threads(), "pid": os.getpid(),
                 "filters_added": [f for f in warnings.filters if f not in _FRESH["filters"]],
                 "fds": sorted(int(x) for x in os.listdir("/proc/self/fd"))}
    except BaseException as exc:  # noqa: BLE001 (told to the client, which runs without us)
        sock.send(pickle.dumps({"error": repr(exc)}))
        return
    sock.send(pickle.dumps(ready))
    while True:
        try:
            message, fds, _, _ = socket.recv_fds(sock, _MAX_MESSAGE, 3)
        except (OSError, KeyboardInterrupt):
            return
        if not message:
            return  # the worker is gone or done
        request = pickle.loads(message)
        threads = _threads()
        if threads != (1, 1):
            for x in fds:
                os.close(x)
            sock.send(pickle.dumps({"refused": f"zygote has threads {threads}"}))
            continue
        start = time.monotonic()
        pid = os.fork()
        if pid == 0:
            _child(sock, request, fds)  # never returns
        for x in fds:
            os.close(x)
        try:
            verdict = _wait(sock, pid, request["timeout"], start)
        except KeyboardInterrupt:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            return
        if verdict is None:  # the worker went away while the command ran
            return
        sock.send(pickle.dumps(verdict))


def _wait(sock, pid: int, timeout, start: float) -> dict | None:
    pidfd = os.pidfd_open(pid)
    timed_out = False
    try:
        with selectors.DefaultSelector() as sel:
            sel.register(pidfd, selectors.EVENT_READ, "child")
            sel.register(sock, selectors.EVENT_READ, "worker")
            while True:
                wait = None if timeout is None else start + timeout - time.monotonic()
                events = sel.select(None if wait is None else max(wait, 0))
                if not events:  # the timeout: kill it, as subprocess.run does
                    os.kill(pid, signal.SIGKILL)
                    timed_out = True
                    break
                if any(key.data == "child" for key, _ in events):
                    break
                if not sock.recv(1, socket.MSG_PEEK):  # the worker closed: stop the child
                    os.kill(pid, signal.SIGKILL)
                    os.wait4(pid, 0)
                    return None
    finally:
        os.close(pidfd)
    _, status, usage = os.wait4(pid, 0)
    return {"status": os.waitstatus_to_exitcode(status), "timed_out": timed_out,
            "cpu": usage.ru_utime + usage.ru_stime, "wall": time.monotonic() - start,
            "pid": pid}


def _stdio(fd: int, like, write: bool):
    """A new ``sys.std*`` on ``fd`` as Python's start-up builds one (create_stdio), with
    the zygote's (that is, a fresh start's) encoding, errors and buffering."""
    import io

    unbuffered = isinstance(sys.__stdout__.buffer, io.FileIO)  # PYTHONUNBUFFERED or -u
    raw = io.FileIO(fd, "wb" if write else "rb", closefd=False)
    buf = raw if (unbuffered and write) else (
        io.BufferedWriter(raw) if write else io.BufferedReader(raw))
    raw.name = ("<stdin>", "<stdout>", "<stderr>")[fd]
    line_buffering = not unbuffered and (raw.isatty() or fd == 2)
    stream = io.TextIOWrapper(buf, like.encoding, like.errors, "\n", line_buffering,
                              unbuffered)
    stream.mode = "w" if write else "r"
    return stream


def _child(sock, request: dict, fds: list[int]) -> None:
    """In the fork: become a fresh ``python -m sielaff argv`` and exit with its status."""
    status = 1
    try:
        sock.close()
        for target, fd in enumerate(fds):
            os.dup2(fd, target)
        os.closerange(3, 1 << 16)  # subprocess's close_fds
        os.chdir(request["cwd"])
        os.environ.clear()
        os.environ.update(request["env"])
        if request["rlimit_as"] is not None:
            resource.setrlimit(resource.RLIMIT_AS, (request["rlimit_as"],) * 2)
        for s, handler in _FRESH["signals"].items():
            if handler is not None and signal.getsignal(s) is not handler:
                signal.signal(s, handler)
        signal.pthread_sigmask(signal.SIG_SETMASK, _FRESH["mask"])
        # A fresh process's filters, plus the four numpy adds as it loads (every command
        # but help loads numpy before any warning could be shown).
        warnings.filters[:] = _FRESH["after_imports"]
        warnings._filters_mutated()
        for stream in (sys.stdout, sys.stderr):
            stream.flush()
        sys.stdin = sys.__stdin__ = _stdio(0, sys.__stdin__, False)
        sys.stdout = sys.__stdout__ = _stdio(1, sys.__stdout__, True)
        sys.stderr = sys.__stderr__ = _stdio(2, sys.__stderr__, True)
        sys.path[0] = os.getcwd()  # -m puts the working directory first
        if "random" in sys.modules:
            sys.modules["random"].seed()
        if "numpy.random" in sys.modules:
            sys.modules["numpy.random"].seed()
        sys.orig_argv = [sys.executable, "-m", request["module"], *request["argv"]]
        sys.argv = ["-m", *request["argv"]]
        status = _as_main(request["module"])
    except BaseException:  # noqa: BLE001 (a bug here: say so on the child's stderr)
        import traceback

        try:
            traceback.print_exc()
        finally:
            os._exit(1)
    os._exit(status)


def _as_main(module: str) -> int:
    """runpy's ``_run_module_as_main`` in a fresh ``__main__``, then the interpreter's
    exit: SystemExit's code, a traceback and 1, threads joined, atexit, stdout flushed
    (120 if it cannot be)."""
    import atexit as _atexit
    import runpy
    import threading
    import types

    main = types.ModuleType("__main__")
    sys.modules["__main__"] = main
    interrupted = False
    try:
        runpy._run_module_as_main(module, alter_argv=True)
        status = 0
    except SystemExit as exc:
        status = _exit_code(exc.code)
    except KeyboardInterrupt:
        _traceback()
        status, interrupted = 1, True
    except BaseException:  # noqa: BLE001
        _traceback()
        status = 1
    threading._shutdown()
    _atexit._run_exitfuncs()
    try:
        sys.stdout.flush()
    except Exception:  # noqa: BLE001 (Python: "Exception ignored ..." and 120)
        sys.unraisablehook(_Unraisable(sys.exc_info()))
        status = 120
    try:
        sys.stderr.flush()
    except Exception:  # noqa: BLE001, S110
        pass
    if interrupted:  # Python ends by SIGINT itself after an uncaught KeyboardInterrupt
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGINT)
    return status


def _traceback() -> None:
    """The uncaught exception as the interpreter prints it: from runpy's frame down (this
    function's caller is not in a fresh process's traceback)."""
    kind, value, tb = sys.exc_info()
    tb = tb.tb_next if tb is not None else None
    sys.excepthook(kind, value.with_traceback(tb), tb)


class _Unraisable:
    def __init__(self, info) -> None:
        self.exc_type, self.exc_value, self.exc_traceback = info
        self.err_msg = "Exception ignored on flushing sys.stdout"
        self.object = None


def _exit_code(code) -> int:
    if code is None:
        return 0
    if isinstance(code, int):
        return code & 0xFF
    try:
        print(code, file=sys.stderr)
    except Exception:  # noqa: BLE001, S110
        pass
    return 1


# ---------------------------------------------------------------------------- the probe
def _probe() -> None:
    """``python -m procs``: what a test can see of its process, as JSON on stdout."""
    import json
    import threading

    if "numpy" in sys.argv:
        import numpy  # noqa: F401  (its import-time warning filters)
    print(json.dumps({
        "flags": list(sys.flags), "argv0_is_file": sys.argv[0] == __file__,
        "argv": sys.argv[1:], "path0": sys.path[0], "cwd": os.getcwd(),
        "env": dict(os.environ), "main": sorted(k for k in vars(sys.modules["__main__"])
                                                if not k.startswith("_") and k != "json"),
        "filters": [repr(f) for f in warnings.filters],
        "signals": {str(int(s)): repr(signal.getsignal(s))
                    for s in signal.valid_signals() if s not in (signal.SIGKILL,
                                                                 signal.SIGSTOP)},
        "mask": sorted(int(s) for s in signal.pthread_sigmask(signal.SIG_BLOCK, ())),
        "stdio": [(s.encoding, s.errors, s.line_buffering, s.write_through, s.mode, s.name,
                   type(s.buffer).__name__, s.buffer.seekable()) for s in
                  (sys.stdin, sys.stdout, sys.stderr)],
        "same_dunder": [sys.stdin is sys.__stdin__, sys.stdout is sys.__stdout__],
        "rlimit_as": resource.getrlimit(resource.RLIMIT_AS)[0],
        "threads": [threading.active_count(), len(os.listdir("/proc/self/task"))],
        "fds": sorted(int(x) for x in os.listdir("/proc/self/fd")),
        "stdin": sys.stdin.read() if "read" in sys.argv else None,
        "ppid": os.getppid(), "pid": os.getpid(),
        "random": __import__("random").random(), "hash": hash("sielaff"),
        "preferred": locale.getpreferredencoding(False),
    }))
    if "warn" in sys.argv:
        warnings.warn("a probe warning", UserWarning, stacklevel=1)
    if "exit" in sys.argv:
        sys.exit(int(sys.argv[-1]))
    if "raise" in sys.argv:
        raise ValueError("a probe error")


if __name__ == "__main__":
    _probe()
