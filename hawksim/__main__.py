"""`python -m hawksim`: the hawksim command."""

import sys

from hawksim.cli import main

sys.exit(main())
