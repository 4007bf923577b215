"""Output files that are written whole or not at all."""

from __future__ import annotations

import contextlib
import os
import stat
import sys
import tempfile
from collections.abc import Iterator
from typing import TextIO


def _cannot_write(path: str, err: OSError) -> str:
    """Why an output cannot be written, in words that fit the case."""
    folder = os.path.dirname(os.path.abspath(path))
    if os.path.isdir(folder):  # the folder is there: it takes no new file (/proc, read-only)
        return f"cannot write (no new file can be made in {folder}: {err.strerror})"
    return f"cannot write ({err.strerror})"


def _mode_for(path: str) -> int:
    """The permissions a replacement of ``path`` gets: the old file's, or 0666 less the
    umask for a new one."""
    try:
        return stat.S_IMODE(os.stat(path).st_mode)
    except OSError:
        umask = os.umask(0o022)
        os.umask(umask)
        return 0o666 & ~umask


@contextlib.contextmanager
def atomic_output(path: str | None, newline: str | None = None) -> Iterator[TextIO]:
    """Yield a stream for ``path`` (stdout if None or "-").

    A file is written to a temporary file in the same directory and renamed
    over ``path`` only when the block ends without an exception, so an
    existing file survives any failure, Ctrl-C included.  The new file gets
    the old file's permissions (a new one: 0666 less the umask), and a
    symbolic link is followed, so the file it points to is the one replaced.
    A missing folder on the way is created.

    A path that exists and is not a regular file (``/dev/null``, a named
    pipe, a terminal) cannot be replaced and is written in place.
    """
    if path in (None, "-"):
        yield sys.stdout
        sys.stdout.flush()
        return
    try:
        st = os.stat(path)  # follows links: /dev/stdout is the pipe or terminal it names
    except (FileNotFoundError, NotADirectoryError):
        st = None
    if st is not None and not stat.S_ISREG(st.st_mode):
        with open(path, "w", newline=newline, buffering=1 << 16) as stream:
            yield stream
        return
    target = os.path.realpath(path)
    mode = _mode_for(path)
    try:
        os.makedirs(os.path.dirname(target), exist_ok=True)  # -o out/x.asa makes out/
        fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(target)}.", suffix=".tmp",
                                   dir=os.path.dirname(target))
    except OSError as err:  # name the file asked for, not the temporary one
        raise OSError(err.errno, _cannot_write(target, err), path) from None
    try:
        with os.fdopen(fd, "w", newline=newline, buffering=1 << 16) as stream:
            os.fchmod(stream.fileno(), mode)
            yield stream
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


@contextlib.contextmanager
def atomic_files(paths: list[str]) -> Iterator[list[str]]:
    """Yield a temporary path for each of ``paths``; rename them all into place only when
    the block ends without an exception (Ctrl-C and signals turned into exceptions
    included), else remove them: several files are replaced all together or not at all.

    The folders are created first, so a missing folder fails before any work is done.
    The renames come last, one after the other, each atomic.
    """
    temps: list[str] = []
    try:
        for path in paths:
            folder = os.path.dirname(os.path.abspath(path))
            try:
                os.makedirs(folder, exist_ok=True)
                fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(path)}.",
                                           suffix=".tmp" + os.path.splitext(path)[1],
                                           dir=folder)
            except OSError as err:
                raise OSError(err.errno, _cannot_write(path, err), path) from None
            os.close(fd)
            temps.append(tmp)
        yield list(temps)
        for tmp, path in zip(list(temps), paths):
            os.chmod(tmp, _mode_for(path))
            os.replace(tmp, path)
            temps.remove(tmp)
    finally:
        for tmp in temps:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
