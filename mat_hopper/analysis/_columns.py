"""The column check shared by the tables for reading: a table that lacks a
column a function needs raises a ValueError that names the function and the
missing columns, before any row is computed.
"""

from __future__ import annotations

import pandas as pd


def need_columns(table: pd.DataFrame, columns, what: str) -> None:
    """ValueError naming the `columns` `table` lacks (the caller `what`)."""
    missing = [c for c in dict.fromkeys(columns) if c not in table.columns]
    if missing:
        raise ValueError(f"{what} needs columns {missing}")
