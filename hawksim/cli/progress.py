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
