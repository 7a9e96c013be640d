"""Blocks written on a thread while the run goes on.

The writer keeps two sets of row buffers: the run fills one while the
previous block goes to the file from the other on this thread (h5py lets
go of the GIL inside HDF5's write, and a second core does the copy into
the page cache).  One block at a time, and HDF5 is called from one thread
at a time: the writer waits for the block before any other HDF5 call (the
next block, the gauges alone, the status at the end).  A block's failure
is raised by that wait; the file then keeps every block before it.
"""

import threading


class BlockThread:
    """At most one write in flight; :meth:`wait` raises its error."""

    def __init__(self):
        self._thread = None
        self._error = None

    def start(self, write):
        """Run ``write()`` on a thread, after the previous one has ended."""
        self.wait()

        def body():
            try:
                write()
            except BaseException as exc:          # raised again by wait()
                self._error = exc
        self._thread = threading.Thread(target=body, name="vstpetsc-block", daemon=True)
        self._thread.start()

    def wait(self):
        """Until the write in flight has ended; its exception, if any."""
        if self._thread is not None:
            self._thread.join()
            self._thread = None
        error, self._error = self._error, None
        if error is not None:
            raise error
