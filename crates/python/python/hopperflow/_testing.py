"""Hooks for hopperflow's own tests; not part of the package's API.

``engine_reference`` is the reference of the bit-identity test of ``Simulation``: the same
set-up stepped by the engine in one uninterrupted run, without the Python class in between.
"""

from ._native import _engine_reference as engine_reference

__all__ = ["engine_reference"]
