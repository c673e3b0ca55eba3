"""Progress display of long work (solves, paths, sweeps): a tqdm bar on a terminal or in a
notebook, plain lines elsewhere (a log file, a pipe, a batch job), where a bar's carriage
returns and cursor escapes would end up in the log."""

from __future__ import annotations

__all__ = ["progress_bar", "LOG_INTERVAL"]

#: seconds between two progress lines when stderr is not a terminal (:func:`progress_bar`)
LOG_INTERVAL = 10.0


def _terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):  # no isatty, or a closed stream
        return False


class _LineProgress:
    """The progress of :func:`progress_bar` on a stderr that is not a terminal (a log file,
    a pipe): plain lines ``desc: n/total unit, text (t s)``, the first at the first count
    after a start or reset, then at most one per :data:`LOG_INTERVAL` seconds and the last
    count of a known total; no carriage returns or escape codes.  The part of tqdm's
    interface the package uses."""

    def __init__(self, iterable=None, desc: str = "", total=None, initial: int = 0,
                 unit: str = "it", **_):
        import sys
        import time

        if total is None and iterable is not None and hasattr(iterable, "__len__"):
            total = len(iterable)
        self.iterable, self.desc, self.total, self.unit = iterable, desc, total, unit
        self.n, self.postfix, self.file = initial, "", sys.stderr
        self._clock, self._start, self._last, self._shown = (time.monotonic, time.monotonic(),
                                                             None, None)

    def __iter__(self):
        for x in self.iterable:
            yield x
            self.update(1)

    def set_postfix_str(self, text: str = "", refresh: bool = True) -> None:
        self.postfix = str(text)

    def update(self, n: int = 1) -> None:
        self.n += n
        self.refresh()

    def refresh(self) -> None:
        now = self._clock()
        done = (self.total is not None and self.n >= self.total
                and (self.n, self.postfix) != self._shown)
        if self._last is not None and now - self._last < LOG_INTERVAL and not done:
            return
        self._line(now)

    def _line(self, now: float) -> None:
        self._last, self._shown = now, (self.n, self.postfix)
        count = f"{self.n}/{self.total}" if self.total else f"{self.n}"
        text = f", {self.postfix}" if self.postfix else ""
        try:
            print(f"{self.desc}: {count} {self.unit}{text} ({now - self._start:.0f} s)",
                  file=self.file, flush=True)
        except (OSError, ValueError):  # a closed or broken stream: progress is optional
            pass

    def reset(self, total=None) -> None:
        """A new count (the next state of a path): the last one's final line first."""
        self.close()
        self.n, self.postfix, self._last, self._shown = 0, "", None, None
        if total is not None:
            self.total = total

    def close(self) -> None:
        """The final count and text, unless the last line showed them."""
        if self._last is not None and (self.n, self.postfix) != self._shown:
            self._line(self._clock())


def progress_bar(iterable=None, **kw):
    """A tqdm progress bar on a terminal (and in a Jupyter notebook); where stderr is not one
    (a log, a pipe, a batch job) plain progress lines at most every :data:`LOG_INTERVAL`
    seconds instead, without the carriage returns and cursor escapes a bar writes
    (:class:`_LineProgress`).
    Keywords: tqdm's (``desc``, ``total``, ``initial``, ``unit``, ``position``, ``leave``)."""
    import sys

    if _terminal(sys.stderr):
        from tqdm import tqdm

        return tqdm(iterable, **kw)
    if "ipykernel" in sys.modules:  # a notebook: its widget bar (stderr is no terminal there)
        from tqdm.auto import tqdm

        return tqdm(iterable, **kw)
    return _LineProgress(iterable, **kw)
