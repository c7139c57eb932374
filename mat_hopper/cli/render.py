"""``mat-hopper render``: the command line of
:func:`mat_hopper.viz.render.render_files`."""

from __future__ import annotations

import math
import sys

from ..sim import is_auto
from ..viz.render import (
    _LIBS,
    IMAGE_EXTENSIONS,
    VIDEO_EXTENSIONS,
    RenderBackendError,
    choose_backend,
    parse_size,
    render_files,
)
from ..viz.render import _check_extension as check_extension
from ._checks import check_distinct_outputs, check_output_file
from .simulate import add_sim_arguments, describe_settings, design_from_args, sim_settings_from_args


def cmd_render(args) -> int:
    if not args.tiles and not args.video and not args.still:
        raise ValueError("nothing to render: give --tiles FILE, --video FILE and/or --still FILE")
    for flag, allowed in (("tiles", IMAGE_EXTENSIONS), ("video", VIDEO_EXTENSIONS), ("still", IMAGE_EXTENSIONS)):
        if check_output_file(getattr(args, flag), f"--{flag}"):
            try:
                check_extension(getattr(args, flag), allowed)
            except ValueError as e:
                raise ValueError(f"--{flag}: {e}") from None
    check_distinct_outputs(tiles=args.tiles, video=args.video, still=args.still)
    size = parse_size(args.size)
    design = design_from_args(args)
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
    seconds = max(args.seconds, args.tile_start + 1.0)
    length = "--start + --seconds" if args.seconds >= args.tile_start + 1.0 else "--start + --tile-start + 1 s"
    settings = sim_settings_from_args(args, design, args.start + seconds, 0.0, duration_flag=length)
    try:  # a named error before any work
        backend = choose_backend({"MUJOCO_GL": args.backend} if args.backend else None)
    except RenderBackendError as e:
        print(f"mat-hopper render: error: {e}", file=sys.stderr)
        return 3
    print(f"{design.name} on {args.behaviour}: {describe_settings(settings, is_auto(str(args.timestep)))}")
    for path in render_files(
        design,
        args.behaviour,
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
    ):
        print(f"wrote {path}")
    return 0


def register_cli(sub) -> None:
    p = sub.add_parser(
        "render",
        help="render gait tiles, a video or a still of a design, off-screen",
        description="Render gait tiles (PNG), a video (MP4 or GIF) or a still of one design "
        "on one behaviour, off-screen (OSMesa by default, EGL with MUJOCO_GL=egl).",
    )
    add_sim_arguments(p)
    p.add_argument("--tiles", help="gait-tile figure to write (.png, .svg, .pdf, .jpg)")
    p.add_argument("--video", help="video to write (.mp4 or .gif)")
    p.add_argument("--still", help="picture of the model at rest to write (.png, .jpg)")
    p.add_argument("--seconds", type=float, default=10.0, help="simulated seconds of video (10)")
    p.add_argument("--start", type=float, default=0.0, help="video starts at this simulated time, s (0)")
    p.add_argument("--tile-start", type=float, default=5.0, help="gait tiles start this many seconds after --start (5)")
    p.add_argument("--fps", type=float, default=30.0, help="video frames per simulated second (30)")
    p.add_argument("--size", default="640x480", help="video and still size WIDTHxHEIGHT in pixels")
    p.add_argument(
        "--backend",
        choices=tuple(_LIBS),
        default=None,
        help="OpenGL backend (default: $MUJOCO_GL if osmesa or egl, else osmesa, else egl)",
    )
    p.set_defaults(func=cmd_render)
