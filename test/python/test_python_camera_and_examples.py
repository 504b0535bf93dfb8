"""rov_tether.Camera and the examples of examples/python (issue 23, docs/python.md), run by scripts/test.sh with
pytest in the catkin build's environment."""
import math
import os
import pathlib
import subprocess
import sys
import time

import numpy as np
import pytest

import rov_tether

ROOT = pathlib.Path(__file__).resolve().parents[2]


def taut_world():
    """A 5 m tether held taut along x at z = -1 m between its spool at x = 0 and a vehicle at x = 5.01 m."""
    world = rov_tether.World({"spool": [0.0, 0.0, -1.0], "vehicle": [[0.0, 5.01, 0.0, -1.0]],
                              "params": {"cable_length": 10.0, "initial_deployed_length": 5.0, "winch_mode": "locked",
                                         "noise": 0.0, "diameter": 0.04}})
    world.advance_to(5.0)
    return world


# The camera d = 4 m from the tether's axis, looking along +y at it, level: its optical frame is the world's
# turned -90 degrees about x. The tether (radius r = 2 cm) then lies along the image row through the principal
# point, cy = 239.5: every tether pixel within r f / d = 2 px of it (and half a pixel of rasterisation), at
# depths between d - r and d + r; it spans the columns of x in [0, 5] m, u = cx + f (x - 2.5) / d, less a pixel
# at each end. The renderer itself is checked against closed forms in test_camera; this checks the binding:
# pose, frames, array shapes, types and units.
def test_a_camera_sees_a_taut_tether_where_the_pinhole_model_puts_it():
    world = taut_world()
    f, d, r = 400.0, 4.0, 0.02
    camera = rov_tether.Camera(640, 480, K=[f, 0.0, 319.5, 0.0, f, 239.5, 0.0, 0.0, 1.0])
    mask, depth = camera.render(world, [2.5, -d, -1.0], [-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)])
    assert mask.shape == (480, 640) and mask.dtype == np.uint8
    assert depth.shape == (480, 640) and depth.dtype == np.float32
    rows, columns = np.nonzero(mask)
    assert set(np.unique(mask)) == {0, 255}
    assert np.abs(rows - 239.5).max() <= r * f / d + 0.5
    seen = depth[mask > 0]
    assert np.all((seen >= d - r - 1e-3) & (seen <= d + r + 1e-3))
    assert np.all(np.isnan(depth[mask == 0]))
    first, last = 319.5 + f * (0.0 - 2.5) / d, 319.5 + f * (5.0 - 2.5) / d
    assert columns.min() <= first + 1.0 and columns.max() >= last - 1.0
    assert columns.min() >= first - r * f / d - 1.0 and columns.max() <= last + r * f / d + 1.0
    # Looking the other way (yawed half a turn about the world's z), it sees nothing.
    mask, depth = camera.render(world, [2.5, -d, -1.0], [0.0, -math.sqrt(0.5), math.sqrt(0.5), 0.0])
    assert not mask.any() and np.isnan(depth).all()


def test_a_bad_camera_raises():
    with pytest.raises(ValueError, match="K"):
        rov_tether.Camera(640, 480, K=[400.0, 0.0, 319.5])
    with pytest.raises(ValueError, match="width|height"):
        rov_tether.Camera(0, 480, K=[400.0, 0.0, 319.5, 0.0, 400.0, 239.5, 0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="distortion cannot be inverted"):
        rov_tether.Camera(640, 480, K=[400.0, 0.0, 319.5, 0.0, 400.0, 239.5, 0.0, 0.0, 1.0], D=[5.0, 5.0, 5.0, 5.0, 5.0])
    camera = rov_tether.Camera(64, 48, K=[40.0, 0.0, 31.5, 0.0, 40.0, 23.5, 0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="quaternion"):
        camera.render(taut_world(), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0])


def run_example(name, *arguments):
    """Runs examples/python/NAME headless; its output and how long it took [s]."""
    start = time.monotonic()
    done = subprocess.run([sys.executable, str(ROOT / "examples" / "python" / name), *map(str, arguments)],
                          capture_output=True, text=True, env=dict(os.environ, MPLBACKEND="Agg"), timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout, time.monotonic() - start


# The budget for each example in the suite: 30 s.
def test_the_pillar_example_plots_tension_and_wrap_turns(tmp_path):
    output, seconds = run_example("pillar_tension.py", "--out", tmp_path)
    assert "2.00 wrap turns" in output  # the scenario circles the pillar twice, counter-clockwise
    assert (tmp_path / "pillar_tension.png").stat().st_size > 10000
    assert seconds < 30.0


def test_the_planner_example_chooses_the_path_that_unwinds():
    output, seconds = run_example("choose_path.py")
    assert "straight home wrap turns +1.00" in output
    assert "chosen: unwind first" in output
    assert seconds < 30.0


def test_the_dataset_example_writes_masks_depth_and_an_index(tmp_path):
    output, seconds = run_example("tether_dataset.py", "--out", tmp_path, "--seconds", 20)
    rows = (tmp_path / "index.csv").read_text().splitlines()
    assert rows[0] == "frame,t,mask,pixels,nearest_m,deployed_length_m" and len(rows) == 1 + 21
    depth = np.load(tmp_path / "depth.npz")
    assert len(depth.files) == 21 and depth["depth_0020"].shape == (480, 640)
    from PIL import Image
    mask = np.array(Image.open(tmp_path / "mask_0020.png"))
    assert mask.dtype == np.uint8 and mask.shape == (480, 640)
    pixels = int(rows[-1].split(",")[3])
    assert pixels == np.count_nonzero(mask) > 0
    assert np.count_nonzero(np.isfinite(depth["depth_0020"])) == pixels
    assert seconds < 30.0
