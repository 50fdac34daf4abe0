"""Trims, the operating points: the one :class:`Trim` type (``point``), the paper's fitness and the GA + Nelder-Mead
search on a surrogate (Eq. 3, ``search``), the balance on the UVLM or the quasi-steady model (``balance``) and the
shipped tables (``tables``)."""

from hawksim.trim.point import Trim

__all__ = ["Trim"]
