"""Off-screen rendering (OSMesa in CI): pictures, determinism, videos,
colours by material, and a named error when no GL library exists."""

import imageio.v3 as iio
import numpy as np
import pytest
from conftest import run_python

from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.materials import parse_design
from mat_hopper.core.sim import simulate
from mat_hopper.viz.render import (
    Camera,
    OffscreenRenderer,
    RenderBackendError,
    choose_backend,
    density_color,
    gait_tiles,
    parse_size,
    render_frames,
    render_spec,
    render_still,
    save_video,
    standing_qpos,
    video_times,
    write_video,
)

SIZE = (160, 120)


@pytest.fixture(scope="module")
def rollout():
    return simulate("rho-inc", "ramp", duration_s=1.5, transient_s=0.0, record_qpos=True)


def test_frames_have_shape_and_show_the_hopper(rollout):
    frames = render_frames(rollout, [0.5, 1.0], size=SIZE)
    assert frames.shape == (2, 120, 160, 3) and frames.dtype == np.uint8
    # The same scene with the camera turned away from the hopper differs where the hopper is.
    empty = render_frames(rollout, [0.5], size=SIZE, camera=Camera(elevation_deg=80.0, height_m=-5.0))
    assert np.abs(frames[0].astype(int) - empty[0]).sum(axis=2).astype(bool).mean() > 0.05
    assert frames[0].std() > 10  # not a blank image


def test_same_rollout_same_pixels(rollout):
    a = render_frames(rollout, [0.7], size=SIZE)
    b = render_frames(rollout, [0.7], size=SIZE)
    assert np.array_equal(a, b)


def test_video_has_the_expected_frames(rollout, tmp_path):
    frames = render_frames(rollout, video_times(rollout, start_s=0.0, seconds=1.0, fps=10), size=SIZE)
    assert len(frames) == 11
    mp4 = write_video(frames, str(tmp_path / "hop.mp4"), fps=10)
    gif = write_video(frames, str(tmp_path / "hop.gif"), fps=10)
    assert len(iio.imread(gif, index=None)) == 11
    import imageio.v2 as imageio

    with imageio.get_reader(mp4) as r:
        assert r.count_frames() == 11
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hop.gif", "hop.mp4"]


def test_graded_leg_segments_have_different_colours():
    colours = [tuple(density_color(d)) for d in (1.39, 4.43, 8.0)]
    assert len(set(colours)) == 3
    # and they reach the picture: the still of rho-inc holds each segment's colour
    img = render_still("rho-inc", size=(320, 240)).reshape(-1, 3).astype(int)
    for c in colours:
        target = (np.array(c[:3]) * 255).astype(int)
        assert (np.abs(img - target).max(axis=1) < 40).sum() > 3, c
    mono = render_still("SS", size=(320, 240)).reshape(-1, 3).astype(int)
    purple = (np.array(colours[0][:3]) * 255).astype(int)
    assert (np.abs(mono - purple).max(axis=1) < 20).sum() == 0


def test_gait_tiles_figure(rollout):
    fig = gait_tiles("rho-inc", "ramp", rollout=rollout, start_s=0.5, seconds=0.7, n_frames=4, size=(80, 120))
    assert fig.frames.shape == (4, 120, 80, 3)
    assert "3.5 % ramp" in fig.axes[0].get_title()


def test_missing_gl_library_is_named():
    none = lambda name: None  # noqa: E731
    with pytest.raises(RenderBackendError, match="libOSMesa.*libosmesa6.*libEGL"):
        choose_backend({}, find_library=none)
    with pytest.raises(RenderBackendError, match="MUJOCO_GL=egl but libEGL"):
        choose_backend({"MUJOCO_GL": "egl"}, find_library=none)
    only_egl = lambda name: "libEGL.so.1" if name == "EGL" else None  # noqa: E731
    assert choose_backend({}, find_library=only_egl) == "egl"
    assert choose_backend({}, find_library=lambda n: "x") == "osmesa"


def test_bad_input(tmp_path, rollout):
    with pytest.raises(ValueError, match="WIDTHxHEIGHT"):
        parse_size("big")
    with pytest.raises(ValueError, match="fps"):
        save_video("SS", "forward", str(tmp_path / "a.mp4"), fps=0)
    with pytest.raises(ValueError, match="unknown file type '.avi'"):
        save_video("SS", "forward", str(tmp_path / "a.avi"))
    with pytest.raises(ValueError, match="record_qpos"):
        render_frames(simulate("SS", "static", duration_s=0.2, transient_s=0.0), [0.1])
    assert list(tmp_path.iterdir()) == []


def test_cli_render_writes_files_and_rejects_bad_input(tmp_path):
    from mat_hopper.cli import main

    tiles, video = tmp_path / "t.png", tmp_path / "v.gif"
    assert (
        main(
            [
                "render",
                "--design",
                "PVC-Ti-SS",
                "--behaviour",
                "forward",
                "--tiles",
                str(tiles),
                "--video",
                str(video),
                "--seconds",
                "1",
                "--tile-start",
                "0.2",
                "--fps",
                "5",
                "--size",
                "96x64",
            ]
        )
        == 0
    )
    assert tiles.stat().st_size > 1000 and len(iio.imread(video, index=None)) == 6
    assert main(["render", "--design", "SS", "--video", str(tmp_path / "x.mp4"), "--size", "10"]) == 2
    assert main(["render", "--design", "SS", "--video", str(tmp_path / "x.mov")]) == 2
    assert not (tmp_path / "x.mp4").exists() and not (tmp_path / "x.mov").exists()


def test_lights_are_placed_and_the_key_light_follows_the_hopper(rollout):
    model = render_spec(rollout.design, rollout.behaviour, width=64, height=48).compile()
    with OffscreenRenderer(model, 64, 48) as r:
        lit = r.frame(rollout.qpos[500], Camera(), rollout.behaviour)
        dirs = r.data.light_xdir.copy()
        key = r.data.light_xpos[model.light("key").id] - r.data.subtree_com[0]
    assert np.all(np.linalg.norm(dirs, axis=1) > 0.99)  # no light left without a direction
    assert np.linalg.norm(key) > 1.0 and lit.std() > 10  # placed relative to the centre of mass


@pytest.mark.parametrize("name", ["static", "ramp"])
def test_still_pose_stands_on_the_terrain(name):
    """The foot touches the ground or ramp as MuJoCo's own geometry sees it."""
    import mujoco

    beh = behaviour(name)
    model = render_spec(parse_design("SS"), beh, width=64, height=48).compile()
    d = mujoco.MjData(model)
    d.qpos[:] = standing_qpos(model, beh)
    mujoco.mj_kinematics(model, d)
    terrain = [g for g in ("ground", "ramp") if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, g) >= 0]
    gaps = [mujoco.mj_geomDistance(model, d, model.geom("foot").id, model.geom(g).id, 1.0, None) for g in terrain]
    assert abs(min(gaps)) < 1e-6, dict(zip(terrain, gaps))


def test_save_video_streams_an_mp4(rollout, tmp_path):
    import imageio.v2 as imageio

    path = save_video(None, None, str(tmp_path / "s.mp4"), rollout=rollout, seconds=0.5, fps=8, size=SIZE)
    with imageio.get_reader(path) as r:
        assert r.count_frames() == 5  # t = 0, 1/8, ..., 4/8 s
    assert [p.name for p in tmp_path.iterdir()] == ["s.mp4"]


def test_cli_names_the_missing_gl_library(tmp_path):
    out = tmp_path / "t.png"
    code = (
        "import ctypes.util, sys; ctypes.util.find_library = lambda name: None\n"
        "from mat_hopper.cli import main\n"
        f"sys.exit(main(['render', '--design', 'SS', '--still', {str(out)!r}]))"
    )
    res = run_python(code, {"MUJOCO_GL": "", "PYOPENGL_PLATFORM": ""}, timeout=120)
    assert res.returncode == 3, res.stderr
    assert "libOSMesa" in res.stderr and "libosmesa6" in res.stderr and "libEGL" in res.stderr
    assert "Traceback" not in res.stderr and not out.exists()


def test_an_rgb_picture_to_a_vector_file_is_refused_before_any_work(tmp_path, monkeypatch):
    from mat_hopper.cli import main
    from mat_hopper.viz import render

    rgb = np.zeros((4, 4, 3), dtype=np.uint8)
    for ext in (".svg", ".pdf"):
        with pytest.raises(ValueError, match=rf"unknown file type '\{ext}'.*accepted: .png, .jpg, .jpeg$"):
            render.save_image(rgb, str(tmp_path / f"s{ext}"))
    assert list(tmp_path.iterdir()) == []
    assert render.save_image(rgb, str(tmp_path / "s.png")) == str(tmp_path / "s.png")  # a raster file still works

    def no_rendering(*args, **kwargs):
        raise AssertionError("rendered before the still's file type was checked")

    monkeypatch.setattr(render, "render_still", no_rendering)
    monkeypatch.setattr(render, "record", no_rendering)
    with pytest.raises(ValueError, match=r"unknown file type '\.svg'"):
        render.render_files("SS", "static", still=str(tmp_path / "still.svg"), tiles=str(tmp_path / "t.png"))
    assert main(["render", "--design", "SS", "--still", str(tmp_path / "still.pdf")]) == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.png"]


@pytest.fixture(scope="module")
def diverged():
    # SS at 1e-3 s: above its springs' bound (1.26e-4 s); it diverges a few ms in
    return simulate("SS", "forward", duration_s=1.0, timestep_s=1e-3, transient_s=0.0, record_qpos=True, warn=False)


def _tile_times(fig) -> list[float]:
    return [float(t.get_text().split()[2]) for t in fig.axes[0].texts]


def test_tiles_stop_at_a_divergence_marked_and_time_runs_forward(diverged, rollout):
    r = diverged
    assert r.diverged and r.diverged_at_s < 0.05
    fig = gait_tiles("SS", "forward", rollout=r, start_s=0.0, n_frames=4, size=(40, 60))
    times = _tile_times(fig)
    assert times == sorted(times) and times[0] == 0.0 and times[-1] > 0.0  # forward, a few ms apart, told apart
    assert times[-1] <= r.diverged_at_s and fig.axes[0].texts[-1].get_text().endswith("(diverged)")
    assert f"diverged at t = {r.diverged_at_s:.4f} s, the frames end there" in fig.axes[0].get_title()
    # a window after the divergence (or after a stable run's end) is refused, never frozen poses backwards
    with pytest.raises(
        ValueError, match=r"nothing to draw: the tiles start at 5 s, after the run diverged at t = 0\.0"
    ):
        gait_tiles("SS", "forward", rollout=r, start_s=5.0, size=(40, 60))
    with pytest.raises(ValueError, match="nothing to draw: the tiles start at 5 s, after the run ends at 1.49"):
        gait_tiles("rho-inc", "ramp", rollout=rollout, start_s=5.0, size=(40, 60))
    with pytest.raises(ValueError, match="nothing to draw: frames start at 0.5 s, after the run diverged"):
        render_frames(r, [0.5], size=(40, 60))
    assert video_times(r, start_s=0.0, seconds=1.0, fps=240)[-1] <= r.diverged_at_s
    stable = _tile_times(gait_tiles("rho-inc", "ramp", rollout=rollout, start_s=0.5, n_frames=3, size=(40, 60)))
    assert stable == [0.5, 0.85, 1.2]


def test_cli_render_of_a_diverging_design_exits_1_and_draws_nothing_past_it(tmp_path, capsys):
    from mat_hopper.cli import main

    five = ["--density", "2.0,3.0,4.5,6.0,7.8", "--modulus", "50,80,110,150,200", "--behaviour", "forward"]
    tiles = tmp_path / "t.png"
    assert main(["render", *five, "--tiles", str(tiles)]) == 1  # the tiles start at 5 s; it diverges at 4.3 ms
    cap = capsys.readouterr()
    assert "mat-hopper render: warning: the physics step 0.0001 s is above" in cap.err
    assert "UNSTABLE: diverged at t = 0.0043 s (numerical divergence" in cap.out and "try --timestep auto" in cap.out
    assert f"tiles not written ({tiles}): its window starts at 5 s, after the run diverged at t = 0.0043 s" in cap.out
    assert not tiles.exists()
