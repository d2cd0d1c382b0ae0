"""The command line, ``fastline <command>``: built on fastline's public API alone.

:mod:`~fastline.cli.app` holds the parser, the cylinder's ``profile``, ``sweep``, ``batch`` and
``paper`` commands and :func:`main`; :mod:`~fastline.cli.common` the option groups and
printing shared by every command; ``leak``, ``psd``, ``validate`` and ``--geometry sphere`` have
a module each."""

from fastline.cli.app import main

__all__ = ["main"]
