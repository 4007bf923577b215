"""Output files that are written whole or not at all, one file or a set of them.

Every output goes to a temporary file in its target's folder; the temporaries are
renamed over the targets only when all of them are written.  The renames (the
*commit*) run with Ctrl-C, SIGTERM and SIGHUP deferred: a signal that arrives during
them is acted on just after, so a set is replaced all together or not at all, and
:data:`committed` says which files were, for the exit message to be true.

One policy for every command's ``-o``:

* a symbolic link is followed: the file it points to is replaced (as the shell's ``>``
  writes through it), and the link stays;
* a target that exists and is not a regular file (``/dev/null``, a named pipe, a
  terminal) is written in place (``atomic_output`` only: a set of files is refused);
* a folder where a file is to go is refused before anything is written, naming it;
* the same file named twice in one set is refused;
* a missing folder on the way is created;
* a write that fails (a full disk, ``ulimit -f``) names the file asked for, never the
  temporary one.
"""

from __future__ import annotations

import contextlib
import errno
import os
import signal
import stat
import sys
import tempfile
from collections.abc import Iterator
from typing import TextIO

#: The output files this process has replaced (the paths asked for), in order.
committed: list[str] = []

#: Signals that arrived while a commit was running (acted on when it ends).
_pending: list[int] = []
_deferring = False


def deferring() -> bool:
    """True while a commit runs: a signal handler should call :func:`defer` and return."""
    return _deferring


def defer(signum: int) -> None:
    """Remember ``signum`` until the running commit ends."""
    _pending.append(signum)


@contextlib.contextmanager
def _signals_deferred() -> Iterator[None]:
    """Run the block with Ctrl-C, SIGTERM and SIGHUP held back (the handlers of
    :func:`sielaff.tools.common.install_signal_handlers` defer them); the first one that
    arrived is raised again when the block ends."""
    global _deferring
    if _deferring:  # nested: the outer block re-raises
        yield
        return
    _deferring = True
    try:
        yield
    finally:
        _deferring = False
        if _pending:
            signum = _pending[0]
            _pending.clear()
            signal.raise_signal(signum)  # the handler runs now, outside the commit


def changed_note() -> str:
    """What the exit message says about the outputs: true in every interleaving."""
    if not committed:
        return "no output file was changed"
    names = ", ".join(committed)
    return (f"{names} {'was' if len(committed) == 1 else 'were'} written whole before it "
            "arrived; no other file was changed")


def _cannot_write(path: str, err: OSError, in_place: bool = False) -> str:
    """Why an output cannot be written, in words that fit the case."""
    folder = os.path.dirname(os.path.abspath(path))
    if err.errno in (errno.ENOSPC, errno.EFBIG, errno.EDQUOT):
        return f"cannot write ({err.strerror})" + (
            "" if in_place else "; the file was not changed")
    if os.path.isdir(folder):  # the folder is there: it takes no new file (/proc, read-only)
        return f"cannot write (no new file can be made in {folder}: {err.strerror})"
    return f"cannot write ({err.strerror})"


def _named(err: OSError, path: str, in_place: bool = False) -> OSError:
    """``err`` naming ``path`` (the file asked for), not a temporary file."""
    return OSError(err.errno, _cannot_write(path, err, in_place), path)


def _mode_for(path: str) -> int:
    """The permissions a replacement of ``path`` gets: the old file's, or 0666 less the
    umask for a new one."""
    try:
        return stat.S_IMODE(os.stat(path).st_mode)
    except OSError:
        umask = os.umask(0o022)
        os.umask(umask)
        return 0o666 & ~umask


def check_targets(paths: list[str]) -> list[str]:
    """The files ``paths`` will replace (symbolic links followed), checked before any work:
    OSError naming the path if one is a folder (or another kind of file that cannot be
    replaced) or if two name the same file."""
    targets: list[str] = []
    for path in paths:
        if path in (None, "", "-"):
            raise OSError(errno.EINVAL, "an empty file name", path)
        target = os.path.realpath(path)
        try:
            st = os.stat(target)
        except OSError:
            st = None
        if st is not None and stat.S_ISDIR(st.st_mode):
            raise OSError(errno.EISDIR, "is a folder: name a file to write (nothing was "
                          "written)", path)
        if st is not None and not stat.S_ISREG(st.st_mode):
            raise OSError(errno.EINVAL, "is not a regular file: a set of outputs is "
                          "replaced whole, so each must be a file (nothing was written)", path)
        if target in targets:
            other = paths[targets.index(target)]
            raise OSError(errno.EINVAL, f"is the same file as {other}: two outputs cannot "
                          "share a name (nothing was written)", path)
        targets.append(target)
    return targets


def _commit(temps: list[str], paths: list[str], targets: list[str]) -> None:
    """Rename every temporary over its target, signals deferred; if a rename fails, the
    targets already replaced get their old content back (kept as hard links)."""
    with _signals_deferred():
        backups: list[tuple[str, str | None]] = []
        try:
            for target in targets:  # the old files, kept until every rename succeeded
                backup = None
                if os.path.lexists(target):
                    backup = target + f".{os.getpid()}.old"
                    with contextlib.suppress(OSError):
                        os.unlink(backup)
                    try:
                        os.link(target, backup)
                    except OSError:
                        backup = None
                backups.append((target, backup))
            done: list[str] = []
            try:
                for tmp, path, target in zip(temps, paths, targets):
                    os.chmod(tmp, _mode_for(target))
                    try:
                        os.replace(tmp, target)
                    except OSError as err:
                        raise _named(err, path) from None
                    done.append(target)
            except BaseException:
                for target in done:  # undo: the set is all or none
                    backup = dict(backups)[target]
                    with contextlib.suppress(OSError):
                        if backup is not None:
                            os.replace(backup, target)
                        else:
                            os.unlink(target)
                raise
            committed.extend(paths)
        finally:
            for _, backup in backups:
                if backup is not None:
                    with contextlib.suppress(OSError):
                        os.unlink(backup)


def _cleanup(temps: list[str]) -> None:
    with _signals_deferred():
        for tmp in temps:
            with contextlib.suppress(OSError):
                os.unlink(tmp)


def _temporary(path: str, target: str, extension: bool) -> str:
    folder = os.path.dirname(target)
    try:
        os.makedirs(folder, exist_ok=True)  # -o out/x.asa makes out/
        fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(target)}.",
                                   suffix=".tmp" + (os.path.splitext(target)[1] if extension
                                                          else ""), dir=folder)
    except OSError as err:  # name the file asked for, not the temporary one
        raise _named(err, path) from None
    os.close(fd)
    return tmp


@contextlib.contextmanager
def atomic_files(paths: list[str], extension: bool = True) -> Iterator[list[str]]:
    """Yield a temporary path for each of ``paths``; rename them all into place only when
    the block ends without an exception (Ctrl-C and signals turned into exceptions
    included), else remove them: several files are replaced all together or not at all.

    The targets are checked (:func:`check_targets`) and the folders created first, so a
    folder in the way or a missing permission fails before any work is done.  An OSError
    in the block without a file name (a full disk) is given the name of the output.
    Each temporary name ends with its target's extension (matplotlib reads the format
    from it) unless ``extension`` is False (then ``.tmp``).
    """
    targets = check_targets(paths)
    temps: list[str] = []
    try:
        for path, target in zip(paths, targets):
            temps.append(_temporary(path, target, extension))
        try:
            yield list(temps)
        except OSError as err:
            if err.filename in (None, *temps):
                name = (paths[temps.index(err.filename)] if err.filename in temps
                        else ", ".join(paths))
                raise _named(err, name) from None
            raise
        _commit(temps, paths, targets)
        temps = []
    finally:
        _cleanup(temps)


@contextlib.contextmanager
def atomic_output(path: str | None, newline: str | None = None) -> Iterator[TextIO]:
    """Yield a stream for ``path`` (stdout if None or "-").

    A file is written to a temporary file in the same directory and renamed
    over ``path`` only when the block ends without an exception, so an
    existing file survives any failure, Ctrl-C included (see the module's policy:
    a symbolic link is followed, a missing folder created, the permissions kept).

    A path that exists and is not a regular file (``/dev/null``, a named pipe, a
    terminal) cannot be replaced and is written in place.
    """
    if path in (None, "-"):
        yield sys.stdout
        sys.stdout.flush()
        return
    try:
        st = os.stat(path)  # follows links: /dev/stdout is the pipe or terminal it names
    except (FileNotFoundError, NotADirectoryError):
        st = None
    if st is not None and not stat.S_ISREG(st.st_mode) and not stat.S_ISDIR(st.st_mode):
        try:
            with open(path, "w", newline=newline, buffering=1 << 16) as stream:
                yield stream
        except OSError as err:
            if err.filename in (None, path):
                raise _named(err, path, in_place=True) from None
            raise
        return
    with atomic_files([path], extension=False) as (tmp,):
        with open(tmp, "w", newline=newline, buffering=1 << 16) as stream:
            yield stream
