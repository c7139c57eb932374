"""The CLI's refusal of bad input, as every bad-input test of tests/cli checks it."""

import time

from mat_hopper.cli import main


def refused(argv, capsys, *texts, max_wall_s=10.0):
    """main(argv) answers one line on stderr, exit code 2, containing every
    text, before any work; returns pytest's captured (out, err)."""
    t0 = time.perf_counter()
    try:
        code = main(argv)
    except SystemExit as e:  # argparse's own errors (one line too)
        code = e.code
    wall = time.perf_counter() - t0
    cap = capsys.readouterr()
    err = cap.err.strip()
    assert code == 2, (cap.out, err)
    assert len(err.splitlines()) == 1, err
    for t in texts:
        assert t in err, err
    assert "Traceback" not in err and "invalid literal" not in err
    assert wall < max_wall_s, f"{wall:.1f} s: work started before the check"
    return cap
