"""The one progress bar of the command line (tqdm on stderr; off when stderr is not a terminal or with
``--no-progress``)."""

from __future__ import annotations

import sys
import weakref

_OPEN: weakref.WeakSet = weakref.WeakSet()


class Progress:
    """A callable ``progress(done, total, **postfix)`` for the library's progress hooks.

    The bar opens on the first call (so a resumed job starts at its ``done``), shows ``postfix`` (name -> text; at
    once when ``done`` did not change, so a long step can say what it is doing), and closes when ``done == total``
    or on :meth:`close`.
    """

    def __init__(self, desc: str, unit: str = "step", mininterval: float = 0.5, smoothing: float = 0.3):
        self.desc, self.unit, self.mininterval, self.smoothing = desc, unit, mininterval, smoothing
        self.bar = None

    def __call__(self, done: int, total: int, **postfix) -> None:
        if self.bar is None:
            from tqdm import tqdm

            self.bar = tqdm(total=total, initial=done, desc=self.desc, unit=self.unit, file=sys.stderr, disable=None,
                            mininterval=self.mininterval, smoothing=self.smoothing)
            _OPEN.add(self)
        moved = done - self.bar.n
        if postfix:  # shown at once when the count stays (a note of the stage in progress)
            self.bar.set_postfix(postfix, refresh=moved == 0)
        self.bar.update(moved)
        if done == total:
            self.close()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
        _OPEN.discard(self)


def close_all() -> None:
    """Close the bars still open (before an error message, so that it starts a line of its own on a terminal)."""
    for bar in list(_OPEN):
        bar.close()


def progress_for(args, desc: str, unit: str = "step", **kw) -> Progress | None:
    """The bar of a subcommand, or None with ``--no-progress``."""
    return None if getattr(args, "no_progress", False) else Progress(desc, unit, **kw)


class Stage:
    """A bar for a stage with no step count (an orbit solve, the controller's start-up, writing a file): its name,
    the seconds elapsed (redrawn twice a second by a daemon thread, so that a long silent computation shows that
    it runs) and the last note (``stage.note(text)``, e.g. a library ``log`` line). A context manager; like
    :class:`Progress`, drawn on a terminal's stderr only."""

    def __init__(self, desc: str, interval: float = 0.5):
        self.desc, self.interval = desc, interval
        self.bar = None
        self._stop = None

    def __enter__(self) -> Stage:
        import threading

        from tqdm import tqdm

        self.bar = tqdm(total=None, desc=self.desc, file=sys.stderr, disable=None,
                        bar_format="{desc}: {elapsed}{postfix}")
        _OPEN.add(self)
        if not self.bar.disable:
            self._stop = threading.Event()
            threading.Thread(target=self._tick, daemon=True).start()
        return self

    def _tick(self) -> None:
        while not self._stop.wait(self.interval):
            try:
                self.bar.refresh()
            except Exception:  # the bar closed under us: stop quietly
                return

    def note(self, text: str) -> None:
        """Show ``text`` after the elapsed time (the stage's last news)."""
        if self.bar is not None:
            self.bar.set_postfix_str(str(text)[:80], refresh=True)

    def close(self) -> None:
        if self._stop is not None:
            self._stop.set()
        if self.bar is not None:
            self.bar.close()
            self.bar = None
        _OPEN.discard(self)

    def __exit__(self, *exc) -> None:
        self.close()


class NoStage:
    """The silent stand-in of a :class:`Stage` (``--no-progress``, or a caller that gives none); it takes and ignores
    a description, so that the class itself can stand for ``Stage``."""

    def __init__(self, desc: str = ""):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        pass

    def note(self, text: str) -> None:
        pass

    def close(self) -> None:
        pass


def stage_for(args, desc: str):
    """A :class:`Stage` for a subcommand, or a silent stand-in with ``--no-progress``."""
    return NoStage() if getattr(args, "no_progress", False) else Stage(desc)
