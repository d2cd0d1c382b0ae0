"""Reading text tables and spectrum files: :func:`read_table`, :func:`parse_table` and
:func:`read_spectrum` of :mod:`fastline.theory.files` (beneath the contact solvers, which read
spectrum files too), offered here beside the profile and map readers."""

from __future__ import annotations

from fastline.theory import Table, parse_table, read_spectrum, read_table, split_fields

__all__ = ["Table", "parse_table", "read_spectrum", "read_table", "split_fields"]
