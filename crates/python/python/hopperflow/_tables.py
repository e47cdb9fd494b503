"""Reading the CSV tables a run or a study writes."""

from __future__ import annotations

import csv
import os
from pathlib import Path
from typing import Any, Dict, List, Union

import numpy as np

#: A path argument: a str or any os.PathLike of str (pathlib.Path, ...).
PathLike = Union[str, "os.PathLike[str]"]

#: A table read from a CSV file: a ``pandas.DataFrame`` when pandas can be imported, else
#: a ``dict`` of numpy arrays, one per column (float64 where every cell is a number, str
#: otherwise). Annotated ``Any`` because which of the two it is depends on the
#: installation, not on the code: code written for either form type-checks.
Table = Any

#: The tables a finished run writes, by the name of the ``Run`` property that reads each:
#: flow.csv, profiles.csv, field.csv (a slab's, when its steady window was found),
#: crossings.csv, remaining.csv (the particles left in the container against time),
#: wall_forces.csv (the mean loads on the walls, by window of the run), wall_pressure.csv
#: (a cylindrical silo's wall pressure by zone of height), for a mixture,
#: composition.csv (the outflow by component), and for a run that breaks its arches
#: (``[protocol.unclog]``) avalanches.csv (each avalanche between clogs, with its arch).
RUN_TABLES: Dict[str, str] = {
    "flow": "flow.csv",
    "profiles": "profiles.csv",
    "field": "field.csv",
    "crossings": "crossings.csv",
    "remaining": "remaining.csv",
    "wall_forces": "wall_forces.csv",
    "wall_pressure": "wall_pressure.csv",
    "composition": "composition.csv",
    "avalanches": "avalanches.csv",
    "residence": "residence.csv",
}

# Set by hopperflow._testing.numpy_tables(), so that the tests can read the dict form of
# the tables in an environment that has pandas.
_pandas_off = False


def _pandas() -> Any:
    """pandas, or None when it is not installed (or the tests switched it off)."""
    if _pandas_off:
        return None
    try:
        import pandas  # noqa: PLC0415 (optional dependency)
    except ImportError:
        return None
    return pandas


def _column(values: List[str]) -> "np.ndarray[Any, Any]":
    """A CSV column as float64 where every cell is a number, else as str."""
    try:
        return np.array([float(v) if v != "" else np.nan for v in values], dtype=np.float64)
    except ValueError:
        return np.array(values, dtype=str)


def read_table(path: PathLike) -> Table:
    """A CSV file of hopperflow as a DataFrame, or a dict of numpy arrays without pandas.

    Numbers are parsed as Python parses them (shortest round-trip text, so the same bits
    as the writer's), in both forms.
    """
    path = Path(path)
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ValueError(f"{path}: empty file, expected a header line")
    header, body = rows[0], rows[1:]
    columns = {name: _column([r[i] if i < len(r) else "" for r in body]) for i, name in enumerate(header)}
    pandas = _pandas()
    if pandas is None:
        return columns
    return pandas.DataFrame(columns)
