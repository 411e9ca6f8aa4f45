"""Progress a person sees: a tqdm bar over features on stderr, kept alive while one feature is slow.

The exact engine runs one feature in a single call that may take seconds or minutes (a 75k-vertex
outline). A bar that only moves between features looks hung meanwhile, so a small daemon thread redraws
it every `TICK` seconds with the feature at work, its vertex count and how long it has taken so far.
"""

from __future__ import annotations

import sys
import threading
import time

__all__ = ["FeatureBar"]

#: Seconds between redraws while one feature is being worked on.
TICK = 0.5
#: A feature shows in the bar's postfix once it has taken this long (seconds).
SLOW = 1.0


class FeatureBar:
    """A progress bar over ``total`` features; does nothing when ``enabled`` is False.

    Parameters
    ----------
    total : int
        Number of features.
    enabled : bool
        Draw it (on stderr). Callers decide: on when stderr is a terminal, off with ``--quiet``.
    desc : str
        Its label.
    unit : str
        What it counts.
    stream : file, optional
        Where to draw (default ``sys.stderr``).

    Examples
    --------
    >>> with FeatureBar(3, enabled=False) as bar:
    ...     for i in range(3):
    ...         bar.start(i, 10)
    ...         bar.advance()
    >>> bar.done
    3
    """

    def __init__(self, total: int, *, enabled: bool, desc: str = "tightening", unit: str = "feature",
                 stream=None):
        self.total, self.done, self.enabled = total, 0, enabled
        self._bar = None
        self._current: tuple[str, int, float] | None = None
        self._stop = threading.Event()
        self._thread = None
        if enabled:
            from tqdm import tqdm

            self._bar = tqdm(total=total, desc=desc, unit=unit, file=stream or sys.stderr,
                             dynamic_ncols=True, mininterval=0.2, leave=True)
            self._thread = threading.Thread(target=self._tick, name="vectortighten-progress", daemon=True)
            self._thread.start()

    def _tick(self) -> None:
        while not self._stop.wait(TICK):
            current = self._current
            if current is None or self._bar is None:
                continue
            label, vertices, since = current
            took = time.monotonic() - since
            if took >= SLOW:
                self._bar.set_postfix_str(f"{label}: {vertices} vertices, {took:.0f} s", refresh=True)

    def start(self, label, vertices: int) -> None:
        """Say that feature ``label`` (``vertices`` vertices) is being worked on now."""
        self._current = (f"feature {label}" if not isinstance(label, str) else label, int(vertices),
                         time.monotonic())

    def advance(self, n: int = 1) -> None:
        """Count ``n`` more features done."""
        self.done += n
        self._current = None
        if self._bar is not None:
            if self._bar.postfix:
                self._bar.set_postfix_str("", refresh=False)
            self._bar.update(n)

    def close(self) -> None:
        """Stop the redraws and leave the finished bar on its line."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
        if self._bar is not None:
            self._bar.close()

    def __enter__(self) -> FeatureBar:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
