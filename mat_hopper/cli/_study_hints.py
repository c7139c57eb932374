"""What a message about a study tells a command-line user: the options that
find the same study again (``--storage`` or ``--studies-dir``, shell-quoted,
for a command it prints), and a study that cannot run as asked
(:class:`mat_hopper.optimize.StudyMismatch`) in the options' terms rather
than the stored settings' field names."""

from __future__ import annotations

import os
import shlex

# Fields of a study's stored settings that an option of `optimize` sets,
# besides those of cli.optimize.OPTION_OF_FIELD (the caller's).
_MORE_OPTIONS = {
    "profile": "--profile",
    "timestep_s": "--timestep",
    "convention": "--convention",
    "segment_mass": "--segment-mass",
    "objectives": "--objectives",
}


def study_flags(args) -> list[str]:
    """The options that name the study's storage in a printed command:
    ``--storage URL`` (its password hidden), ``--studies-dir DIR`` for a
    folder other than the default ``studies``, else none."""
    from ..optimize import redact

    if getattr(args, "storage", None):
        return ["--storage", redact(args.storage)]
    folder = getattr(args, "studies_dir", None)
    if folder and os.path.normpath(folder) != "studies":
        return ["--studies-dir", folder]
    return []


def command_text(*words: str) -> str:
    """A command line to paste into a shell: each word quoted where it
    needs to be (``--design 'rho=1.4 E=340'``)."""
    return shlex.join(str(w) for w in words)


def _value_text(field: str, value) -> str:
    if value is None:
        return "0" if field == "replicates" else "none"  # a study without replicates stores None
    if isinstance(value, (list, tuple)):
        return ",".join(map(str, value))
    return str(value)


def mismatch_text(e, option_of_field: dict) -> str:
    """`e` (a StudyMismatch) as one line for the command line: what to give
    (``--race`` again, or without it) or which options differ, each by its
    option, with the study's value and the asked one."""
    if e.kind == "racing":
        return f"study {e.name!r} is a racing study: give --race again to resume it, or use a new --study name"
    if e.kind == "not racing":
        return f"study {e.name!r} was not run with --race: resume it without --race, or use a new --study name"
    options = {**_MORE_OPTIONS, **option_of_field}
    paths = {p for p, _, _ in e.differences}
    parts = []
    for path, has, asked in e.differences:
        field = path.rsplit(".", 1)[-1]
        if field == "replicate_seed_start" and "objective.replicates" in paths:
            continue  # follows from --replicates
        if path.startswith("racing."):
            name = f"--race's {field.replace('_', ' ')}"
        else:
            name = options.get(field) or f"the study's {field.replace('_', ' ')} (no option sets it)"
        parts.append(f"{name} (study has {_value_text(field, has)}, asked {_value_text(field, asked)})")
    return (
        f"study {e.name!r} exists with other settings: {', '.join(parts)}; give the study's own values "
        "(an option left out takes the study's) or use a new --study name"
    )
