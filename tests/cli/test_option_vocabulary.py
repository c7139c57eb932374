"""One vocabulary of options across the commands: the same flag does the
same thing (default, choices, help) in every command that has it; the
flags a message names are options of the command that prints it; an
unknown name is answered with "did you mean ...?"; a list that may be a
decimal comma is questioned; and an existing output is replaced only with
--force."""

from __future__ import annotations

import argparse
import ast
import functools
import os
import pathlib
import re

import pytest
from _refusal import refused

import mat_hopper
from mat_hopper.cli import COMMAND_HELP, build_parser, main, subcommand_parser
from mat_hopper.core.materials import DEFAULT_CONVENTION

COMMANDS = tuple(COMMAND_HELP)
PACKAGE = pathlib.Path(mat_hopper.__file__).parent


def _parser(command: str) -> argparse.ArgumentParser:
    return subcommand_parser(build_parser(command), command)


def _actions(command: str) -> dict[str, argparse.Action]:
    return {s: a for a in _parser(command)._actions for s in a.option_strings}


ACTIONS = {c: _actions(c) for c in COMMANDS}

# Options several commands share and that must mean one thing; the
# commands left out of one are those where it is another option that
# happens to share the name (optimize's --segments is the search space's
# size; its --behaviour takes a comma list, default ramp, the study's) or
# one read by another reader (optimize's --segment-mass, by the study's
# config, which keeps a resumed study's own).
SHARED = {
    "--no-progress": (),
    "--profile": (),
    "--convention": (),
    "--force": (),
    "--behaviour": ("optimize",),
    "--segment-mass": ("optimize",),
    "--sensor-timing": (),
    "--density": (),
    "--modulus": (),
    "--segments": ("optimize",),
    "--duration": (),
    "--transient": (),
    "--design-csv": (),
}
# Commands whose parser default is None so that a value given can be told
# from one left out: render (a --still refuses run settings) and optimize
# (a resumed study keeps its stored settings); batch's --behaviour
# (--stability refuses it). Each applies the shared default itself.
SENTINEL = {
    ("render", "--convention"),
    ("optimize", "--convention"),
    ("render", "--sensor-timing"),
    ("render", "--segment-mass"),
    ("batch", "--behaviour"),
}


@pytest.mark.parametrize("flag", sorted(SHARED))
def test_a_shared_option_has_one_default_choices_and_help(flag):
    have = {c: a[flag] for c, a in ACTIONS.items() if flag in a and c not in SHARED[flag]}
    assert len(have) >= 2, f"{flag} is in {sorted(have)} only"
    for what in ("help", "choices", "nargs", "const", "metavar"):
        seen = {repr(getattr(a, what)) for a in have.values()}
        assert len(seen) == 1, f"{flag}'s {what} differs: " + "; ".join(
            f"{c}: {getattr(a, what)!r}" for c, a in have.items()
        )
    defaults = {c: a.default for c, a in have.items() if (c, flag) not in SENTINEL}
    assert len(set(map(repr, defaults.values()))) == 1, f"{flag}'s default differs: {defaults}"
    for c in have:
        if (c, flag) in SENTINEL:
            assert have[c].default is None, (c, flag)


def test_every_command_with_an_output_has_force_and_every_progress_display_no_progress():
    for command, actions in ACTIONS.items():
        outputs = {"--csv", "--tiles", "--video", "--still", "--out", "--export"} & set(actions)
        if outputs:
            assert "--force" in actions, (command, outputs)
    assert ACTIONS["batch"]["--quiet"] is ACTIONS["batch"]["--no-progress"]  # --quiet kept, one option
    for command in ("simulate", "batch", "reproduce", "optimize"):
        assert ACTIONS[command]["--no-progress"].dest == "no_progress"


def test_the_convention_defaults_to_paper_everywhere_modes_included():
    from mat_hopper.cli.render import RUN_DEFAULTS
    from mat_hopper.optimize import StudyConfig

    for command, actions in ACTIONS.items():
        if "--convention" in actions and (command, "--convention") not in SENTINEL:
            assert actions["--convention"].default == DEFAULT_CONVENTION == "paper", command
    assert RUN_DEFAULTS["convention"] == DEFAULT_CONVENTION
    assert StudyConfig("x").objective.convention == DEFAULT_CONVENTION
    assert _parser("modes").parse_args([]).convention == "paper"


def test_batch_takes_no_progress_and_quiet(capsys):
    p = _parser("batch")
    assert p.parse_args(["--designs", "SS", "--no-progress"]).no_progress
    assert p.parse_args(["--designs", "SS", "--quiet"]).no_progress
    assert not p.parse_args(["--designs", "SS"]).no_progress


@pytest.mark.parametrize(
    "mode", [["--report", "none"], ["--study", "none", "--export", "0"], ["--study", "none", "--replay", "0"]]
)
def test_optimize_takes_no_progress_in_every_kind_of_work(tmp_path, capsys, mode):
    """--no-progress is a shared option: a script that passes it to every
    command is never refused for it (the study is then looked for)."""
    cap = refused(["optimize", *mode, "--no-progress", "--studies-dir", str(tmp_path)], capsys, "no study 'none'")
    assert "--no-progress" not in cap.err


def test_an_unknown_option_is_refused_by_its_command_with_the_nearest(capsys):
    _, err = refused(["batch", "--designs", "SS", "--no-progess"], capsys)
    assert err.startswith("mat-hopper batch: error: unrecognized arguments: --no-progess;")
    assert "did you mean --no-progress?" in err
    refused(["modes", "--segmnts", "4"], capsys, "mat-hopper modes: error:", "did you mean --segments?")


# --- messages name real options ---------------------------------------------------------------------------


FLAG = re.compile(r"(?<![\w-])--[a-z][a-z0-9-]*")
# A command named in a message, then its options ("simulate --design-csv", "mat-hopper modes --design D").
NAMED = re.compile(r"(?<![-\w])(" + "|".join(COMMANDS) + r")\b((?:\s+--[a-z][a-z0-9-]*(?:\s+[^\s-]\S*)?)*)")
# What a shared module is reached from: a function in one command module that other commands import.
USED_BY = {"_optimize_outputs": ("optimize",)}
# A function that writes another command's line (optimize --export prints a simulate command).
WRITES_COMMAND = {("_optimize_outputs", "simulate_command"): "simulate"}
# (command, flag) a shared function names only where the command has it:
# design_from_args' --design-csv branch (read with getattr; modes has none),
# and sim_settings_from_args' default duration_flag (render passes its own).
GUARDED = {("modes", "--design-csv"), ("render", "--duration")}
TOP_LEVEL = {s for a in build_parser("")._actions for s in a.option_strings}  # --version, --help


def _messages(path: pathlib.Path):
    """(line, text) of every string literal that is not a docstring; an
    f-string as one text, its fields as {}."""
    tree = ast.parse(path.read_text())
    docs, parts = set(), set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                docs.add(id(first.value))
        if isinstance(node, ast.JoinedStr):
            parts.update(id(v) for v in node.values)
            text = "".join(v.value if isinstance(v, ast.Constant) else "{}" for v in node.values)
            yield node.lineno, text
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs | parts:
            yield node.lineno, node.value


@functools.cache
def _imports() -> dict[tuple[str, str], set[str]]:
    """{(cli module, name): the commands whose module imports the name from it}."""
    out: dict = {}
    for c in COMMANDS:
        for node in ast.walk(ast.parse((PACKAGE / "cli" / f"{c}.py").read_text())):
            if isinstance(node, ast.ImportFrom) and node.level == 1:
                for a in node.names:
                    out.setdefault((node.module, a.name), set()).add(c)
    return out


def _not_an_option(text: str) -> list[str]:
    return [f for f in FLAG.findall(text) if f not in TOP_LEVEL and not any(f in a for a in ACTIONS.values())]


def _unknown_flags(text: str, commands) -> list[str]:
    """The flags of `text` that are not options of every one of `commands`
    (a flag after a command's name is checked against that command)."""
    bad, rest = [], text
    for m in NAMED.finditer(text):
        for flag in FLAG.findall(m.group(2)):
            if flag not in ACTIONS[m.group(1)]:
                bad.append(f"{m.group(1)} {flag}")
        rest = rest.replace(m.group(0), m.group(1))
    for flag in FLAG.findall(rest):
        bad += [f"{c} {flag}" for c in commands if flag not in ACTIONS[c] and (c, flag) not in GUARDED]
    return bad


def _functions_of(path: pathlib.Path):
    """{function name: (first line, last line)} of a module's top-level functions."""
    tree = ast.parse(path.read_text())
    return {n.name: (n.lineno, n.end_lineno) for n in tree.body if isinstance(n, ast.FunctionDef)}


def test_every_flag_a_message_names_is_an_option_of_its_command():
    bad = []
    every = set(COMMANDS)
    for path in sorted(PACKAGE.rglob("*.py")):
        if path.name in ("book.py", "sphinx_ext.py"):  # jupyter-book's and Sphinx's own flags
            continue
        module = path.stem
        in_cli = path.parent.name == "cli"
        functions = _functions_of(path) if in_cli else {}
        for line, text in _messages(path):
            if not in_cli:  # the library: an option of some command (none invented, e.g. --record-rate)
                bad += [f"{path.name}:{line}: {f}" for f in _not_an_option(text)]
                continue
            own = {module} if module in COMMANDS else set(USED_BY.get(module, ()))
            fn = next((n for n, (a, b) in functions.items() if a <= line <= b), None)
            users = own | _imports().get((module, fn), set())  # a function of one module others import
            if (module, fn) in WRITES_COMMAND:  # its options are that command's, not its caller's
                users = {WRITES_COMMAND[module, fn]}
            if not users:  # module-level text of _checks, _options, __init__: shared by all
                bad += [f"{path.name}:{line}: {f}" for f in _not_an_option(text)]
                continue
            bad += [f"{path.name}:{line}: {b}" for b in _unknown_flags(text, users & every)]
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "--duration", "20000", "--transient", "1"],
        ["batch", "--designs", "SS", "--duration", "20000", "--transient", "1"],
        ["render", "--video", "v.mp4", "--seconds", "20000"],
    ],
)
def test_the_recorded_samples_limit_names_the_run_length_options(argv, tmp_path, monkeypatch, capsys):
    """The library's "lower record_rate_hz or duration_s": no option sets
    the record rate; the command line names its run length instead."""
    monkeypatch.chdir(tmp_path)
    _, err = refused(argv, capsys, "recorded samples", "give a shorter --")
    assert "record_rate_hz" not in err
    for flag in FLAG.findall(err):
        assert flag in ACTIONS[argv[0]], (flag, err)


def test_a_setting_is_named_by_an_option_only_where_the_command_has_it():
    from mat_hopper.cli._checks import COMMAND_OPTIONS, named_by_flags

    def text(command):
        COMMAND_OPTIONS[0] = frozenset(ACTIONS[command]) if command else None
        try:
            with named_by_flags():
                raise ValueError("segment_mass must be leg or capsule; n_segments 3")
        except ValueError as e:
            return str(e)
        finally:
            COMMAND_OPTIONS[0] = None

    assert text("simulate") == "--segment-mass must be leg or capsule; --segments 3"
    assert text("reproduce") == "segment_mass must be leg or capsule; n_segments 3"  # it has neither option
    assert text(None) == "--segment-mass must be leg or capsule; --segments 3"


# --- did you mean ...? ------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "argv, hint",
    [
        (["simulate", "--design", "rho_inc"], "did you mean rho-inc?"),
        (["simulate", "--design", "PVC-Tii-SS"], "did you mean PVC-Ti-SS?"),
        (["render", "--design", "rho/dec", "--still", "s.png"], "did you mean rho-dec?"),
        (["modes", "--design", "S"], "did you mean SS?"),
        (["batch", "--designs", "SS,rho_inc"], "did you mean rho-inc?"),
        (["simulate", "--behaviour", "forwrd"], "did you mean forward?"),
        (["batch", "--designs", "SS", "--behavior", "circel"], "did you mean circle?"),
        (["simulate", "--convention", "axail"], "did you mean axial?"),
        (["modes", "--convention", "axial bending"], "did you mean axial+bending?"),
        (["batch", "--designs", "SS", "--profile", "quik"], "did you mean quick?"),
        (["reproduce", "--profile", "papr"], "did you mean paper?"),
        (["reproduce", "--experiments", "1,robustnes"], "did you mean robustness?"),
        (["reproduce", "--conventions", "paper,axal"], "did you mean axial?"),
        (["optimize", "--study", "s", "--objectives", "tracking_eror_m,power_w"], "did you mean tracking_error_m?"),
        (["optimize", "--study", "s", "--space", "catalogue", "--materials", "SS,Tii"], "did you mean Ti?"),
        (["simulate", "--segment-mass", "capsle"], "did you mean capsule?"),
        (["optimize", "--study", "s", "--behaviour", "ramp,forwrd"], "did you mean forward?"),
    ],
)
def test_an_unknown_name_is_answered_with_the_nearest(argv, hint, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    refused(argv, capsys, hint)
    assert os.listdir(tmp_path) == []


def test_design_spellings_that_name_a_design_are_read_or_suggested():
    from mat_hopper.core.materials import parse_design

    assert parse_design("RHO-INC").name == "rho-inc" and parse_design("ss").name == "SS"
    assert parse_design("pvc_ti_ss").name == "PVC-Ti-SS"
    for text, name in (("rho_inc", "rho-inc"), ("rho inc", "rho-inc"), ("RHOINC", "rho-inc"), ("Rho/Dec", "rho-dec")):
        with pytest.raises(ValueError, match=rf"^unknown design {text!r}; accepted: .*; did you mean {name}\?$"):
            parse_design(text)
    with pytest.raises(ValueError, match=r"^unknown material 'kryptonite'; accepted: MD, PVC, .*rho-dec$"):
        parse_design("kryptonite")  # nothing close: no guess


# --- a decimal comma is questioned ------------------------------------------------------------------------


@pytest.mark.parametrize("command", ["simulate", "modes", "render"])
def test_two_lists_that_may_be_decimal_commas_are_questioned(command, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    extra = ["--still", "s.png"] if command == "render" else []
    _, err = refused([command, "--density", "2,7", "--modulus", "1,5", *extra], capsys, "2.7", "1.5", "--segments 2")
    assert "decimal comma" in err
    refused([command, "--density", "8,7", "--modulus", "70", *extra], capsys, "got 2 and 1", "for 8.7 write a point")
    refused([command, "--density", "8,8", "--modulus", "70,70", "--segments", "3", *extra], capsys, "--segments 3")
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize(
    "density, modulus, segments, n",
    [
        ("2,7", "1,5", ["--segments", "2"], 2),  # the count confirmed
        ("2.0,7", "1,5", [], 2),  # a point in one list: two segments
        ("2,7", "70,rigid", [], 2),
        ("1.39,4.43,8", "70,70,70", [], 3),
        ("8,8,8", "193,193,193", ["--segments", "3"], 3),
        ("2.7", "1.5", [], 1),
    ],
)
def test_lists_that_are_lists_are_read(density, modulus, segments, n):
    from mat_hopper.cli.simulate import design_from_args

    args = _parser("simulate").parse_args(["--density", density, "--modulus", modulus, *segments])
    assert design_from_args(args).n_segments == n


def test_the_decimal_comma_rule_is_in_the_help(capsys):
    from mat_hopper.cli._options import DECIMAL_COMMA_RULE, decimal_comma_of

    for command in ("simulate", "render", "modes"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        assert " ".join(DECIMAL_COMMA_RULE.split()) in " ".join(capsys.readouterr().out.split())
    assert [decimal_comma_of(t) for t in ("2,7", " 10,25 ", "2, 7", "-2,7", "2.0,7", "8,8,8", "1e3,5")] == [
        "2.7",
        "10.25",
        None,
        None,
        None,
        None,
        None,
    ]


# --- existing outputs: replaced only with --force ---------------------------------------------------------


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for var in ("MAT_HOPPER_PROFILE", "MAT_HOPPER_MAX_STEPS", "MAT_HOPPER_CACHE"):
        monkeypatch.delenv(var, raising=False)
    return tmp_path


SHORT = ["--duration", "2", "--transient", "1", "--no-progress"]


@pytest.mark.parametrize(
    "argv, flag",
    [
        (["simulate", *SHORT, "--csv", "old.csv"], "--csv"),
        (["batch", "--designs", "SS", *SHORT, "--csv", "old.csv"], "--csv"),
        (["modes", "--csv", "old.csv"], "--csv"),
        (["render", "--still", "old.png"], "--still"),
        (["render", "--tiles", "old.png"], "--tiles"),
        (["render", "--video", "old.mp4", "--seconds", "1"], "--video"),
    ],
)
def test_an_output_file_that_exists_is_replaced_only_with_force(argv, flag, here, capsys, monkeypatch):
    old = argv[-1] if argv[-2] == flag else argv[argv.index(flag) + 1]
    (here / old).write_text("mine")
    refused(argv, capsys, f"{flag} {old}: file exists", "--force")
    assert (here / old).read_text() == "mine"
    if argv[0] == "modes":  # seconds of work: run it
        assert main([*argv, "--force"]) == 0
        assert (here / old).read_text().startswith("mode,")
        return
    monkeypatch.setenv("MAT_HOPPER_MAX_STEPS", "10")  # with --force the next check refuses: the file was let pass
    _, err = refused([*argv, "--force"], capsys, "physics steps")
    assert "exists" not in err and (here / old).read_text() == "mine"


def test_simulate_force_replaces_the_table(here, capsys):
    (here / "hops.csv").write_text("mine")
    assert main(["simulate", *SHORT, "--csv", "hops.csv", "--force"]) in (0, 1)
    assert (here / "hops.csv").read_text().startswith("design")
    capsys.readouterr()
    assert main(["modes", "--csv", "-", "--force"]) == 0  # standard output: nothing to replace, accepted
    assert capsys.readouterr().out.startswith("mode,")


@pytest.mark.parametrize(
    "argv, outputs",
    [
        (["simulate", *SHORT, "--force"], "--csv"),
        (["batch", "--designs", "SS", *SHORT, "--force"], "--csv"),
        (["modes", "--force"], "--csv"),
        (["optimize", "--study", "s", "--force"], "--report, --export or --replay --render"),
        (["optimize", "--study", "s", "--replay", "0", "--force"], "--report, --export or --replay --render"),
    ],
)
def test_force_without_an_output_is_refused(argv, outputs, here, capsys):
    refused(argv, capsys, f"--force is for {outputs}")
    assert os.listdir(here) == []


def test_reproduce_out_with_an_earlier_run_is_replaced_only_with_force(here, capsys, monkeypatch):
    for old in ("r/exp1_runs.csv", "s/claims.md", "f/figures/fig4_mono.png"):
        os.makedirs(os.path.dirname(here / old), exist_ok=True)
        (here / old).write_text("mine")
        out = old.split("/")[0]
        refused(["reproduce", "--profile", "quick", "--out", out], capsys, f"--out {out}:", "--force")
        monkeypatch.setenv("MAT_HOPPER_MAX_STEPS", "10")
        _, err = refused(["reproduce", "--profile", "quick", "--out", out, "--force"], capsys, "physics steps")
        monkeypatch.delenv("MAT_HOPPER_MAX_STEPS")
        assert (here / old).read_text() == "mine"
    (here / "other").mkdir()
    (here / "other" / "notes.txt").write_text("mine")  # not a file reproduce writes
    monkeypatch.setenv("MAT_HOPPER_MAX_STEPS", "10")
    refused(["reproduce", "--profile", "quick", "--out", "other"], capsys, "physics steps")


@pytest.mark.parametrize(
    "argv, old",
    [
        (["--report", "s"], "studies/s-report/pareto.csv"),
        (["--report", "s", "--out", "r"], "r/trials.csv"),
        (["--study", "s", "--export", "0"], "studies/s-trial0.csv"),
        (["--study", "s", "--export", "3", "--out", "ex"], "ex/s-trial3-ramp.xml"),
        (["--study", "s", "--replay", "1", "--render", "--out", "v"], "v/s-trial1-ramp.mp4"),
        (["--study", "s", "--replay", "1", "--render"], "studies/s-trial1-forward-tiles.png"),
    ],
)
def test_optimize_outputs_are_replaced_only_with_force(argv, old, here, capsys):
    """Checked before the study is opened: with --force the next refusal is
    the missing study's."""
    os.makedirs(os.path.dirname(here / old), exist_ok=True)
    (here / old).write_text("mine")
    refused(["optimize", *argv], capsys, "--out", old, "exists already", "--force")
    refused(["optimize", *argv, "--force"], capsys, "no study 's'")
    assert (here / old).read_text() == "mine"


def test_optimize_report_names_match_the_report_it_writes():
    """REPORT_FILES is what write_report writes (read from its source)."""
    from mat_hopper.cli._optimize_outputs import REPORT_FILES

    source = (PACKAGE / "optimize" / "report.py").read_text()
    written = re.findall(r'\("\w+", "(\w+\.(?:csv|png))"\)', source)
    assert sorted(written) == sorted(REPORT_FILES)
