"""Progress, one rule for every command: a bar on a terminal, a line per
stage otherwise.

On a terminal (stderr is a TTY) a stage shows tqdm's bar. In a pipe or a
log, bars would write carriage returns nobody sees; a stage then writes a
line when it starts, a line at most every LINE_EVERY_S seconds while it
runs (so that a long batch is never silent), and a line when it ends, with
its count and wall time ("done", or "stopped" when an error or a signal cut
it short). In a Jupyter kernel tqdm's notebook widget is used.
"""

from __future__ import annotations

import sys
import time

LINE_EVERY_S = 30.0


class StageLines:
    """tqdm's small interface (update, close, n, context manager, iteration)
    as plain lines on a stream."""

    def __init__(self, iterable=None, *, total=None, desc: str = "", unit: str = "it", initial=0, file=None):
        self.iterable = iterable
        self.total = len(iterable) if total is None and hasattr(iterable, "__len__") else total
        self.desc, self.unit, self.n = desc or "progress", unit, initial
        self.file = file or sys.stderr
        self._t0 = self._last = time.monotonic()
        self._closed = False
        self._line(f"started, {self._count()}")

    def _count(self) -> str:
        n = f"{self.n:.4g}" if isinstance(self.n, float) else f"{self.n}"
        total = f"{self.total:.4g}" if isinstance(self.total, float) else f"{self.total}"
        return f"{n}/{total} {self.unit}" if self.total is not None else f"{n} {self.unit}"

    def _line(self, what: str) -> None:
        print(f"{self.desc}: {what}", file=self.file, flush=True)

    def update(self, n=1) -> None:
        self.n += n
        now = time.monotonic()
        if now - self._last >= LINE_EVERY_S:
            self._last = now
            self._line(f"{self._count()} after {now - self._t0:.0f} s")

    def set_postfix(self, *args, **kwargs) -> None:
        pass

    def set_postfix_str(self, *args, **kwargs) -> None:
        pass

    def refresh(self) -> None:
        self.update(0)  # a line if one is due (callers that set n themselves)

    def close(self, stopped: bool | None = None) -> None:
        """The stage's last line: "done" when it ended, "stopped" when it was
        cut short (`stopped`; None: when an exception, such as Ctrl-C or
        SIGTERM, is on its way through the caller's ``finally`` and the
        count is short of its total)."""
        if not self._closed:
            self._closed = True
            if stopped is None:
                short = self.total is None or self.n < self.total
                stopped = sys.exc_info()[0] is not None and short
            what = "stopped" if stopped else "done"
            self._line(f"{what}, {self._count()} in {time.monotonic() - self._t0:.1f} s")

    def __iter__(self):
        try:
            for item in self.iterable:
                yield item
                self.update(1)
        except BaseException:  # an error, an interrupt, or the loop left early (GeneratorExit)
            self.close(stopped=True)
            raise
        self.close(stopped=False)

    def __enter__(self) -> StageLines:
        return self

    def __exit__(self, exc_type, *exc) -> None:
        self.close(stopped=exc_type is not None)


def progress_bar(iterable=None, *, enabled: bool = True, file=None, tqdm_class=None, **kwargs):
    """A progress display by the module's rule: tqdm's bar on a terminal (or
    its widget in Jupyter), :class:`StageLines` otherwise, nothing when not
    `enabled`. kwargs: tqdm's (total, desc, unit, initial, ...); the lines
    use total, desc, unit and initial. tqdm_class: a tqdm subclass for the
    bar (e.g. one without a monitor thread, where processes fork).

    Args:
        iterable: what to iterate over with progress, or None for a display
            updated by hand (``update``).
        enabled: whether to show anything (default True); when False, a
            disabled tqdm is returned.
        file: the stream of the bar or the lines; None (the default) for
            ``sys.stderr``. Whether it is a terminal (``isatty``) picks the
            bar or the lines. Not used in Jupyter.
        tqdm_class: the tqdm class of the bar (and of the disabled one);
            None (the default) for ``tqdm.tqdm``. Not used in Jupyter
            (``tqdm.auto``) nor for the lines.
        **kwargs: tqdm's keyword arguments, passed to tqdm; the lines keep
            only ``total``, ``desc``, ``unit`` and ``initial``.

    Returns:
        A tqdm (disabled, ``tqdm.auto``'s in a Jupyter kernel, or a bar on
        `file`) or a :class:`StageLines` on `file`, used alike: iterate it,
        ``update`` it, ``close`` it or use it as a context manager.
    """
    stream = file or sys.stderr
    if not enabled:
        from tqdm import tqdm

        return (tqdm_class or tqdm)(iterable, disable=True, **kwargs)
    if "ipykernel" in sys.modules:
        from tqdm.auto import tqdm

        return tqdm(iterable, **kwargs)
    if getattr(stream, "isatty", lambda: False)():
        from tqdm import tqdm

        return (tqdm_class or tqdm)(iterable, file=stream, **kwargs)
    keep = {k: kwargs[k] for k in ("total", "desc", "unit", "initial") if k in kwargs}
    return StageLines(iterable, file=stream, **keep)
