"""Blocks written on a thread while the run goes on.

The writer keeps two sets of row buffers: the run fills one while the
previous block goes to the file from the other on this thread (h5py lets
go of the GIL inside HDF5's write, and a second core does the copy into
the page cache).  One block at a time, and HDF5 is called from one thread
at a time: the writer waits for the block before any other HDF5 call (the
next block, the gauges alone, the status at the end).  A block's failure
is raised by that wait; the file then keeps every block before it.
"""

import queue
import threading


class BlockThread:
    """At most one write in flight, on one thread kept for the run (a new
    thread a block cost ~0.3 ms of the run's time to start, about 3 us a
    slab at 10 000 nodes); :meth:`wait` raises its error, :meth:`stop`
    ends the thread."""

    def __init__(self):
        self._thread = None
        self._jobs = queue.SimpleQueue()
        self._idle = threading.Event()
        self._idle.set()
        self._error = None

    def start(self, write):
        """Run ``write()`` on the thread, after the previous one has ended."""
        self.wait()
        if self._thread is None:
            self._thread = threading.Thread(target=self._serve, name="vstpetsc-block",
                                            daemon=True)
            self._thread.start()
        self._idle.clear()
        self._jobs.put(write)

    def _serve(self):
        while True:
            write = self._jobs.get()
            if write is None:
                return
            try:
                write()
            except BaseException as exc:          # raised again by wait()
                self._error = exc
            finally:
                self._idle.set()

    def wait(self):
        """Until the write in flight has ended; its exception, if any."""
        self._idle.wait()
        error, self._error = self._error, None
        if error is not None:
            raise error

    def stop(self):
        """End the thread (after the write in flight; its error is left
        to :meth:`wait`)."""
        if self._thread is not None:
            self._jobs.put(None)
            self._thread.join()
            self._thread = None
