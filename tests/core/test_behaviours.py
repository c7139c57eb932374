import math

import numpy as np
import pytest

from mat_hopper.core.behaviours import Behaviour, behaviour


def test_paper_paths():
    assert behaviour("static").desired(10.0) == (0.0, 0.0, 0.0, 0.0)
    x, y, vx, vy = behaviour("forward").desired(20.0)
    assert (x, y, vx, vy) == pytest.approx((1.0, 0.0, 0.05, 0.0))
    r = behaviour("ramp")
    assert r.ramp_grade_deg == 2.0 and r.desired(20.0)[0] == pytest.approx(1.0)
    c = behaviour("circle")
    assert c.start_xy_m == (0.5, 0.0)
    x, y, vx, vy = c.desired(10.0)
    assert (x, y) == pytest.approx((0.5 * math.cos(1.0), 0.5 * math.sin(1.0)))
    assert math.hypot(vx, vy) == pytest.approx(0.05)


def test_parameters():
    assert behaviour("forward", speed_m_s=0.1).desired(1.0)[0] == pytest.approx(0.1)
    assert behaviour("ramp", grade_deg=4.0).ramp_grade_deg == 4.0
    assert behaviour("circle", radius_m=1.0).desired(0.0)[0] == pytest.approx(1.0)


def test_custom_path_from_function_is_interpolated():
    b = Behaviour.from_function("wave", lambda t: (0.05 * t, 0.1 * math.sin(t)), duration_s=10.0, dt_s=1e-3)
    x, y, vx, vy = b.desired(2.0005)
    assert x == pytest.approx(0.100025) and y == pytest.approx(0.1 * math.sin(2.0005), abs=1e-7)
    assert vx == pytest.approx(0.05)
    # after its end the path holds its last point
    assert b.desired(50.0)[2:] == (0.0, 0.0)
    assert b.key()["table_sha"] != Behaviour.from_function("w2", lambda t: (0, 0), 10.0).key()["table_sha"]


def test_bad_behaviours():
    with pytest.raises(ValueError, match="unknown behaviour 'hop'.*static, forward, ramp, circle"):
        behaviour("hop")
    with pytest.raises(ValueError, match="speed_m_s"):
        behaviour("forward", speed_m_s=-1)
    with pytest.raises(ValueError, match="radius_m"):
        behaviour("circle", radius_m=0)
    with pytest.raises(ValueError, match="table_xy_m"):
        Behaviour.from_samples("bad", 1e-3, np.array([[0.0, np.nan]]))


@pytest.mark.parametrize("bad", [0, 0.0, -1e-3, float("nan"), float("inf"), True, "1e-3"])
def test_from_function_refuses_a_bad_step_or_duration_before_calling_fn(bad):
    # dt_s=0 raised ZeroDivisionError before the fix; nan or inf went on to numpy
    calls = []
    fn = lambda t: calls.append(t) or (0.0, 0.0)
    with pytest.raises(ValueError, match="dt_s must be a finite number > 0 s"):
        Behaviour.from_function("p", fn, duration_s=1.0, dt_s=bad)
    with pytest.raises(ValueError, match="duration_s must be a finite number > 0 s"):
        Behaviour.from_function("p", fn, duration_s=bad)
    with pytest.raises(ValueError, match="dt_s must be a finite number > 0 s"):
        Behaviour.from_samples("p", bad, np.zeros((3, 2)))
    assert calls == []


def test_table_paths_are_capped_before_any_sample_is_taken():
    from mat_hopper.util.limits import MAX_PATH_SAMPLES

    calls = []
    fn = lambda t: calls.append(t) or (0.0, 0.0)
    with pytest.raises(ValueError, match="MAX_PATH_SAMPLES"):
        Behaviour.from_function("p", fn, duration_s=1e9)  # 1e12 samples at 1 ms: no size cap before the fix
    with pytest.raises(ValueError, match="MAX_PATH_SAMPLES"):
        Behaviour.from_function("p", fn, duration_s=1.0, dt_s=1e-300)
    assert calls == []
    with pytest.raises(ValueError, match="MAX_PATH_SAMPLES"):
        Behaviour.from_samples("p", 1e-3, np.broadcast_to(np.zeros(2), (MAX_PATH_SAMPLES + 1, 2)))
    assert len(Behaviour.from_function("p", fn, duration_s=1.0, dt_s=0.25).table_xy_m) == 5


def test_table_step_and_start_must_be_finite():
    with pytest.raises(ValueError, match="table_dt_s must be finite"):
        Behaviour("p", "table", table_dt_s=math.inf)
    with pytest.raises(ValueError, match="start_xy_m"):
        Behaviour("p", start_xy_m=(math.nan, 0.0))


@pytest.mark.parametrize("name", ["", "   "])
def test_from_function_refuses_an_empty_name(name):
    with pytest.raises(ValueError, match="name"):
        Behaviour.from_function(name, lambda t: (t, 0.0), 1.0)


def test_from_function_refuses_a_fn_that_is_not_callable():
    with pytest.raises(ValueError, match="fn must be callable"):
        Behaviour.from_function("x", (0.0, 0.0), 1.0)


@pytest.mark.parametrize(
    "fn, shown",
    [(lambda t: (t, 0.0, 1.0), "(0.0, 0.0, 1.0)"), (lambda t: (float("nan"), 0.0), "nan"), (lambda t: "ab", "'ab'")],
)
def test_from_function_names_fn_and_what_it_returned(fn, shown):
    with pytest.raises(ValueError, match="fn") as e:
        Behaviour.from_function("x", fn, 1.0)
    assert shown in str(e.value) and "fn(0)" in str(e.value)
