"""`python -m hawksim.cli`: the hawksim command."""

import sys

from hawksim.cli import main

sys.exit(main())
