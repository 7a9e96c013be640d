"""The result file on disk: who may write it, and when it gets its name.

- A run holds an exclusive ``flock`` on its result file from before the
  first byte is written until it ends; a second run on the same file (new
  or ``--restart``) finds the lock and stops with one line, before it has
  touched anything.  The lock dies with the process (also on SIGKILL).
- A new file is written beside the target under a hidden temporary name
  and renamed into place once its header and first row are flushed: from
  the moment it has its final name it is a valid result file.  The check
  "nobody holds the old file" and the rename happen under a short lock on
  the folder, so two runs started together cannot both pass it.
- HDF5's own file locking is off for our files (h5py ``locking=False``): it
  would clash with our lock, and readers (``info``, ``plot``, ``Result``)
  must not block a run.
- Disk space is reserved (``posix_fallocate``) before HDF5 writes anything:
  HDF5 1.10 cannot survive a failed write (its file then crashes the
  process when it is closed), so a full disk must show up as a failed
  reservation, while the file is still intact.  The reserved tail beyond
  HDF5's end of allocation is cut off when the file is closed.
"""

import errno
import fcntl
import os
import time

from vstpetsc.errors import InputError

FOLDER_WAIT = 10.0      # seconds to wait for another run's short folder lock


def path_problem(path):
    """Why ``path`` cannot name a result file (None if it can)."""
    if any(not c.isprintable() for c in str(path)):
        return "the path contains a control character"
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        return f"folder {folder} does not exist"
    if os.path.isdir(path):
        return f"{path} is a folder"
    if not os.access(folder, os.W_OK) or (os.path.exists(path) and
                                           not os.access(path, os.W_OK)):
        return f"cannot write {path}"
    return None


def foreign(path):
    """Whether ``path`` is an existing file that is not a vstpetsc result
    (a run must not overwrite it)."""
    if not os.path.exists(path):
        return False
    from vstpetsc.results.hdf5 import open_to_read
    try:
        with open_to_read(path) as f:
            return "case" not in f.attrs or "solver" not in f
    except (OSError, ValueError):
        return True


def same_file(a, b):
    """Whether paths ``a`` and ``b`` name the same existing file."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


class OutputLock:
    """The exclusive lock of a run on its result file (see the module)."""

    def __init__(self, path):
        self.path = os.path.abspath(path)
        self.folder = os.path.dirname(self.path)
        self.fd = None
        self.temp = None

    def _try_lock(self, fd):
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return True
        except OSError as exc:
            if exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                return False
            raise

    def _busy(self):
        return InputError(f"output: {self.path} is being written by another run "
                          "(or held open by another program); nothing was changed")

    def _folder_lock(self):
        """A short exclusive lock on the folder (flock on its descriptor)."""
        fd = os.open(self.folder, os.O_RDONLY)
        deadline = time.monotonic() + FOLDER_WAIT
        while not self._try_lock(fd):
            if time.monotonic() > deadline:
                os.close(fd)
                raise self._busy()
            time.sleep(0.01)
        return fd

    def _free(self):
        """Raise if a live process holds the current file at ``path``."""
        try:
            fd = os.open(self.path, os.O_RDONLY)
        except FileNotFoundError:
            return
        try:
            if not self._try_lock(fd):
                raise self._busy()
        finally:
            os.close(fd)

    def new(self):
        """A temporary path beside the target for a new file; call
        :meth:`publish` once it is valid."""
        self._free()
        self._clean_stale()
        name = os.path.basename(self.path)
        self.temp = os.path.join(self.folder, f".{name}.{os.getpid()}.partial")
        return self.temp

    def publish(self, fd):
        """Lock the temporary file (open as ``fd``, which the lock keeps
        once published) and give it the final name, if nobody took the
        target meanwhile."""
        self._try_lock(fd)
        folder = self._folder_lock()
        try:
            self._free()
            os.replace(self.temp, self.path)
        finally:
            os.close(folder)
        self.fd, self.temp = fd, None

    def existing(self):
        """Lock an existing file to append to it (a restart)."""
        fd = os.open(self.path, os.O_RDWR)
        if not self._try_lock(fd):
            os.close(fd)
            raise self._busy()
        self.fd = fd

    def release(self):
        """Drop the lock; remove a temporary file that was never published."""
        if self.temp is not None:
            try:
                os.unlink(self.temp)
            except OSError:
                pass
            self.temp = None
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None

    def _clean_stale(self):
        """Remove temporary files of runs killed before they published."""
        prefix = f".{os.path.basename(self.path)}."
        # a listing, not glob: glob compiles a pattern per file name (~0.3 ms a run)
        for entry in os.listdir(self.folder):
            if not (entry.startswith(prefix) and entry.endswith(".partial")):
                continue
            pid = entry.rsplit(".", 2)[-2]
            if pid.isdigit() and not _alive(int(pid)):
                try:
                    os.unlink(os.path.join(self.folder, entry))
                except OSError:
                    pass


class DiskFull(OSError):
    """Not enough disk space for the next block of the result file."""


class DiskReserve:
    """Disk blocks reserved ahead of HDF5's writes to the file open as
    ``fd``; falls back to a free-space check where the file system cannot
    reserve."""

    def __init__(self, fd):
        self.fd, self.can_reserve = fd, True

    def ensure(self, end, nbytes):
        """Make sure ``nbytes`` past offset ``end`` (HDF5's end of
        allocation) can be written; DiskFull otherwise."""
        if self.can_reserve:
            try:
                os.posix_fallocate(self.fd, end, nbytes)
                return
            except OSError as exc:
                if exc.errno in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG):
                    raise DiskFull(exc.errno, f"no space for {nbytes / 2**20:.1f} MB more "
                                   f"({os.strerror(exc.errno)})") from None
                self.can_reserve = False       # e.g. EOPNOTSUPP: check instead
        st = os.fstatvfs(self.fd)
        if st.f_bavail * st.f_frsize < nbytes:
            raise DiskFull(errno.ENOSPC, f"no space for {nbytes / 2**20:.1f} MB more "
                           f"({st.f_bavail * st.f_frsize / 2**20:.1f} MB free)")


def held(path):
    """Whether a live process holds the lock of the result file ``path``."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return False
    except OSError:
        return True
    finally:
        os.close(fd)


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True
