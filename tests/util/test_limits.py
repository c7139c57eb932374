"""Run-size limits (mat_hopper.util.limits): the step limit's lower bound, as its
docstring states it (a number >= 1)."""

import pytest

from mat_hopper.util.limits import MAX_TOTAL_STEPS, max_total_steps


def test_max_total_steps_default_and_lower_bound(monkeypatch):
    monkeypatch.delenv("MAT_HOPPER_MAX_STEPS", raising=False)
    assert max_total_steps() == 2e10 == MAX_TOTAL_STEPS
    monkeypatch.setenv("MAT_HOPPER_MAX_STEPS", "1")
    assert max_total_steps() == 1.0  # the least limit accepted
    for bad in ("0.5", "0", "-3"):  # "> 0" would accept 0.5: the bound is 1
        monkeypatch.setenv("MAT_HOPPER_MAX_STEPS", bad)
        with pytest.raises(ValueError, match=r"\$MAT_HOPPER_MAX_STEPS must be >= 1"):
            max_total_steps()


def test_max_total_steps_docstring_states_the_bound():
    assert "number >= 1" in " ".join(max_total_steps.__doc__.split())
    assert "> 0" not in max_total_steps.__doc__
