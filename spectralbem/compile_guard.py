"""Ctrl-C and SIGTERM held back while numba compiles or loads a kernel.

numba's compiler is Python code running in the main thread, so a KeyboardInterrupt (or the
command line's SIGTERM exception) can land in the middle of it: the kernel's library is
left registered but not finished, and the next call of that kernel fails ("no compiled
object yet for <Library ...>", on the first solve of a fresh checkout, where the kernels
are compiled; a segmentation fault seen once at that point is likely of the same cause).
While the global compiler lock is held by the main thread, these signals are recorded
instead; when the outermost compilation ends, the handlers are restored and each recorded
signal is raised again, so that it reaches the command (a load path keeps its finished
steps, ``spectralbem run`` exits 130) with the kernel whole.  Signals whose handler is not
a Python function (ignored, or the default action) are left alone.  Installed by
:mod:`spectralbem.kernels` when numba is used.
"""

from __future__ import annotations

import signal
import threading

#: the signals held back during a compilation
HELD = (signal.SIGINT, signal.SIGTERM)


class _Held:
    """A listener of numba's ``numba:compiler_lock`` events (nested: counted); numba's
    ``event.Listener`` dispatches them (:func:`install`)."""

    def __init__(self):
        self.depth = 0
        self.saved = {}  # signal -> the handler it had before the outermost compilation
        self.pending = []  # signals received meanwhile, in order

    def _record(self, signum, frame):
        self.pending.append(signum)

    def on_start(self, event) -> None:
        if threading.current_thread() is not threading.main_thread():
            return
        self.depth += 1
        if self.depth > 1:
            return
        for sig in HELD:
            old = signal.getsignal(sig)
            if callable(old):
                self.saved[sig] = old
                signal.signal(sig, self._record)

    def on_end(self, event) -> None:
        if threading.current_thread() is not threading.main_thread() or self.depth == 0:
            return
        self.depth -= 1
        if self.depth:
            return
        saved, self.saved = self.saved, {}
        pending, self.pending = self.pending, []
        for sig, old in saved.items():
            signal.signal(sig, old)
        for sig in dict.fromkeys(pending):  # each signal once, in the order received
            signal.raise_signal(sig)


_LISTENER = None


def install() -> None:
    """Register the guard with numba's events (once per process)."""
    global _LISTENER
    if _LISTENER is not None:
        return
    from numba.core import event

    class Listener(_Held, event.Listener):
        pass

    _LISTENER = Listener()
    event.register("numba:compiler_lock", _LISTENER)
