"""``python -m fastline``: the command-line interface (see :mod:`fastline.cli`)."""

import sys

from fastline.cli import main

sys.exit(main())
