"""`hawksim reproduce` (see :mod:`hawksim.reproduce`)."""

from hawksim.reproduce import register  # noqa: F401
