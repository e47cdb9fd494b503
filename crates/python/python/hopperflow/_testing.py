"""Hooks for hopperflow's own tests; not part of the package's API.

``engine_reference`` is the reference of the bit-identity test of ``Simulation``: the same
set-up stepped by the engine in one uninterrupted run, without the Python class in between.
``numpy_tables`` reads tables in their dict-of-arrays form in an environment that has
pandas, so that both forms are tested in one environment.
"""

from __future__ import annotations

from contextlib import contextmanager
from typing import Iterator

from . import _tables
from ._native import _engine_reference as engine_reference

__all__ = ["engine_reference", "numpy_tables"]


@contextmanager
def numpy_tables() -> Iterator[None]:
    """Within the block, tables are dicts of numpy arrays, as without pandas."""
    before = _tables._pandas_off
    _tables._pandas_off = True
    try:
        yield
    finally:
        _tables._pandas_off = before
