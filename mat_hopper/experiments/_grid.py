"""A grid's tables in grid order, from its stored results (:class:`mat_hopper.experiments.runner.Runner`)."""

from __future__ import annotations

import pandas as pd

FAILED = "failed"  # the status of a task without a result (re-exported as runner.FAILED)


def _label_frame(labels: dict, frame: pd.DataFrame) -> pd.DataFrame:
    out = frame.copy()
    for col in [c for c in labels if c in out.columns]:
        out = out.drop(columns=col)
    for i, (col, v) in enumerate(labels.items()):
        out.insert(i, col, [v] * len(out))
    return out


def assemble(tasks, keys, results, errors) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The grid's (tables, summary): every task's table with its labels in
    front and a ``key`` column, and one summary row per task (labels,
    summary fields, then status, error, key), in grid order; a task without
    a result is a ``failed`` row with its error text."""
    frames, rows, empty = [], [], None
    for t, k in zip(tasks, keys):
        labels = {**t.labels, **{c: v for c, v in t.default_labels().items() if c not in t.labels}}
        if k in results:
            table, summary = results[k]
            if len(table) or empty is None:
                f = _label_frame(labels, table)
                f["key"] = k
                if len(f):
                    frames.append(f)
                else:
                    empty = f  # keeps the columns when no task has a row
            row = {**labels, **{c: v for c, v in summary.items() if c not in labels}, "error": ""}
        else:
            row = {**labels, "status": FAILED, "error": errors.get(k, "not computed")}
        row["key"] = k
        rows.append(row)
    tables = (
        pd.concat(frames, ignore_index=True)
        if frames
        else empty.reset_index(drop=True)
        if empty is not None
        else pd.DataFrame()
    )
    summary = pd.DataFrame(rows)
    if "status" in summary.columns:
        cols = [c for c in summary.columns if c not in ("status", "error", "key")]
        summary = summary[cols + ["status", "error", "key"]]
    return tables, summary
