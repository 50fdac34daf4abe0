"""The suite's caches live in a temporary directory, never in the user's home (tests/conftest.py; issue 52)."""

import os
from pathlib import Path

from aero.numba_cache import default_cache_dir
from hawksim.control.cache import cache_dir


def test_caches_point_away_from_the_users_home():
    home_cache = Path.home() / ".cache"
    for d in (default_cache_dir(), cache_dir(), Path(os.environ["MPLCONFIGDIR"])):
        assert not d.is_relative_to(home_cache), d
        assert d.is_relative_to(Path(os.environ["XDG_CACHE_HOME"])), d
