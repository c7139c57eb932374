"""mat_hopper.cli._checks: checks every command makes before any work."""

import pytest

from mat_hopper.cli import main


@pytest.mark.parametrize(
    "argv, flag",
    [
        (["batch", "--designs", "SS", "--designs", "Ti"], "--designs"),
        (["batch", "--designs", "SS", "--behaviour", "forward", "--behavior", "ramp"], "--behaviour"),
        (["simulate", "--design", "SS", "--design", "Ti"], "--design"),
        (["simulate", "--duration", "1", "--duration", "2"], "--duration"),
        (["reproduce", "--experiments", "1", "--experiments", "2"], "--experiments"),
        (["optimize", "--study", "a", "--study", "b"], "--study"),
    ],
)
def test_an_option_given_twice_is_refused(argv, flag, capsys):
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and flag in err and "given twice" in err
