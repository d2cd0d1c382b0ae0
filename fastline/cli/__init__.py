"""The command line, ``fastline <command>``: built on fastline's public API alone.

Its modules import one another downwards only: :mod:`~fastline.cli.common` (option types and
groups, outputs, printing, sweeps on executors) at the bottom; :mod:`~fastline.cli.scene` (the
scene of the options: spectrum, material, measured surfaces) on it; the command modules
``leak``, ``psd``, ``sphere`` (``--geometry sphere``) and ``validate`` above; and
:mod:`~fastline.cli.app` on top, with the parser, the cylinder's ``profile``, ``sweep``,
``batch`` and ``paper`` and :func:`main`."""

from fastline.cli.app import main

__all__ = ["main"]
