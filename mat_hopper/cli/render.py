"""``mat-hopper render``: the command line of
:func:`mat_hopper.viz.render.render_files`."""

from __future__ import annotations

import math
import sys

from ..core.behaviours import behaviour
from ..core.contact import DEFAULT_CONTACT
from ..core.damping import DEFAULT_DAMPING
from ..core.materials import DEFAULT_CONVENTION
from ..core.rollout import FELL_TILT_DEG
from ..core.timestep import CLI_AUTO_HINT, is_auto
from ..viz.render import (
    GL_LIBS,
    IMAGE_EXTENSIONS,
    RASTER_EXTENSIONS,
    VIDEO_EXTENSIONS,
    RenderBackendError,
    check_extension,
    check_fps,
    check_mp4_size,
    choose_backend,
    parse_size,
    record,
    render_files,
)
from ._checks import check_distinct_paths, check_output_file, named_by_flags
from ._options import add_force, add_no_progress, add_profile, profile_of
from .simulate import (
    EXIT_STATUS,
    add_sim_arguments,
    describe_settings,
    design_from_args,
    sim_settings_from_args,
    stable_step_warning,
    unstable_line,
)

# Which outputs use each picture option: given without any of them, it is
# refused (it would be silently ignored). Defaults apply when left out.
PICTURE_OPTIONS = {
    "fps": (("video",), 30.0),
    "seconds": (("video",), 10.0),
    "size": (("video", "still"), "640x480"),  # gait tiles have their own frame size
    "start": (("video", "tiles"), 0.0),
    "tile_start": (("tiles",), 5.0),
}
# A still pictures the leg at rest: nothing is simulated, so run settings have no use.
RUN_DEFAULTS = {
    "convention": DEFAULT_CONVENTION,
    "sensor_timing": "authors",
    "segment_mass": "leg",
    "damping": DEFAULT_DAMPING,
    "contact": DEFAULT_CONTACT,
}


def _flag(dest: str) -> str:
    return "--" + dest.replace("_", "-")


def _check_options(args) -> None:
    """Every option given is used by an output asked for (or the pair is
    refused, one line); then the defaults of those left out."""
    asked = [o for o in ("tiles", "video", "still") if getattr(args, o)]
    for dest, (outputs, default) in PICTURE_OPTIONS.items():
        if getattr(args, dest) is None:
            setattr(args, dest, default)
        elif not any(getattr(args, o) for o in outputs):
            users = " or ".join(_flag(o) for o in outputs)
            verb = "does" if len(asked) == 1 else "do"
            raise ValueError(f"{_flag(dest)} is for {users}; {' and '.join(map(_flag, asked))} {verb} not use it")
    for dest, default in (("timestep", None), ("profile", None), *RUN_DEFAULTS.items()):
        if getattr(args, dest) is not None and asked == ["still"]:
            raise ValueError(f"{_flag(dest)} is for --video and --tiles (a run); --still pictures the leg at rest")
        if getattr(args, dest) is None:
            setattr(args, dest, default)


def cmd_render(args) -> int:
    if not args.tiles and not args.video and not args.still:
        raise ValueError("nothing to render: give --tiles FILE, --video FILE and/or --still FILE")
    check_distinct_paths(  # never over the input table, with --force or not
        {"--tiles": args.tiles, "--video": args.video, "--still": args.still}, {"--design-csv": args.design_csv}
    )
    for flag, allowed in (("tiles", IMAGE_EXTENSIONS), ("video", VIDEO_EXTENSIONS), ("still", RASTER_EXTENSIONS)):
        if check_output_file(getattr(args, flag), f"--{flag}", force=args.force):
            try:
                check_extension(getattr(args, flag), allowed)
            except ValueError as e:
                raise ValueError(f"--{flag}: {e}") from None
    _check_options(args)
    profile_of(args.profile)  # an unknown --profile (or $MAT_HOPPER_PROFILE) before any work
    with named_by_flags(size="--size", fps="--fps"):  # the library's words, the options' names
        size = parse_size(args.size)
        check_fps(args.fps)
        if args.video and args.video.lower().endswith(".mp4"):
            check_mp4_size(size)
    design = design_from_args(args)
    beh = behaviour(args.behaviour)
    # every run setting (time step or auto, sensor timing, segment mass) and the
    # run size are checked here, before any work: the run simulates start + the
    # longer of the video and the tile window
    for flag, v, ok, need in (
        ("--seconds", args.seconds, args.seconds > 0, "> 0"),
        ("--start", args.start, args.start >= 0, ">= 0"),
        ("--tile-start", args.tile_start, args.tile_start >= 0, ">= 0"),
    ):
        if not (math.isfinite(v) and ok):
            raise ValueError(f"{flag} must be {need} simulated seconds, got {v!r}")
    seconds, length = _run_length(args)
    settings = sim_settings_from_args(args, design, args.start + seconds, 0.0, duration_flag=length)
    if args.seconds < settings.control_period_s:  # a video of no step
        raise ValueError(
            f"--seconds must be at least one control period, {settings.control_period_s:g} s, got {args.seconds:g} s"
        )
    try:  # a named error before any work
        backend = choose_backend({"MUJOCO_GL": args.backend} if args.backend else None)
    except RenderBackendError as e:
        print(f"mat-hopper render: error: {e}", file=sys.stderr)
        return 3
    print(f"{design.name} on {beh.name}: {describe_settings(settings, is_auto(str(args.timestep)))}")
    rollout = _run(args, design, beh, settings, seconds) if (args.tiles or args.video) else None
    for path in render_files(
        design,
        beh,
        tiles=args.tiles,
        video=args.video,
        still=args.still,
        seconds=args.seconds,
        start_s=args.start,
        tile_start_s=args.tile_start,
        fps=args.fps,
        size=size,
        backend=backend,
        settings=settings,
        rollout=rollout,
        progress=not args.no_progress,
    ):
        print(f"wrote {path}")
    bad = rollout is not None and (rollout.diverged or rollout.suspect)
    return 1 if bad else 0  # a diverged or numerically suspect run: exit 1, as every command


def _run_length(args) -> tuple[float, str]:
    """The seconds simulated after --start, and the options that set them
    (named in errors): a video's --seconds, the tiles' --tile-start + 1 s
    (their window), the longer of the two when both are asked for."""
    if not args.video and not args.tiles:  # a still alone: no run is made
        return max(args.seconds, args.tile_start + 1.0), "--start + --seconds"
    video, tiles = args.seconds if args.video else 0.0, args.tile_start + 1.0 if args.tiles else 0.0
    if video >= tiles:
        return video, "--start + --seconds"
    return tiles, "--start + --tile-start + 1 s"


def _run(args, design, beh, settings, seconds: float):
    """The run the tiles and the video show, its step checked against the
    leg's analytic bound first (a warning line); a divergence is told in
    one line (when, why, what to try), and nothing past it is drawn."""
    from ..core.timestep import CLI_CONTACT_HINT, soft_contact_note

    stable_step_warning("render", design, settings)
    rollout = record(design, beh, seconds, start_s=args.start, settings=settings, warn=False)  # the lines say it
    if rollout.diverged:
        print(unstable_line(rollout))
    elif rollout.suspect:  # drawn, but its motion is the integrator's, not the hopper's
        print(f"SUSPECT: {rollout.suspect_message(CLI_AUTO_HINT)}")
    if rollout.stable and rollout.fell_at_s is not None:  # drawn, but a hopper down is no gait: tiles and video say so
        # a bending leg on the soft contact: why, what to try
        note = soft_contact_note(design, settings, CLI_CONTACT_HINT)
        print(
            f"note: the hopper fell at t = {rollout.fell_at_s:.3f} s (base tilted past {FELL_TILT_DEG:g} deg); "
            "tiles after it are marked (fell), and the video's line counts its frames after the fall"
            + (f"; {note}" if note else "")
        )
    return rollout


def register_cli(sub) -> None:
    p = sub.add_parser(
        "render",
        help="render gait tiles, a video or a still of a design, off-screen",
        description="Render gait tiles (PNG), a video (MP4 or GIF) or a still of one design "
        "on one behaviour, off-screen (OSMesa by default, EGL with MUJOCO_GL=egl). A time step above the design's "
        "analytic stable step is warned of (try --timestep auto); nothing past a divergence is drawn: the tiles "
        f"and the video stop there (the tiles marked); tiles after a fall are marked (fell). --profile sets only "
        f"the time step (the run lasts --start + --seconds, or + --tile-start + 1 s for the tiles). {EXIT_STATUS} "
        "Exit status 3: no usable off-screen OpenGL.",
    )
    add_sim_arguments(p)
    add_profile(p)
    add_no_progress(p)
    p.add_argument("--tiles", help="gait-tile figure to write (.png, .svg, .pdf, .jpg)")
    p.add_argument("--video", help="video to write (.mp4 or .gif)")
    p.add_argument("--still", help="picture of the model at rest to write (.png, .jpg)")
    add_force(p)
    p.add_argument("--seconds", type=float, default=None, help="simulated seconds of video (10)")
    p.add_argument("--start", type=float, default=None, help="video and tiles start at this simulated time, s (0)")
    p.add_argument(
        "--tile-start", type=float, default=None, help="gait tiles start this many seconds after --start (5)"
    )
    p.add_argument("--fps", type=float, default=None, help="video frames per simulated second (30)")
    p.add_argument("--size", default=None, help="video and still size WIDTHxHEIGHT in pixels (640x480)")
    p.add_argument(
        "--backend",
        choices=tuple(GL_LIBS),
        default=None,
        help="OpenGL backend (default: $MUJOCO_GL if osmesa or egl, else osmesa, else egl)",
    )
    # run settings left out stay None, so that a --still alone can refuse them (cmd_render sets the defaults)
    p.set_defaults(func=cmd_render, **dict.fromkeys(RUN_DEFAULTS))
