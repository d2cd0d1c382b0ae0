"""``python -m fastline``: the command-line interface (see :mod:`fastline.cli.app`)."""

import sys

from fastline.cli.app import main

sys.exit(main())
