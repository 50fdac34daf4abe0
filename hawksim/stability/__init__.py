"""Stability about a trim: derivatives from disturbed held-body runs (Eq. 15, ``derivatives``), the A matrices
and modes (Eqs. 8-12, ``system``) and the CLI's report (``report``)."""
