"""``mat-hopper records``: the book's recorded paper-profile results
(``book/records/``) rebuilt from one finished book build.

A paper-profile book takes hours on a small machine, so the quick book
and the Findings page read its results from records. This command makes
those records from one build, so that they all come from one commit: the
tables the chapters wrote as downloads into the build's folder
(``results/<profile>/``), and the tables computed from the build's
result cache and study storage by the same library calls the chapters
make. It never starts a long computation: a run of experiments 1-3, the
stability map, robustness or the controls that is not in the cache is
refused before any work, with the command that computes it. Each record
file is written atomically; ``provenance.csv`` names, per file, where it
came from, the build's commit and the file's SHA-256.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile

import pandas as pd

from ..experiments.cache import CACHE_ENV, DEFAULT_CACHE_DIR
from ..util.atomic import atomic_path, write_csv
from ._checks import check_no_outputs_in, check_output_dir
from ._options import add_force, add_no_progress, add_profile, profile_of

HELP = "rebuild book/records (the paper-profile results the quick book shows) from one finished book build"

# The experiments whose runs the claims and robustness records read: chapter 10's call.
CLAIM_EXPERIMENTS = "1,2,3,stability,robustness,controls"
# Record (its file is <record>-<profile>.csv): the download a chapter writes
# into the build's folder (its name without .csv) and the chapter that writes it.
DOWNLOADS = {
    "stress-runs": ("stress_runs", "08b-gradients-stress"),
    "stress-verdicts": ("stress_verdicts", "08b-gradients-stress"),
    "stress-pairs": ("stress_pairs", "08b-gradients-stress"),
    "stress-tail": ("stress_tail", "08b-gradients-stress"),
}
# Record file (<record>-<profile><suffix>): the file the claims reproduction
# writes (mat-hopper reproduce's own names).
REPRODUCED = {
    ("claims", ".csv"): "claims.csv",
    ("claims", ".md"): "claims.md",
    ("robustness", ".csv"): "robustness.csv",
}
# Records computed from the build's cache and study storage by the chapters' own calls.
COMPUTED = ("crossed-legs", "optimizer", "optimizer-paired")
# The crossed legs' metrics in the record: the chapter's two and hip power.
CROSSED_METRICS = ("tracking_error_m", "power_w", "power_total_w")
PROVENANCE = "provenance.csv"


def build_commit(root: str) -> str:
    """The commit of the working tree at `root` (its first 7 hex digits),
    with ``+changes`` when tracked files differ from it; ``unknown``
    outside git."""
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True)
        changed = subprocess.run(["git", "status", "-s", "-uno"], cwd=root, capture_output=True, text=True)
    except OSError:
        return "unknown"
    if head.returncode != 0:
        return "unknown"
    return head.stdout.strip()[:7] + ("+changes" if changed.stdout.strip() else "")


def missing_runs(profile, cache_dir: str) -> int:
    """How many runs of :data:`CLAIM_EXPERIMENTS` under `profile` are not in the cache."""
    from ..experiments.paper import parse_experiments
    from ..experiments.plan import cached_keys
    from ..experiments.reproduce import experiment_tasks

    cached = cached_keys(cache_dir)
    keys = {t.key() for ts in experiment_tasks(profile, parse_experiments(CLAIM_EXPERIMENTS)).values() for t in ts}
    return len(keys - cached)


def _sha256(path: str) -> str:
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def record_files(profile_name: str) -> list[str]:
    """The file names this command writes for a profile, provenance included."""
    names = [f"{r}-{profile_name}.csv" for r in DOWNLOADS]
    names += [f"{r}-{profile_name}{suffix}" for r, suffix in REPRODUCED]
    names += [f"{r}-{profile_name}.csv" for r in COMPUTED]
    return [*names, PROVENANCE]


def reproduced_tables(profile, cache_dir: str, folder: str, progress: bool) -> dict[str, str]:
    """The claims table (``claims.csv``, ``claims.md``) and the robustness
    table of :data:`CLAIM_EXPERIMENTS`, written into `folder` from the cache
    (:func:`mat_hopper.experiments.reproduce.reproduce`, figures included as
    the claims need them); record file name -> path written."""
    from ..experiments.reproduce import reproduce

    reproduce(profile, CLAIM_EXPERIMENTS, folder, cache_dir=cache_dir, progress=progress, log=lambda *_: None)
    return {f"{r}-{profile.name}{suffix}": os.path.join(folder, name) for (r, suffix), name in REPRODUCED.items()}


def crossed_table(profile, cache_dir: str) -> pd.DataFrame:
    """Chapter 9c's crossed legs (:mod:`mat_hopper.experiments.crossed_legs`)
    as their factorial of paired contrasts
    (:func:`mat_hopper.analysis.factorial.factorial_effects`, the claim its own
    Holm family), over :data:`CROSSED_METRICS`, from cached runs only.

    Raises:
        ValueError: a run of the grid not in the cache.
    """
    from ..analysis.factorial import factorial_effects
    from ..analysis.stats import drop_unusable, unusable_runs
    from ..experiments import crossed_legs
    from ..experiments.plan import cached_keys
    from ..experiments.runner import run_grid

    tasks = crossed_legs.tasks(profile)
    missing = {t.key() for t in tasks} - cached_keys(cache_dir)
    if missing:
        raise ValueError(f"{len(missing)} crossed-leg runs (chapter 09c) are not in {cache_dir}: build the book first")
    grid = run_grid(tasks, cache_dir, progress=False, desc="crossed legs")
    usable = drop_unusable(grid.tables, unusable_runs(grid.summary))
    means = usable.groupby(["leg", "replicate"])[list(CROSSED_METRICS)].mean()
    return factorial_effects(means, crossed_legs.CONTRASTS, metrics=CROSSED_METRICS, alone=(crossed_legs.CLAIM,))


def computed_tables(profile, cache_dir: str, studies_dir: str, folder: str) -> dict[str, tuple[str, str]]:
    """The crossed legs' factorial (chapter 9c) and the optimizer's
    validated verdicts and paired comparisons (chapter 9,
    :func:`mat_hopper.optimize.book_record_tables`: its finished study and
    cached validation runs), written into `folder`; record file name ->
    (path, how it was made)."""
    from ..optimize import book_record_tables
    from ..optimize.validate import RECORD_FLOAT_FORMAT

    out = {}
    path = os.path.join(folder, "crossed.csv")
    write_csv(crossed_table(profile, cache_dir), path)
    out[f"crossed-legs-{profile.name}.csv"] = (path, "experiments.crossed_legs + analysis.factorial (chapter 09c)")
    verdicts, paired = book_record_tables(studies_dir, cache_dir, profile)
    for record, table in (("optimizer", verdicts), ("optimizer-paired", paired)):
        path = os.path.join(folder, f"{record}.csv")
        table.to_csv(path, index=False, float_format=RECORD_FLOAT_FORMAT)  # the records' digits; copied atomically
        out[f"{record}-{profile.name}.csv"] = (path, "optimize.book_record_tables (chapter 09)")
    return out


def downloaded_tables(build_dir: str, profile_name: str) -> dict[str, tuple[str, str]]:
    """The record files the chapters wrote as downloads into `build_dir`;
    record file name -> (path, how it was made).

    Raises:
        ValueError: a download missing, named with its chapter.
    """
    found = {}
    for record, (name, chapter) in DOWNLOADS.items():
        path = os.path.join(build_dir, f"{name}.csv")
        if not os.path.isfile(path):
            raise ValueError(
                f"--build {build_dir}: no {name}.csv (chapter {chapter} writes it): build the book first "
                f"(make book PROFILE={profile_name})"
            )
        found[f"{record}-{profile_name}.csv"] = (path, f"download {name}.csv of chapter {chapter}")
    return found


def write_records(sources: dict[str, tuple[str, str]], out_dir: str, profile: str, commit: str) -> pd.DataFrame:
    """Copy each source into `out_dir` under its record name, atomically, and
    write ``provenance.csv`` (record, made_from, profile, commit, sha256).

    Args:
        sources: record file name -> (path of the table, how it was made).
        out_dir: the records folder.
        profile: the profile's name.
        commit: the build's commit.

    Returns:
        The provenance table written.
    """
    os.makedirs(out_dir, exist_ok=True)
    rows = []
    for record, (path, made_from) in sorted(sources.items()):
        dst = os.path.join(out_dir, record)
        with atomic_path(dst) as tmp:  # the project's one atomic write
            shutil.copyfile(path, tmp)
        rows.append(
            {"record": record, "made_from": made_from, "profile": profile, "commit": commit, "sha256": _sha256(dst)}
        )
    table = pd.DataFrame(rows, columns=["record", "made_from", "profile", "commit", "sha256"])
    write_csv(table, os.path.join(out_dir, PROVENANCE))
    return table


def cmd_records(args) -> int:
    profile = profile_of(args.profile)
    from ._checks import cache_folder

    cache, flag = cache_folder(args.cache)
    build_dir = args.build or os.path.join("results", profile.name)
    folders = (
        (cache, f"{flag} {cache}"),
        (build_dir, f"--build {build_dir}"),
        (args.studies, f"--studies {args.studies}"),
    )
    for path, what in folders:  # the build first: without one, --out and --force are beside the point
        if os.path.exists(path) and not os.path.isdir(path):
            raise ValueError(f"{what}: is a file, not a folder")
        if not os.path.isdir(path):
            raise ValueError(f"{what} does not exist: build the book first (make book PROFILE={profile.name})")
    check_output_dir(args.out, "--out")
    check_no_outputs_in(args.out, record_files(profile.name), "--out", force=args.force)
    sources = downloaded_tables(build_dir, profile.name)  # before any work
    missing = missing_runs(profile, cache)
    if missing:
        raise ValueError(
            f"{missing} runs of experiments {CLAIM_EXPERIMENTS} are not in {cache}: build the book first "
            f"(make book PROFILE={profile.name}, or mat-hopper plan --profile {profile.name} --run)"
        )
    commit = args.commit or build_commit(".")
    with tempfile.TemporaryDirectory() as tmp:
        sources.update(computed_tables(profile, cache, args.studies, tmp))  # refuses missing runs first
        made = reproduced_tables(profile, cache, tmp, progress=not args.no_progress)
        sources.update({r: (p, f"mat-hopper reproduce --experiments {CLAIM_EXPERIMENTS}") for r, p in made.items()})
        table = write_records(sources, args.out, profile.name, commit)
    print(f"wrote {len(table)} records into {args.out} (profile {profile.name}, commit {commit}), and {PROVENANCE}")
    return 0


def register_cli(sub) -> None:
    p = sub.add_parser(
        "records",
        help=HELP,
        description="Rebuild the recorded results of the book (book/records/) from one finished book build: "
        "the tables its chapters wrote into the build's folder, and the claims and robustness tables from its "
        "result cache, every file atomically, with provenance.csv naming the build's commit. Nothing long is "
        "computed: runs missing from the cache are refused before any work.",
    )
    add_profile(p)
    p.add_argument(
        "--cache", default=None, help=f"the build's result cache (default ${CACHE_ENV}, else {DEFAULT_CACHE_DIR})"
    )
    p.add_argument("--studies", default="studies", help="the build's optimizer studies folder (default studies)")
    p.add_argument("--build", default=None, help="the build's folder of tables (default results/<profile>)")
    p.add_argument("--out", default=os.path.join("book", "records"), help="the records folder (default book/records)")
    p.add_argument("--commit", default=None, help="the build's commit (default: this working tree's)")
    add_no_progress(p)
    add_force(p)
    p.set_defaults(func=cmd_records)
