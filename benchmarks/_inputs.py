"""Checks of a benchmark's command line before any run, as the package's
commands check theirs: a bad profile, convention, contact or output path is
one line from argparse (exit 2), not a traceback, and never after the runs
(a paper-profile benchmark runs for minutes before it writes)."""

from __future__ import annotations

import os
import tempfile

from mat_hopper.core.contact import check_contact
from mat_hopper.core.conventions import check_convention
from mat_hopper.experiments.profiles import get_profile


def settings(ap, profile: str, conventions, contact: str):
    """(Profile, canonical conventions, canonical contact), or ap.error naming the bad one."""
    try:
        prof = get_profile(profile)
        convs = tuple(check_convention(c) for c in conventions)
        return prof, convs, check_contact(contact)
    except ValueError as e:
        ap.error(str(e))


def outputs(ap, cache: str, **files) -> None:
    """ap.error unless the cache folder can be made and each output file
    (by its option, e.g. ``csv="out.csv"``; None: not asked for) can be
    written: its folder exists and is writable, and it is not a folder."""
    try:
        os.makedirs(cache, exist_ok=True)
    except OSError as e:
        ap.error(f"--cache {cache}: cannot make the folder ({e.strerror})")
    if not os.access(cache, os.W_OK):
        ap.error(f"--cache {cache}: the folder is not writable")
    for option, path in files.items():
        if path is None:
            continue
        flag = "--" + option.replace("_", "-")
        folder = os.path.dirname(os.path.abspath(path))
        if os.path.isdir(path):
            ap.error(f"{flag} {path}: is a folder; give a file name")
        if not os.path.isdir(folder):
            ap.error(f"{flag} {path}: the folder {folder} does not exist")
        try:  # a file made and removed there: the folder takes new files (os.access says yes in /proc)
            with tempfile.NamedTemporaryFile(dir=folder):
                pass
        except OSError as e:
            ap.error(f"{flag} {path}: cannot write in the folder {folder} ({e.strerror})")
