"""Output files that are written whole or not at all."""

from __future__ import annotations

import contextlib
import os
import stat
import sys
import tempfile
from collections.abc import Iterator
from typing import TextIO


@contextlib.contextmanager
def atomic_output(path: str | None, newline: str | None = None) -> Iterator[TextIO]:
    """Yield a stream for ``path`` (stdout if None or "-").

    A file is written to a temporary file in the same directory and renamed
    over ``path`` only when the block ends without an exception, so an
    existing file survives any failure, Ctrl-C included.  The new file gets
    the old file's permissions (a new one: 0666 less the umask), and a
    symbolic link is followed, so the file it points to is the one replaced.

    A path that exists and is not a regular file (``/dev/null``, a named
    pipe, a terminal) cannot be replaced and is written in place.
    """
    if path in (None, "-"):
        yield sys.stdout
        sys.stdout.flush()
        return
    try:
        st = os.stat(path)  # follows links: /dev/stdout is the pipe or terminal it names
    except FileNotFoundError:
        st = None
    if st is not None and not stat.S_ISREG(st.st_mode):
        with open(path, "w", newline=newline, buffering=1 << 16) as stream:
            yield stream
        return
    target = os.path.realpath(path)
    if st is not None:
        mode = stat.S_IMODE(st.st_mode)
    else:
        umask = os.umask(0o022)
        os.umask(umask)
        mode = 0o666 & ~umask
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(target)}.", suffix=".tmp",
                                   dir=os.path.dirname(target))
    except OSError as err:  # name the file asked for, not the temporary one
        raise OSError(err.errno, f"cannot write ({err.strerror})", path) from None
    try:
        with os.fdopen(fd, "w", newline=newline, buffering=1 << 16) as stream:
            os.fchmod(stream.fileno(), mode)
            yield stream
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
