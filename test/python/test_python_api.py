"""The Python API (import rov_tether; issue 23, docs/python.md), run by scripts/test.sh with pytest in the
catkin build's environment (its devel space on PYTHONPATH). ROV_TETHER_RUN names the runner to compare with
(default: the catkin build's)."""
import copy
import csv
import math
import os
import pathlib
import signal
import subprocess
import sys
import threading
import time
import warnings

import numpy as np
import pytest

import rov_tether

ROOT = pathlib.Path(__file__).resolve().parents[2]
RUNNER = os.environ.get("ROV_TETHER_RUN", str(ROOT / "catkin_build" / "devel" / "lib" / "rov_tether" / "rov_tether_run"))


def run_scenario(path, out):
    """rov_tether_run PATH --out OUT; its stdout and stderr, and whether it succeeded."""
    done = subprocess.run([RUNNER, str(path), "--out", str(out)], capture_output=True, text=True)
    return done.returncode == 0, done.stdout + done.stderr


def shape_rows(path):
    """shape.csv as {t: (positions N x 3, tensions N - 1)}."""
    rows = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            positions, tensions = rows.setdefault(float(row["t"]), ([], []))
            positions.append([float(row["x"]), float(row["y"]), float(row["z"])])
            if row["tension"]:
                tensions.append(float(row["tension"]))
    return {t: (np.array(p), np.array(s)) for t, (p, s) in rows.items()}


# The runner prints positions with 6 decimals (%.6f) and tensions with 6 significant digits (%.6g): the same
# state read through Python must match to that rounding, so the bounds are half a unit of the last digit
# (plus a little for the binary value of the decimal). The two step the world by the same calls
# (ScenarioStepper), so any larger difference is a different simulation.
@pytest.mark.parametrize("scenario", ["pillar_wrap.yaml", "two_rovs.yaml", "dynamic_dive.yaml"])
def test_a_scenario_from_python_gives_the_runners_shapes_and_tensions(scenario, tmp_path):
    ok, output = run_scenario(ROOT / "scenarios" / scenario, tmp_path)
    assert ok, output
    world = rov_tether.World.from_scenario(str(ROOT / "scenarios" / scenario))
    names = [t.name for t in world.tethers]
    single = names == ["tether"] and not (tmp_path / "tether").exists()
    expected = {name: shape_rows(tmp_path / ("shape.csv" if single else name + "/shape.csv")) for name in names}
    times = sorted(next(iter(expected.values())))
    assert len(times) > 10
    for t in times:
        world.advance_to(t)
        for tether in world.tethers:
            positions, tensions = expected[tether.name][t]
            assert tether.positions.shape == positions.shape, (tether.name, t)
            np.testing.assert_allclose(tether.positions, positions, rtol=0, atol=5.1e-7, err_msg="%s at %g s" % (tether.name, t))
            np.testing.assert_allclose(tether.segment_tension, tensions, rtol=5.1e-6, atol=1e-12,
                                       err_msg="%s at %g s" % (tether.name, t))


def hanging_world():
    """A 5 m cable of 1 N/m in water hanging from a spool at 2 m depth with a free end: no path, no noise."""
    return rov_tether.World({"spool": [1.0, -2.0, -2.0],
                             "params": {"cable_length": 10.0, "initial_deployed_length": 5.0, "segment_length": 0.25,
                                        "weight_in_water": 1.0, "noise": 0.0, "winch_mode": "locked"}})


# A chain hanging in still water: segment k carries the weight in water of the particles below it, each
# particle a segment's (the free end half of one), so the spool's segment holds w (L - ds / 2) and the last
# w ds / 2; and the chain hangs straight down from the spool, as long as it is deployed (the stretch is
# w L / EA, 5e-5 here). 1% on the tensions and 1 mm on the line, after 40 s of water drag.
def test_arrays_have_the_documented_shapes_units_and_frames():
    world = hanging_world()
    world.advance_to(40.0)
    assert world.time == pytest.approx(40.0)
    (tether,) = world.tethers
    positions, tensions = tether.positions, tether.segment_tension
    assert positions.shape == (21, 3) and positions.dtype == np.float64
    assert isinstance(tensions, np.ndarray) and tensions.shape == (20,) and tensions.dtype == np.float64
    np.testing.assert_allclose(positions[0], [1.0, -2.0, -2.0])             # the spool, world frame, first
    np.testing.assert_allclose(positions[:, :2], np.tile([1.0, -2.0], (21, 1)), atol=1e-3)
    assert positions[-1, 2] == pytest.approx(-2.0 - 5.0, abs=1e-3)          # z up: the end below the spool
    assert tether.deployed_length == pytest.approx(5.0)
    assert tether.tension_spool == pytest.approx(1.0 * (5.0 - 0.125), rel=0.01)
    assert tether.tension_vehicle == pytest.approx(0.125, rel=0.01)
    # The spool's and the vehicle's tension are the array's ends (the summary reads the same segments).
    assert tensions[0] == tether.tension_spool and tensions[-1] == tether.tension_vehicle


def test_a_vehicle_driven_from_python_pulls_its_tether():
    world = hanging_world()
    (tether,) = world.tethers
    tether.add_vehicle_sample(0.0, [1.0, -2.0, -7.5])   # 0.5 m below the hanging end: the cable is pulled taut
    tether.add_vehicle_sample(30.0, [1.0, -2.0, -7.5])
    world.advance_to(30.0)
    np.testing.assert_allclose(tether.positions[-1], [1.0, -2.0, -7.5], atol=1e-9)
    # Taut between two points 5.5 m apart with 5 m of cable locked: a 10% stretch, so T = EA 0.1 = 1e4 N with the
    # default axial_stiffness EA = 1e5 N; its weight in water (5 N) moves it by 0.05%.
    assert tether.tension_vehicle == pytest.approx(1.0e5 * 0.1, rel=0.01)


# A speed-mode winch pays out at |winch_speed| towards its target and holds it there, reaching the speed at
# max_winch_acceleration (1 m/s^2, the default): from 5 m at 0.5 m/s it has paid out 0.5 t - 0.5^2 / 2 m after
# t >= 0.5 s (0.875 m at 2 s, within one step's pay-out at full speed, 0.5 m/s x 5 ms, for the discrete ramp),
# and it stops at the 7 m target.
def test_the_winch_pays_out_to_a_target_set_from_python():
    world = rov_tether.World({"spool": [0.0, 0.0, 0.0], "params": {"cable_length": 10.0, "initial_deployed_length": 5.0,
                                                                   "winch_mode": "speed", "winch_speed": 0.5}})
    (tether,) = world.tethers
    tether.set_target_length(7.0)
    world.advance_to(2.0)
    winch = tether.winch
    assert winch["mode"] == "speed" and winch["target_length"] == 7.0 and not winch["outrun"]
    assert winch["speed"] == pytest.approx(0.5)
    assert winch["deployed_length"] == pytest.approx(5.0 + 0.5 * 2.0 - 0.125, abs=2.5e-3) == tether.deployed_length
    world.advance_to(6.0)
    assert tether.deployed_length == pytest.approx(7.0, abs=1e-9)
    assert tether.winch["speed"] == 0.0
    with pytest.raises(ValueError):
        tether.set_target_length(50.0)  # beyond cable_length


# The hanging chain of test_arrays_...: doubling its weight in water between steps doubles what the spool holds.
def test_a_parameter_set_from_python_changes_the_physics(tmp_path):
    world = hanging_world()
    (tether,) = world.tethers
    world.advance_to(20.0)
    tether.set_param("weight_in_water", 2.0)
    world.advance_to(60.0)
    assert tether.tension_spool == pytest.approx(2.0 * (5.0 - 0.125), rel=0.01)
    path = tmp_path / "ok.yaml"
    path.write_text("spool: [0, 0, 0]\nduration: 0.1\n")
    done = subprocess.run([RUNNER, str(path), "--out", str(tmp_path / "out"), "--set", "no_such_parameter=1"],
                          capture_output=True, text=True)
    assert done.returncode != 0
    with pytest.raises(ValueError) as raised:
        tether.set_param("no_such_parameter", 1)
    assert str(raised.value) in done.stdout + done.stderr
    with pytest.raises(ValueError):
        tether.set_param("iterations", 0)


# A parameter that changes the cable's structure (segment_length 0.25 -> 0.125 m) is taken and lays the cable out
# anew at its deployed length: twice the segments on the same 5 m, said as a warning, not raised as a refusal
# (the refusal used to be raised after the change was made). The topology of the rebuilt cable reads before its
# next step and after it (the over-read of the old contact record that crashed it is
# Contact.ARebuiltCableHasTouchedNothingUntilItsNextStep's, which the sanitized build runs).
def test_a_parameter_that_rebuilds_the_cable_is_taken_with_a_warning():
    world = rov_tether.World({"spool": [0.0, 0.0, -1.0], "params": {"cable_length": 10.0, "initial_deployed_length": 5.0,
                                                                     "segment_length": 0.25, "noise": 0.0},
                              "obstacles": [{"name": "pillar", "type": "cylinder", "radius": 0.3, "length": 10,
                                             "position": [3.0, 0.0, -1.0]}]})
    (tether,) = world.tethers
    world.advance_to(1.0)
    assert len(tether.positions) == 5.0 / 0.25 + 1
    with pytest.warns(UserWarning, match="segment_length: cable rebuilt"):
        tether.set_param("segment_length", 0.125)
    assert len(tether.positions) == 5.0 / 0.125 + 1
    assert tether.deployed_length == pytest.approx(5.0)
    assert {entry["kind"] for entry in world.topology()} >= {"wrap_turns", "wrap_angle"}
    world.advance_to(2.0)
    assert {entry["kind"] for entry in world.topology()} >= {"wrap_turns", "wrap_angle"}


# A path that starts out of the tether's reach (30 m out on a locked winch with 8 m out: laid stretched, strain
# (30 - 8) / 8 = 2.75) is said to Python as a UserWarning when the World is built, as the runner prints it, and
# nothing reaches the process's stderr (the library printed it there: raw C stderr beside Python's own warnings).
def test_a_path_out_of_the_tethers_reach_is_a_python_warning(capfd):
    with pytest.warns(UserWarning, match=r"30 m from the spool, beyond the 8 m of cable .*\(strain 2.75\): its path "
                                         r"starts out of the tether's reach"):
        rov_tether.World({"spool": [0.0, 0.0, 0.0], "vehicle": [[0, 30, 0, 0], [1, 30, 0, 0]],
                          "params": {"winch_mode": "locked", "initial_deployed_length": 8.0, "noise": 0.0}})
    assert capfd.readouterr().err == ""


# The BlueROV2 Heavy (config/vehicles/bluerov2_heavy.yaml: Xu 13.7 N s/m, Xuu 141 N s^2/m^2) pushed by 20 N of surge
# from Python, its tether paying out behind it through a 1 N brake. Its time constant m' / (Xu + 2 Xuu U) is
# 0.2 s, so after 20 s it moves at the speed where the thrust less the tether's pull (the tension at the vehicle,
# along the surge axis) meets its drag: 20 - T = Xu U + Xuu U^2, within 1% (the pull grows with the cable paid
# out, a few mN/s of change in m' du/dt). Without the pull it would reach U0 (20 N = Xu U0 + Xuu U0^2), never more.
# The scenario's thrust schedule (zero) no longer applies once Python commands the thrust.
def test_a_dynamic_vehicle_takes_its_thrust_from_python():
    world = rov_tether.World({
        "spool": [0.0, 0.0, -1.0],
        "params": {"solver": "direct", "cable_length": 40.0, "initial_deployed_length": 3.0, "winch_mode": "brake",
                   "brake_tension": 1.0, "water_density": 1000.0},  # the vehicle file's fresh water
        "vehicle": {"model": "dynamic", "params": str(ROOT / "config" / "vehicles" / "bluerov2_heavy.yaml"),
                    "start": [3.0, 0.0, -1.0, 0.0], "wrench": [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]]}})
    (tether,) = world.tethers
    assert rov_tether.World({"spool": [0, 0, 0]}).tethers[0].vehicle is None
    world.advance_to(1.0)
    assert abs(tether.vehicle["velocity"][0]) < 0.05 and tether.vehicle["thrust"] == [0.0] * 6
    tether.set_vehicle_thrust([20.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    world.advance_to(21.0)
    state = tether.vehicle

    def steady(force):
        return (-13.7 + math.sqrt(13.7 ** 2 + 4.0 * 141.0 * force)) / (2.0 * 141.0)

    assert 0.5 < tether.tension_vehicle < 5.0  # the brake's 1 N and the cable's drag
    assert state["velocity"][0] == pytest.approx(steady(20.0 - tether.tension_vehicle), rel=0.01)
    assert state["velocity"][0] < steady(20.0)
    assert state["thrust"] == [20.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    assert math.fsum(q * q for q in state["orientation"]) == pytest.approx(1.0)
    np.testing.assert_allclose(tether.positions[-1], state["position"], atol=1e-9)  # attached at its origin
    with pytest.raises(ValueError, match="Fx"):
        tether.set_vehicle_thrust([1.0, 2.0])
    with pytest.raises(ValueError, match="no dynamic vehicle"):
        hanging_world().tethers[0].set_vehicle_thrust([0.0] * 6)
    # The tether's water changed after the attachment: said as the attachment says it (Tether::setParams).
    with pytest.warns(UserWarning, match="its water_density 1000 kg/m.3 is not the tether's 1025 kg/m.3"):
        tether.set_param("water_density", 1025.0)


def runner_error(tmp_path, text):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    ok, output = run_scenario(path, tmp_path / "out")
    assert not ok
    return path, output


@pytest.mark.parametrize("text", [
    "params: {iterations: -3}\nspool: [0, 0, 0]\nduration: 1.0\n",
    "spool: [0, 0]\nduration: 1.0\n",
    "spool: [0, 0, 0]\nduration: 1.0\nvehicle: [[0.0, 1.0, 0.0, 0.0], [-1.0, 2.0, 0.0, 0.0]]\n",
    "spool: [0, 0, 0]\nduration: 1.0\nobstacles: [{name: wreck, type: mesh, file: missing.stl}]\n",
    "spool: [0, 0, 0]\nduration: 1.0\nunknown_key: 1\n",
])
def test_bad_input_raises_with_the_runners_message(tmp_path, text):
    path, output = runner_error(tmp_path, text)
    with pytest.raises(ValueError) as raised:
        rov_tether.World.from_scenario(str(path))
    assert str(raised.value) in output
    assert len(str(raised.value)) > 10


def test_bad_calls_raise():
    world = hanging_world()
    (tether,) = world.tethers
    with pytest.raises(ValueError, match="finite"):
        world.advance_to(math.nan)
    with pytest.raises(ValueError, match="1e10"):
        world.advance_to(1e11)  # refused before the world sees it: the world goes on
    world.advance_to(1.0)
    with pytest.raises(ValueError, match="does not step back"):
        world.advance_to(0.5)
    with pytest.raises(ValueError, match="not negative"):
        world.step(-0.1)
    world.step(0.5)
    assert world.time == pytest.approx(1.5)
    with pytest.raises(KeyError, match="no tether named 'b'"):
        world.tether("b")
    with pytest.raises(ValueError, match=r"\[x, y, z\]"):
        tether.add_vehicle_sample(2.0, [1.0, 2.0])
    with pytest.raises(ValueError):
        tether.add_vehicle_sample(2.0, [math.nan, 0.0, 0.0])
    with pytest.raises(ValueError, match="vehicle path"):
        rov_tether.World.from_scenario(str(ROOT / "scenarios" / "pillar_wrap.yaml")).tethers[0].add_vehicle_sample(
            0.0, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="spool"):
        rov_tether.World({"spool": "here"})
    with pytest.raises(ValueError, match="not plain data"):
        rov_tether.World({"spool": [0.0, 0.0, object()]})
    with pytest.raises(ValueError, match="expected a number"):
        tether.set_param("drag", "0.5\nnoise: 0.1")  # one value, a string: it sets nothing else
    with pytest.raises(ValueError, match="unknown parameter"):
        tether.set_param("drag=0.5\nnoise", 0.1)
    assert rov_tether.World({"spool": np.zeros(3)}).tethers[0].positions[0].tolist() == [0.0, 0.0, 0.0]
    assert world.tether("tether").name == "tether"


# A float that is not finite, passed from Python, is refused as the runner refuses `--set drag=.nan`: as not
# finite, naming the value. Python's json writes NaN and Infinity, which YAML reads as strings, so it used to be
# refused as "wrong type (a string)". A string "NaN" stays a string.
def test_a_value_that_is_not_finite_is_refused_as_not_finite(tmp_path):
    world = hanging_world()
    (tether,) = world.tethers
    for value in (math.nan, math.inf, np.float64(-np.inf)):
        with pytest.raises(ValueError, match=r"drag = -?(nan|inf): must be a finite number in \(0, 1\]"):
            tether.set_param("drag", value)
    with pytest.raises(ValueError, match="wrong type"):
        tether.set_param("drag", "NaN")
    with pytest.raises(ValueError, match="finite"):
        tether.set_param("current", [math.nan, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"spool\[1\]: must be finite"):
        rov_tether.World({"spool": [0.0, math.nan, 0.0]})
    with pytest.raises(ValueError) as raised:
        rov_tether.World({"spool": [0.0, 0.0, 0.0], "params": {"drag": math.inf}})
    path, output = runner_error(tmp_path, "spool: [0, 0, 0]\nduration: 1.0\nparams: {drag: .inf}\n")
    assert str(raised.value) in output  # the runner's message for the same file
    world.step(0.1)  # nothing was set: the world goes on


# While one thread steps, another runs Python: with the GIL held through advance_to the second would stand
# still for the whole call (a C++ call is never pre-empted for the switch interval), so its longest pause
# would be the call's length. Released, its pauses are the scheduler's: a quarter of the call bounds them on
# two cores with margin.
def test_the_gil_is_released_while_stepping():
    world = rov_tether.World.from_scenario(str(ROOT / "scenarios" / "pillar_wrap.yaml"))
    world.advance_to(0.1)
    span = {}

    def step():
        span["start"] = time.perf_counter()
        world.advance_to(20.0)
        span["end"] = time.perf_counter()

    stepping = threading.Thread(target=step)
    ticks = []
    stepping.start()
    while stepping.is_alive():
        ticks.append(time.perf_counter())
    stepping.join()
    ticks = [t for t in ticks if span["start"] <= t <= span["end"]]
    length = span["end"] - span["start"]
    assert length > 0.05, "the call is too short to tell"
    pauses = np.diff([span["start"]] + ticks + [span["end"]])
    assert pauses.max() < 0.25 * length, (pauses.max(), length)


# Reading a world while another thread steps it: each read takes the world's lock with the GIL released, so
# the stepping thread keeps going (it reaches 20 s; the join's timeout would show a hang) and every read is of
# a world between steps: finite numbers in the documented shapes. (A read that held the GIL while waiting for
# the lock, or the lock while making Python objects, could deadlock here.)
def test_reading_while_another_thread_steps_neither_blocks_nor_breaks():
    world = rov_tether.World.from_scenario(str(ROOT / "scenarios" / "pillar_wrap.yaml"))
    tether = world.tethers[0]
    stepping = threading.Thread(target=lambda: [world.step(0.05) for _ in range(400)])
    reads = []
    stepping.start()
    while stepping.is_alive():
        reads.append((tether.positions, tether.segment_tension, world.topology()))
    stepping.join(timeout=60.0)
    assert not stepping.is_alive()
    assert world.time == pytest.approx(20.0)
    assert len(reads) > 0  # at least one read while it stepped (how many depends on who gets the lock)
    for positions, tensions, topology in reads:
        assert positions.ndim == 2 and positions.shape[1] == 3 and positions.shape[0] >= 2
        assert np.isfinite(positions).all() and np.isfinite(tensions).all()
        assert {r["kind"] for r in topology} >= {"wrap_turns", "wrap_angle"}  # always reported, contact or not


# The API's names are loaded on first use (module __getattr__), and listed before it: dir() and tab completion
# show World, Tether and Camera (they showed none of them).
def test_dir_lists_the_names_loaded_on_first_use():
    assert {"Camera", "Tether", "World"} <= set(dir(rov_tether))


# World(description) reads the caller's dict and leaves it as it was: it used to add the `duration` and
# `output_rate` it invented for the reader to the caller's own dict (a py::dict made from a dict is another handle to
# the same object, not a copy), so the dict read back with keys its writer never gave. Nested lists and dicts are
# compared too, deep copies being what the caller had.
def test_a_world_leaves_the_callers_description_as_it_was():
    description = {"spool": [0.0, 0.0, -1.0], "params": {"noise": 0.0, "winch_mode": "locked"},
                   "obstacles": [{"name": "pillar", "type": "cylinder", "radius": 0.3, "length": 10,
                                  "position": [1.0, 1.0, -1.0]}]}
    before = copy.deepcopy(description)
    rov_tether.World(description)
    assert description == before


def swinging_world():
    """hanging_world's chain, slack, with its end driven up and sideways at 1.4 m/s: drag and weight shape it."""
    world = hanging_world()
    tether = world.tethers[0]
    tether.add_vehicle_sample(0.0, [1.0, -2.0, -6.0])
    tether.add_vehicle_sample(2.0, [3.0, -2.0, -4.0])
    return world


# set_param's name is exactly one parameter's name: it was pasted into YAML text before the value, so a name that
# was YAML of its own set what it said ("drag: 0.5 #" set drag to 0.5 and the value 5 became a comment; a flow map
# set two parameters and the value was never read). Each is refused naming what was given, and changes nothing:
# the world steps as a twin that was never asked, bit for bit (the same calls on the same state), while a twin
# really given drag 0.5 (the default is 0.9) ends 0.27 m away somewhere along the cable, so a change shows beyond
# the 1 mm bound. A typo still gets the nearest name.
def test_set_param_takes_exactly_one_parameter_name():
    world, twin, changed = swinging_world(), swinging_world(), swinging_world()
    tether = world.tethers[0]
    for name, value in [("drag: 0.5 #", 5), ("{weight_in_water: 2.0, drag: 0.5} #", "anything"),
                        ("drag: 0.5\t#", 0.7), ("drag ", 0.5), ("", 0.5), ("drag=0.5\nnoise", 0.1)]:
        with pytest.raises(ValueError) as raised:
            tether.set_param(name, value)
        assert "unknown parameter '%s'" % name in str(raised.value)
    with pytest.raises(ValueError, match=r"unknown parameter 'drg' \(did you mean 'drag'\?\)"):
        tether.set_param("drg", 0.5)
    changed.tethers[0].set_param("drag", 0.5)
    for w in (world, twin, changed):
        w.advance_to(2.0)
    assert np.array_equal(world.tethers[0].positions, twin.tethers[0].positions)
    assert not np.allclose(changed.tethers[0].positions, twin.tethers[0].positions, rtol=0, atol=1e-3)


# A path with a NUL in it is refused as Python's open() refuses it: the C++ reader opened the path up to the NUL, so
# 'good.yaml\0/etc/passwd' silently loaded good.yaml. The good file itself still loads (what is refused is the NUL).
def test_a_scenario_path_with_a_nul_is_refused_as_open_refuses_it(tmp_path):
    path = tmp_path / "good.yaml"
    path.write_text("spool: [0, 0, 0]\nduration: 1.0\n")
    with pytest.raises(ValueError, match="embedded null byte"):
        open(str(path) + "\0/etc/passwd")
    for bad in (str(path) + "\0/etc/passwd", str(path).encode() + b"\0x"):
        with pytest.raises(ValueError, match="embedded null byte"):
            rov_tether.World.from_scenario(bad)
    assert rov_tether.World.from_scenario(str(path)).time == 0.0
    # The path types open() takes: a pathlib.Path was refused as an incompatible argument (a TypeError from
    # pybind11); anything else is refused as open() refuses it.
    assert rov_tether.World.from_scenario(path).time == 0.0
    assert rov_tether.World.from_scenario(str(path).encode()).time == 0.0
    with pytest.raises(TypeError, match="expected str, bytes or os.PathLike"):
        rov_tether.World.from_scenario(3)
    # A file name that is not UTF-8 (Latin-1 bytes) opens, as open() opens it.
    latin1 = bytes(tmp_path) + b"/caf\xe9.yaml"
    with open(latin1, "w") as f:
        f.write("spool: [0, 0, 0]\nduration: 1.0\n")
    assert rov_tether.World.from_scenario(latin1).time == 0.0


# A reader's message that echoes bytes of a file that are not UTF-8 (a Latin-1 key, 'dur\xe9e') reaches Python
# whole, each such byte as U+FFFD, and says what the runner says of the same file: pybind11 made it a
# ValueError('') (the message could not be decoded, and the decoding error was dropped). Random bytes, which the
# reader takes for a scalar, are refused with a message too.
def test_a_message_that_echoes_bytes_that_are_not_utf8_reaches_python(tmp_path):
    path = tmp_path / "latin1.yaml"
    path.write_bytes(b"spool: [0, 0, 0]\nduration: 1.0\ndur\xe9e: 1\n")
    done = subprocess.run([RUNNER, str(path), "--out", str(tmp_path / "out")], capture_output=True)
    assert done.returncode != 0
    with pytest.raises(ValueError) as raised:
        rov_tether.World.from_scenario(str(path))
    assert "unknown field 'dur\ufffde'" in str(raised.value)
    assert str(raised.value) in (done.stdout + done.stderr).decode("utf-8", "replace")
    path.write_bytes(bytes(range(128, 256)) + b"\n")
    with pytest.raises(ValueError) as raised:
        rov_tether.World.from_scenario(str(path))
    assert "scenario: expected a map" in str(raised.value)


# An obstacle's name is text that reaches Python (world.topology()) and the node's messages, so it must be UTF-8: a
# Latin-1 name in a scenario file was taken, and world.topology() then raised UnicodeDecodeError. It is refused by
# the core's check of every obstacle (the reader's, the runner's and the node's), naming the obstacle with '?' for
# each byte that is not UTF-8, as the runner says it; a name in UTF-8 beyond ASCII is taken and comes back as given.
def test_an_obstacle_name_that_is_not_utf8_is_refused(tmp_path):
    path = tmp_path / "latin1_obstacle.yaml"
    path.write_bytes(b'spool: [0, 0, -1]\nduration: 1.0\nobstacles: [{name: "pil\xe9r", type: cylinder, radius: 0.3, '
                     b'length: 10, position: [1, 1, -1]}]\n')
    done = subprocess.run([RUNNER, str(path), "--out", str(tmp_path / "out")], capture_output=True)
    assert done.returncode != 0
    with pytest.raises(ValueError, match=r"obstacle 'pil\?r' \(cylinder\): the name must be UTF-8") as raised:
        rov_tether.World.from_scenario(str(path))
    assert str(raised.value) in (done.stdout + done.stderr).decode("utf-8", "replace")
    world = rov_tether.World({"spool": [0, 0, -1], "obstacles": [{"name": "pilier \u00e9", "type": "cylinder",
                                                                 "radius": 0.3, "length": 10,
                                                                 "position": [1, 1, -1]}]})
    assert {r["object"] for r in world.topology()} == {"pilier \u00e9"}


# A dict that leaves `duration` out steps as far as it is advanced, so no check of a duration can refuse it: the
# binding gave the reader an invented 1e4 s, and an output_rate of 200 rows/s (or a camera at 200 Hz) was then
# refused as "duration x output_rate = 2000000: more than 1e6 output times", a duration the user never gave. Each
# rate is still checked alone, and a duration the user gives is checked with it, the message naming the user's
# numbers (2e4 s x 100 rows/s).
def test_a_description_without_a_duration_is_not_refused_by_a_check_of_one():
    camera = {"name": "front", "width": 64, "height": 48, "K": [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1], "rate": 200.0}
    path = [[0.0, 1.0, 0.0, -1.0], [10.0, 5.0, 0.0, -1.0]]
    for description in ({"spool": [0, 0, 0], "output_rate": 200.0},
                        {"spool": [0, 0, 0], "vehicle": path, "cameras": [camera]}):
        world = rov_tether.World(description)
        world.advance_to(0.1)
        assert world.time == pytest.approx(0.1)
    with pytest.raises(ValueError, match=r"^output_rate = -1\.0+: must be in \(0, 1e4\]"):
        rov_tether.World({"spool": [0, 0, 0], "output_rate": -1.0})
    with pytest.raises(ValueError, match=r"cameras\[0\]\.rate = 2000: must be in \(0, 1000\] Hz"):
        rov_tether.World({"spool": [0, 0, 0], "vehicle": path, "cameras": [dict(camera, rate=2000.0)]})
    with pytest.raises(ValueError, match=r"^duration x output_rate = 2000000\.0+: more than 1e6 output times"):
        rov_tether.World({"spool": [0, 0, 0], "duration": 2e4, "output_rate": 100.0})


# step(dt) goes on from the time last asked for, not from the world's last whole step. The world takes whole steps
# of time_step (5 ms by default) and ends an advance at the last one at or before its target, so the remainder was
# lost at every call: 100 x step(0.001) never moved (each asked for 1 ms past 0) and 100 x step(0.0075) took one
# step each, 0.5 s, not 0.75. Now they add up to 20 and 150 whole steps. advance_to(t) ends at the last whole step
# at or before t (0.0123 s: at 0.010), and a step(dt) after it goes on from t (0.0123 + 0.0027: 0.015). Two threads
# stepping 50 x 1 ms each reach 0.1 s between them: each takes its target under the world's lock.
def test_small_steps_add_up_to_whole_steps():
    def world():
        return rov_tether.World({"spool": [0.0, 0.0, -1.0]})

    for dt, calls, reached in [(0.001, 100, 0.1), (0.0075, 100, 0.75)]:
        w = world()
        for _ in range(calls):
            w.step(dt)
        assert w.time == pytest.approx(reached, abs=1e-12) == w.tethers[0].time
    w = world()
    w.advance_to(0.0123)
    assert w.time == pytest.approx(0.010, abs=1e-12)
    w.step(0.0027)
    assert w.time == pytest.approx(0.015, abs=1e-12)
    w = world()
    threads = [threading.Thread(target=lambda: [w.step(0.001) for _ in range(50)]) for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert w.time == pytest.approx(0.1, abs=1e-12)


def interrupted(script, after):
    """Runs `script` in a child Python, sends it SIGINT `after` seconds after it prints "stepping", and returns its
    exit code, output, errors and the seconds from the signal to its exit. The child first puts back Python's own
    SIGINT handler (KeyboardInterrupt), as a terminal's Python has it: a suite started in the background (`&`,
    nohup) starts its children with SIGINT ignored, and Python then leaves it ignored."""
    script = "import signal\nsignal.signal(signal.SIGINT, signal.default_int_handler)\n" + script
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline() == "stepping\n"
        time.sleep(after)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=60.0)
        return child.returncode, out, err, time.monotonic() - sent
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()


# Ctrl-C (SIGINT) stops a long advance: Python's handler only sets a flag, which the binding now checks between
# chunks of about 0.05 s of stepping (PyErr_CheckSignals, the GIL taken back for it). It raised nothing until the call
# returned, here after 1e9 s of simulated time (2e11 steps: days). The child steps for a second, is sent SIGINT and
# must exit within 3 s of it (the check every ~0.1 s at worst, and the child's exit, on a loaded machine), having
# caught KeyboardInterrupt from advance_to with the world consistent: stopped at a whole step (a whole number of 5 ms
# steps, the tether at the world's time, finite positions), and a step(0.05) after it goes on from there.
def test_ctrl_c_stops_a_long_advance_at_a_whole_step():
    script = """
import sys
import numpy as np
import rov_tether
world = rov_tether.World({"spool": [0.0, 0.0, -1.0]})
print("stepping", flush=True)
try:
    world.advance_to(1e9)
except KeyboardInterrupt:
    stopped = world.time
    tether = world.tethers[0]
    ok = tether.time == stopped and bool(np.isfinite(tether.positions).all())
    world.step(0.05)
    print(repr(stopped), ok, repr(world.time), flush=True)
    sys.exit(0)
sys.exit(3)
"""
    returncode, out, err, took = interrupted(script, after=1.0)
    assert returncode == 0, err
    assert took < 3.0
    stopped, ok, after = out.split()
    assert float(stopped) > 0.0 and ok == "True"  # it had stepped, and stopped between two steps
    assert float(stopped) / 0.005 == pytest.approx(round(float(stopped) / 0.005), abs=1e-6)
    assert float(after) == pytest.approx(float(stopped) + 0.05, abs=1e-9)


# The chunks are sized by how long the last took, and a step's cost changes by any factor with set_param: 100 m of
# cable in 1 m segments stepped for 300 s grew the chunk to tens of seconds, and after segment_length 0.01 (100
# times the particles, some 800 times the cost of a step) one chunk took most of a minute, so Ctrl-C waited for it
# (a reviewer measured 3.8 s on a shorter case). The first chunk after set_param is short again. The child is sent
# SIGINT 0.5 s into the finer cable's advance and must exit within 2 s (the old chunk alone takes far longer).
def test_ctrl_c_after_a_set_param_that_makes_steps_slower_is_as_prompt():
    script = """
import sys, warnings
import rov_tether
warnings.simplefilter("ignore")
world = rov_tether.World({"spool": [0.0, 0.0, -1.0], "params": {"cable_length": 100.0,
                          "initial_deployed_length": 100.0, "min_deployed_length": 1.0, "segment_length": 1.0,
                          "noise": 0.0}})
world.advance_to(300.0)
world.tethers[0].set_param("segment_length", 0.01)
print("stepping", flush=True)
try:
    world.advance_to(1e9)
except KeyboardInterrupt:
    sys.exit(0)
sys.exit(3)
"""
    returncode, out, err, took = interrupted(script, after=0.5)
    assert returncode == 0, err
    assert took < 2.0


# set_param's warning (a cable_length or segment_length that lays the cable out anew) comes before the change: a
# warning raised as an error (python -W error, warnings.simplefilter("error"), pytest's filterwarnings = error) then
# leaves the tether unchanged, as a refused value does. It came after the change, so the call raised with the cable
# already rebuilt: 41 particles, not 21. Unchanged means it steps bit for bit as a twin that was never asked; asked
# again with warnings as warnings, it is taken with its warning.
def test_a_set_param_warning_raised_as_an_error_changes_nothing():
    def world():
        return rov_tether.World({"spool": [0.0, 0.0, -1.0], "params": {"cable_length": 10.0, "noise": 0.0,
                                                                        "initial_deployed_length": 5.0,
                                                                        "segment_length": 0.25}})

    asked, twin = world(), world()
    tether = asked.tethers[0]
    for w in (asked, twin):
        w.advance_to(1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(UserWarning, match="segment_length: cable rebuilt"):
            tether.set_param("segment_length", 0.125)
    assert len(tether.positions) == 21
    for w in (asked, twin):
        w.advance_to(2.0)
    assert np.array_equal(tether.positions, twin.tethers[0].positions)
    with pytest.warns(UserWarning, match="segment_length: cable rebuilt"):
        tether.set_param("segment_length", 0.125)
    assert len(tether.positions) == 41
