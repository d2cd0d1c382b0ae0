"""Where fastline's warnings point: at the first frame outside the package (the user's line)."""

from __future__ import annotations

import os
import sys

__all__ = ["outside_stacklevel"]

#: the package's directory: frames there are fastline's own
_PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep


def outside_stacklevel() -> int:
    """The ``stacklevel`` that makes a warning emitted by the caller of this function point at
    the first frame outside fastline: the user's line, however many of fastline's functions lie
    between (``solve_line_contact`` -> ``LineContact.solve`` -> ..., ``analyse_scan`` -> a
    reader -> ...). Python 3.12's ``skip_file_prefixes`` does this in ``warnings.warn``;
    fastline supports 3.10."""
    frame = sys._getframe(1)
    level = 1
    while frame is not None and frame.f_code.co_filename.startswith(_PACKAGE_DIR):
        frame = frame.f_back
        level += 1
    return level
