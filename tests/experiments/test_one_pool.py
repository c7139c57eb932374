"""One pool for the book: every planned run known before any run, each
once, longest first; and a grid's uncached runs submitted longest first."""

import pandas as pd

from mat_hopper.experiments.plan import Estimate, book_tasks, plan
from mat_hopper.experiments.runner import Runner
from mat_hopper.optimize.book_plan import chapters
from mat_hopper.util.limits import task_steps


def test_book_tasks_are_the_plans_runs_once_longest_first():
    registry = chapters()
    tasks = book_tasks("quick", registry)
    keys = [t.key() for t in tasks]
    assert len(keys) == len(set(keys))
    steps = [task_steps(t) for t in tasks]
    assert steps == sorted(steps, reverse=True) and steps[0] > steps[-1]
    table = plan("quick", chapters=registry)
    exact = table[table["counted"] != "estimate"]
    # the plan's distinct runs, its estimates (sampled trials) left out
    assert len(tasks) == int(exact["runs"].sum() - exact["shared_with_earlier"].sum())
    assert not any(isinstance(t, Estimate) for t in tasks)


class _Task:
    """A runner task of a given size that records when it ran."""

    log: list = []

    def __init__(self, name: str, steps: int):
        self.name, self.steps, self.labels = name, steps, {"name": name}

    def key(self) -> str:
        return f"test-{self.name}"

    def key_dict(self) -> dict:
        return {"name": self.name}

    def default_labels(self) -> dict:
        return {}

    def estimated_steps(self) -> float:
        return float(self.steps)

    def compute(self):
        _Task.log.append(self.name)
        return pd.DataFrame({"x": [1.0]}), {"status": "ok"}


def test_a_grids_uncached_runs_start_longest_first(tmp_path):
    _Task.log = []
    grid = [_Task("short", 10), _Task("long", 1000), _Task("middle", 100)]
    with Runner(tmp_path, workers=1, progress=False) as runner:
        res = runner.run(grid)
    assert _Task.log == ["long", "middle", "short"]
    assert list(res.summary["name"]) == ["short", "long", "middle"]  # results stay in grid order
