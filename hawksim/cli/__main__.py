"""`python -m hawksim.cli`: the hawksim command."""

import sys

from hawksim.__main__ import run

sys.exit(run())
