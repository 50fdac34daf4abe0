"""Free flight of the hawkmoth in MuJoCo: the flight loop (``simulator``), the start on the trim's periodic path
(``start``), ``fly`` and its result (``fly``, ``result``), and Rerun recordings (``recording``)."""
