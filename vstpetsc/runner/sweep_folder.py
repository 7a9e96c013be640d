"""The folder of a sweep: checked on every rank before anything is made,
then made and held by one sweep at a time (docs/sweeps.md).

A sweep holds its folder by an exclusive ``flock`` on ``folder/.sweep.lock``;
the lock dies with the process, so a killed sweep leaves at most the file,
which the next sweep takes over.  A second sweep into the folder would
take the runs' files from under the first and call its completed runs
failed, so it is refused.

The sweep removes the file when it ends (left behind, it looked like a
sweep still at work), while it still holds the lock.  A sweep that
opened the file just before that locks a file no longer in the folder
once the lock is dropped; so a sweep, once it has the lock, checks that
the file it locked is the one the folder holds, and takes the new one if
not.
"""

import contextlib
import fcntl
import os

from vstpetsc.errors import InputError

LOCK = ".sweep.lock"     # held by the sweep writing into a folder


def check(folder):
    """InputError if ``folder`` cannot be a sweep's folder, decided on every
    rank alike before anything is made."""
    if any(not c.isprintable() for c in str(folder)):
        raise InputError("-o: the path contains a control character")
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise InputError(f"-o {folder}: exists and is not a folder")


def take(folder):
    """Make ``folder`` and hold it for this sweep: the descriptor holding
    the lock (give it to :func:`release`); InputError if another sweep
    holds it or the folder cannot be written."""
    path = os.path.join(folder, LOCK)
    while True:
        fd = _open(folder, path)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            raise InputError(f"-o {folder}: the folder is being used by another sweep; "
                             "nothing was changed") from None
        if _in_folder(fd, path):
            return fd
        os.close(fd)        # a sweep that ended removed it after we opened it


def release(folder, fd):
    """Remove the lock file, then drop the lock (in this order: see the
    module).  A folder removed meanwhile is no error."""
    with contextlib.suppress(OSError):
        os.unlink(os.path.join(folder, LOCK))
    os.close(fd)


def _open(folder, path):
    try:
        os.makedirs(folder, exist_ok=True)
        return os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as exc:
        raise InputError(f"-o {folder}: cannot write there ({exc.strerror})") from None


def _in_folder(fd, path):
    """Whether ``path`` names the file open as ``fd``."""
    try:
        named = os.stat(path)
    except FileNotFoundError:
        return False
    held = os.fstat(fd)
    return (named.st_dev, named.st_ino) == (held.st_dev, held.st_ino)
