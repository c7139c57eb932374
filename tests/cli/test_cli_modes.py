import pandas as pd

from mat_hopper.cli import main


def test_modes_prints_chain_beside_rod_and_writes_csv(tmp_path, capsys):
    csv = tmp_path / "modes.csv"
    assert main(["modes", "--design", "SS", "--segments", "16", "--convention", "axial", "--csv", str(csv)]) == 0
    out = capsys.readouterr().out
    assert "chain_hz" in out and "rod_hz" in out and "boundary conditions" in out
    assert "set by the spring chain" in out and "--timestep auto:" in out
    t = pd.read_csv(csv)
    assert list(t.columns[:3]) == ["mode", "chain_hz", "rod_hz"]
    assert abs(t["chain_hz"][0] / t["rod_hz"][0] - 1) < 0.01  # mode 1 within 1 % at N = 16


def test_modes_gives_a_graded_leg_its_stable_step_and_refuses_its_table(tmp_path, capsys):
    assert main(["modes", "--design", "rho-inc"]) == 0  # its help's example is graded: the step, no table
    out = capsys.readouterr().out
    assert "no modes table" in out and "analytic stable time step" in out and "chain_hz" not in out
    assert main(["modes", "--design", "rho-inc", "--csv", str(tmp_path / "m.csv")]) == 2
    err = capsys.readouterr().err
    assert "one elastic material" in err and len(err.strip().splitlines()) == 1


def test_modes_does_not_deny_what_its_auto_line_offers(capsys):
    """A 64-segment SS leg under bending: the controller's limit (5.8e-5 s)
    lies below the 1e-4 s period, and --timestep auto shortens the period
    to 2.5e-5 s, within it: no line may say this leg is beyond the controller."""
    assert main(["modes", "--design", "SS", "--segments", "64", "--convention", "bending"]) == 0
    out = capsys.readouterr().out
    assert "2.5e-05 s control period" in out
    assert "beyond" not in out and "shortens the control period to 2.5e-05 s" in out
