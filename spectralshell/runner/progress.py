"""Progress of long work on stderr: a tqdm bar (rate, ETA) on a terminal, and when stderr is
not a terminal (piped to a file, a CI log) one plain line every :data:`PIPE_SECONDS`, so that
a log shows the work moving without a bar's carriage returns. The lines come from a clock, not
only from finished items, so that work spending minutes on one item (one large truncation of a
``floquet cochlea`` solve) is not silent (issue 23, section 4). Work shorter than
PIPE_SECONDS prints nothing when piped."""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Iterable, Iterator
from typing import Any, TypeVar

T = TypeVar("T")

#: Seconds between the progress lines written to a piped stderr.
PIPE_SECONDS = 15.0


def _duration(seconds: float) -> str:
    """'42s', '3m05s' or '1h02m'."""
    seconds = int(round(seconds))
    if seconds < 60:
        return f"{seconds}s"
    if seconds < 3600:
        return f"{seconds // 60}m{seconds % 60:02d}s"
    return f"{seconds // 3600}h{seconds % 3600 // 60:02d}m"


class LineProgress:
    """The progress of ``total`` items (``unit``) as a line on stderr every
    :data:`PIPE_SECONDS`: 'sweep: 120/960 pt (12%), 3.4 pt/s, 35s elapsed, ETA 4m07s'. A daemon
    thread writes the line when no update did for PIPE_SECONDS (none while PIPE_SECONDS is 0:
    then every update writes one), until :meth:`close`. Offers the part of tqdm's interface the
    runners use (update, set_description, set_postfix_str, close, with)."""

    def __init__(self, total: int | None, desc: str, unit: str):
        self.total, self.desc, self.unit = total, desc, unit
        self.n, self.postfix = 0, ""
        self._start = self._last = time.monotonic()
        self._lock = threading.Lock()
        self._closed = threading.Event()
        if PIPE_SECONDS > 0:
            threading.Thread(target=self._clock, args=(PIPE_SECONDS,), daemon=True,
                             name="progress-lines").start()

    def update(self, count: int = 1) -> None:
        """Count ``count`` more finished items; write a line if PIPE_SECONDS have passed."""
        with self._lock:
            self.n += count
        self._write_if_due()

    def _write_if_due(self) -> float:
        """Write the line if PIPE_SECONDS have passed since the last; the seconds until the
        next is due."""
        with self._lock:
            now = time.monotonic()
            wait = PIPE_SECONDS - (now - self._last)
            if wait > 0:
                return wait
            self._last = now
            text = self.line(now - self._start)
        print(text, file=sys.stderr, flush=True)
        return PIPE_SECONDS

    def _clock(self, period: float) -> None:
        """The thread's loop: a line whenever ``period`` passed without one, until closed."""
        wait = period
        while not self._closed.wait(max(wait, 1e-3)):
            wait = self._write_if_due()

    def line(self, elapsed: float) -> str:
        """The progress line after ``elapsed`` seconds."""
        rate = self.n / elapsed if elapsed > 0 else 0.0
        done = f"{self.n}/{self.total}" if self.total else f"{self.n}"
        share = f" ({100 * self.n / self.total:.0f}%)" if self.total else ""
        eta = (f", ETA {_duration((self.total - self.n) / rate)}"
               if self.total and rate > 0 else "")
        postfix = f" ({self.postfix})" if self.postfix else ""
        return (f"{self.desc}: {done} {self.unit}{share}, {rate:.3g} {self.unit}/s, "
                f"{_duration(elapsed)} elapsed{eta}{postfix}")

    def set_description(self, desc: str) -> None:
        self.desc = desc

    def set_postfix_str(self, text: str) -> None:
        """Text shown at the end of the next lines (e.g. 'M = 64')."""
        self.postfix = text

    def close(self) -> None:
        """Stop the lines (those written stay in the log)."""
        self._closed.set()

    def __enter__(self) -> LineProgress:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


def progress_bar(total: int | None, desc: str, unit: str, enabled: bool, **options: Any):
    """A progress reporter for ``total`` items: a tqdm bar on a terminal (``options`` go to
    tqdm), a :class:`LineProgress` when stderr is not one, a disabled tqdm when not
    ``enabled``."""
    if enabled and not sys.stderr.isatty():
        return LineProgress(total, desc, unit)
    from tqdm import tqdm  # lazy: ~30 ms to import

    return tqdm(total=total, desc=desc, unit=unit, disable=not enabled, file=sys.stderr,
                dynamic_ncols=True, **options)


def tracked(items: Iterable[T], desc: str, unit: str, enabled: bool) -> Iterator[T]:
    """The ``items``, reporting the progress through them (:func:`progress_bar`)."""
    items = list(items)
    with progress_bar(len(items), desc, unit, enabled) as bar:
        for item in items:
            yield item
            bar.update()
