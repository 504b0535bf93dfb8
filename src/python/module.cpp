// rov_tether._core: the Python API over the ROS-free core (docs/python.md). A World is built from the runner's
// description of a world (a scenario file, or the same as a dict) by the same reader and builder as the runner
// (loadScenario / parseScenario, buildWorld), and stepped by the same loop (ScenarioStepper), so a scenario run
// from Python and by rov_tether_run gives the same numbers. Bad input raises ValueError with the reader's
// message; a refused advance raises RuntimeError with the runner's (any byte of either that is not UTF-8 read as
// U+FFFD: translateMessages, session.hpp). Every read, change and step of a world
// holds its lock with the GIL released (withWorld, session.hpp), so other threads run Python meanwhile.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rov_tether/core/tether_params.hpp"
#include "rov_tether/core/vehicle_body.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"
#include "rov_tether/scenario/world_spec.hpp"
#include "session.hpp"

namespace py = pybind11;

namespace rov_tether::python
{
namespace
{

/// Python's json writes a float that is not finite as NaN, Infinity or -Infinity, which YAML reads as strings
/// (a NaN was refused as "wrong type (a string)"); YAML's own spellings are .nan, .inf and -.inf, which the
/// readers take as numbers and refuse as not finite, as the runner does. Outside the text's strings only.
std::string yamlNonFinite(const std::string& json)
{
  std::string out;
  out.reserve(json.size());
  bool in_string = false;
  for (std::size_t i = 0; i < json.size(); ++i)
  {
    const char c = json[i];
    if (in_string)
    {
      out += c;
      if (c == '\\' && i + 1 < json.size())
      {
        out += json[++i];  // an escaped character, a quote included
      }
      else if (c == '"')
      {
        in_string = false;
      }
      continue;
    }
    if (c == '"')
    {
      in_string = true;
      out += c;
    }
    else if (json.compare(i, 3, "NaN") == 0)
    {
      out += ".nan";
      i += 2;
    }
    else if (json.compare(i, 8, "Infinity") == 0)
    {
      out += ".inf";  // after a '-', -.inf
      i += 7;
    }
    else
    {
      out += c;
    }
  }
  return out;
}

std::shared_ptr<Session> build(const std::string& error, Scenario scenario)
{
  if (!error.empty())
  {
    throw py::value_error(error);
  }
  auto session = std::make_shared<Session>();
  session->scenario = std::move(scenario);
  std::vector<std::string> warnings;
  const std::string built = buildWorld(worldSpecOf(session->scenario), &session->world, &warnings);
  if (!built.empty())
  {
    throw py::value_error(built);
  }
  for (const std::string& warning : warnings)
  {
    py::module_::import("warnings").attr("warn")(pythonText(warning));  // out of reach, other water: as the runner says
  }
  session->stepper = std::make_unique<ScenarioStepper>(session->scenario, session->world);
  session->asked = session->world.time();
  return session;
}

std::shared_ptr<Session> fromScenario(const py::object& file)
{
  // A str, bytes or os.PathLike (pathlib.Path), as open() takes (os.fspath: TypeError for anything else).
  const py::module_ os = py::module_::import("os");
  // The file system's bytes (os.fsencode), so that a path that is not UTF-8 opens as open() opens it.
  const std::string path = os.attr("fsencode")(file).cast<std::string>();
  if (path.find('\0') != std::string::npos)
  {
    // Refused as open() refuses it: the file would be opened up to the NUL, another file than the one named.
    throw py::value_error("from_scenario: embedded null byte in the path");
  }
  Scenario scenario;
  const std::string error = loadScenario(path, &scenario);
  return build(error, std::move(scenario));
}

/// A dict in the runner's scenario format, as JSON (a subset of YAML that the reader takes as it is; numpy
/// arrays and numbers as lists and numbers). A dict without `duration` steps as far as it is advanced: the reader
/// checks nothing against a duration it was not given (ScenarioDuration::kOptional).
std::shared_ptr<Session> fromDict(const py::dict& description)
{
  std::string text;
  try
  {
    const py::cpp_function plain(
        [](const py::object& value) -> py::object
        {
          if (py::hasattr(value, "tolist"))
          {
            return value.attr("tolist")();  // numpy arrays and scalars
          }
          throw py::type_error("not a number, string, list or dict: " + py::repr(value).cast<std::string>());
        });
    text = yamlNonFinite(
        py::module_::import("json").attr("dumps")(description, py::arg("default") = plain).cast<std::string>());
  }
  catch (const py::error_already_set& error)
  {
    throw py::value_error(std::string("World: the description is not plain data: ") + error.what());
  }
  Scenario scenario;
  const std::string error = parseScenario(text, &scenario, ScenarioDuration::kOptional);
  return build(error, std::move(scenario));
}

/// advance_to(t), or step(t) with `relative`: the time last asked for plus t (Session::asked, not the world's time,
/// which is the last whole step at or before it: the remainder was lost at every call). The target is taken under
/// the lock, so two threads' steps add up. A target the world refuses is refused here, as ValueError, before the
/// world sees it; a refused advance (RuntimeError) stops the world for good, as it stops the runner.
///
/// The world steps towards the target in chunks of simulated time that take about kChunkSeconds of wall time each
/// (Session::chunk, scaled by how long the last one took; afresh after set_param), and between two the GIL is taken
/// back to run Python's
/// signal handlers: Ctrl-C (SIGINT) in the main thread stops the advance at the chunk's end, a whole step, and
/// raises KeyboardInterrupt; the time asked for is then the world's, so step(dt) goes on from where it stopped.
/// With the GIL released for the whole call, a SIGINT was seen only once it returned. The chunks step as one call
/// would (ScenarioStepper::advance feeds the paths by the sample, wherever a call ends), and take nothing on the heap.
void advance(Session& session, double t, bool relative)
{
  const char* call = relative ? "step: dt" : "advance_to: t";
  if (!std::isfinite(t) || std::abs(t) > Tether::kMaxTime || (relative && t < 0.0))
  {
    throw py::value_error(std::string(call) + " must be finite, within +-1e10 s" +
                          (relative ? " and not negative" : "") + " (got " + std::to_string(t) + ")");
  }
  std::string error;
  bool refused_argument = false;
  double target = 0.0;
  double reached = 0.0;
  withWorld(session,
            [&]
            {
              target = relative ? std::max(session.asked, session.world.time()) + t : t;
              if (target < session.world.time() || target > Tether::kMaxTime)
              {
                refused_argument = true;
                error = std::string(call) + " = " + std::to_string(t) + " s: the world is at " +
                        std::to_string(session.world.time()) + " s (it does not step back, nor beyond 1e10 s)";
              }
              else if (!session.stepper->runError().empty())
              {
                error = "the world stopped at an earlier error: " + session.stepper->runError();
              }
              else
              {
                session.asked = target;
                reached = session.world.time();
              }
            });
  if (refused_argument)
  {
    throw py::value_error(error);
  }
  bool done = !error.empty();
  while (!done)
  {
    withWorld(session,
              [&]
              {
                if (!session.stepper->runError().empty())
                {
                  error = "the world stopped at an earlier error: " + session.stepper->runError();  // another thread's
                  done = true;
                  return;
                }
                const double end = std::min(target, reached + session.chunk);
                const double before = session.world.time();
                const auto start = std::chrono::steady_clock::now();
                if (!session.stepper->advance(end))
                {
                  error = session.stepper->runError();
                  done = true;
                  return;
                }
                const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                // Scaled to take kChunkSeconds after a whole chunk (at most 4 times longer at once: a chunk's time
                // is noisy), doubled after one that took no step, and shortened after any slow one at once, in
                // proportion; not lengthened after the last of a call, nor one the world had passed (another
                // thread's), which say nothing of it.
                const bool whole = end < target && end > before;
                if (whole && session.world.time() == before)
                {
                  session.chunk *= 2.0;
                }
                else if ((whole && took < Session::kChunkSeconds) || took > 2.0 * Session::kChunkSeconds)
                {
                  // From the time it stepped: a call's last chunk is shorter than session.chunk.
                  const double stepped = std::max(session.world.time() - before, Session::kShortestChunk);
                  session.chunk = std::clamp(stepped * Session::kChunkSeconds / std::max(took, 1e-9),
                                             Session::kShortestChunk, 4.0 * session.chunk);
                }
                reached = end;
                done = end >= target;
              });
    if (!done && PyErr_CheckSignals() != 0)
    {
      // A handler raised (KeyboardInterrupt): the world is at a whole step, and the next step(dt) goes on from it
      // unless another thread has asked for more meanwhile.
      py::error_already_set raised;
      withWorld(session,
                [&]
                {
                  if (session.asked == target)
                  {
                    session.asked = session.world.time();
                  }
                });
      throw raised;
    }
  }
  if (!error.empty())
  {
    raisePython(PyExc_RuntimeError, error);
  }
}

void throwIfRefused(const Status& status)
{
  if (!status.ok)
  {
    throw py::value_error(status.message);
  }
}

/// What a dynamic vehicle's state is at one moment (TetherView::vehicle).
struct VehicleState
{
  Eigen::Vector3d position;
  Eigen::Quaterniond attitude;
  Twist velocity;
  Wrench thrust;
};

/// One topology record, as plain data (World::topology with the names resolved).
struct TopologyRecord
{
  std::string tether, object, kind;
  bool object_is_tether = false;
  double value = 0.0;
};

/// One tether of a world: a view that keeps the world alive. Its name and scenario entry do not change after
/// the world is built; everything else is read under the world's lock (withWorld).
struct TetherView
{
  std::shared_ptr<Session> session;
  std::size_t index = 0;

  Tether& tether() const { return session->world.tether(index); }
  const std::string& name() const { return session->world.name(index); }

  py::array_t<double> positions() const
  {
    const std::vector<Position> points = withWorld(*session,
                                                   [&]
                                                   {
                                                     std::vector<Position> copy;
                                                     tether().copyPositions(copy);
                                                     return copy;
                                                   });
    py::array_t<double> out({points.size(), std::size_t{3}});
    auto view = out.mutable_unchecked<2>();
    for (std::size_t k = 0; k < points.size(); ++k)
    {
      view(k, 0) = points[k].x(), view(k, 1) = points[k].y(), view(k, 2) = points[k].z();
    }
    return out;
  }

  py::array_t<double> tensions() const
  {
    const std::vector<double> tensions = withWorld(*session,
                                                   [&]
                                                   {
                                                     std::vector<double> copy;
                                                     tether().computeSegmentTensions(copy);
                                                     return copy;
                                                   });
    py::array_t<double> out(tensions.size());
    std::copy(tensions.begin(), tensions.end(), out.mutable_data());
    return out;
  }

  TetherSummary summary() const
  {
    return withWorld(*session,
                     [&]
                     {
                       std::vector<double> tensions;
                       tether().computeSegmentTensions(tensions);
                       return tether().summarize(tensions);
                     });
  }

  double time() const
  {
    return withWorld(*session, [&] { return tether().time(); });
  }

  bool hasPath() const
  {
    const ScenarioTether& spec = session->stepper->tethers()[index];
    return !spec.vehicle.empty() || spec.dynamic.has_value();
  }

  void addVehicleSample(double t, const std::vector<double>& position)
  {
    if (position.size() != 3)
    {
      throw py::value_error("add_vehicle_sample: position must be [x, y, z] (got " + std::to_string(position.size()) +
                            " numbers)");
    }
    if (hasPath())
    {
      throw py::value_error("add_vehicle_sample: tether '" + name() +
                            "' follows its scenario's vehicle path; give it no `vehicle` to drive it from Python");
    }
    const Position p(position[0], position[1], position[2]);
    throwIfRefused(withWorld(*session, [&] { return tether().addVehicleSample(t, p); }));
  }

  py::dict winch() const
  {
    struct State
    {
      WinchMode mode;
      double deployed, speed, target;
      bool outrun;
    };
    const State state = withWorld(*session,
                                  [&]
                                  {
                                    const Tether& sim = tether();
                                    return State{sim.params().winch_mode, sim.deployedLength(), sim.winchSpeed(),
                                                 sim.targetLength(), sim.winchOutrun()};
                                  });
    py::dict out;
    out["mode"] = toString(state.mode);
    out["deployed_length"] = state.deployed;
    out["speed"] = state.speed;
    out["target_length"] = state.target;
    out["outrun"] = state.outrun;
    return out;
  }

  void setTargetLength(double length)
  {
    throwIfRefused(withWorld(*session, [&] { return tether().setTargetLength(length); }));
  }

  /// As rov_tether_run --set name=value: the value as JSON (YAML reads it as it is), on one line. The name must be
  /// exactly a parameter's: it is put into the YAML text as it is, where anything else would be read as YAML of
  /// its own ("drag: 0.9 #" set drag, and the value became a comment).
  void setParam(const std::string& parameter, const py::object& value)
  {
    const std::vector<std::string>& names = parameterNames();
    // The cable's sections and attachments are parameters too, lists of maps outside the parameter table (as
    // spec::readTetherParams reads them).
    if (std::find(names.begin(), names.end(), parameter) == names.end() && parameter != "sections" &&
        parameter != "attachments")
    {
      const std::string guess = closestName(parameter, names);
      throw py::value_error("unknown parameter '" + parameter + "'" +
                            (guess.empty() ? "" : " (did you mean '" + guess + "'?)"));  // the runner's words
    }
    const py::object plain = py::hasattr(value, "tolist") ? value.attr("tolist")() : value;
    std::string text;
    try
    {
      text = yamlNonFinite(py::module_::import("json").attr("dumps")(plain).cast<std::string>());
    }
    catch (const py::error_already_set& error)
    {
      throw py::value_error("set_param: " + parameter + ": the value is not plain data: " + error.what());
    }
    if (text.find_first_of("\n\r") != std::string::npos)
    {
      throw py::value_error("set_param: " + parameter + ": one value, on one line");
    }
    const std::string assignment = parameter + "=" + text;
    // In two turns of the lock, with what the change has to say (a cable_length or segment_length lays the cable out
    // anew) said between them, before the change: a warning raised as an error (-W error) then leaves the tether as
    // it was, as a refused value does. (Said after the change, it raised with the change made.)
    TetherParams params;
    std::uint64_t changes = 0;
    const Status checked = withWorld(*session,
                                     [&]
                                     {
                                       params = tether().params();
                                       changes = session->param_changes;
                                       const std::string read = applyAssignment(assignment, &params);
                                       return read.empty() ? tether().checkParams(params) : Status::error(read);
                                     });
    if (!checked.ok)
    {
      throw py::value_error(checked.message);
    }
    if (!checked.message.empty())
    {
      py::module_::import("warnings").attr("warn")(pythonText("set_param: " + parameter + ": " + checked.message));
    }
    const Status status = withWorld(*session,
                                    [&]
                                    {
                                      // Another thread's set_param in between: the assignment goes onto its change.
                                      std::string read;
                                      if (session->param_changes != changes)
                                      {
                                        params = tether().params();
                                        read = applyAssignment(assignment, &params);
                                      }
                                      ++session->param_changes;
                                      // A finer cable or more iterations make a step slower by any factor: the
                                      // next advance sizes its chunks afresh (Ctrl-C within about 0.1 s).
                                      session->chunk = Session::kFirstChunk;
                                      return read.empty() ? tether().setParams(params) : Status::error(read);
                                    });
    if (!status.ok)
    {
      throw py::value_error(status.message);
    }
  }

  py::object vehicle() const
  {
    const std::optional<VehicleState> state =
        withWorld(*session,
                  [&]() -> std::optional<VehicleState>
                  {
                    const VehicleBody* body = tether().vehicleBody();
                    if (body == nullptr)
                    {
                      return std::nullopt;
                    }
                    return VehicleState{body->position(), body->attitude(), body->velocity(),
                                        tether().vehicleThrustUsed()->applied};
                  });
    if (!state)
    {
      return py::none();
    }
    const Eigen::Quaterniond& q = state->attitude;
    py::dict out;
    out["position"] = std::vector<double>{state->position.x(), state->position.y(), state->position.z()};
    out["orientation"] = std::vector<double>{q.x(), q.y(), q.z(), q.w()};
    out["velocity"] = std::vector<double>(state->velocity.data(), state->velocity.data() + 6);
    out["thrust"] = std::vector<double>(state->thrust.data(), state->thrust.data() + 6);
    return std::move(out);
  }

  void setVehicleThrust(const std::vector<double>& wrench)
  {
    if (wrench.size() != 6)
    {
      throw py::value_error("set_vehicle_thrust: [Fx, Fy, Fz, Mx, My, Mz] in the body frame (got " +
                            std::to_string(wrench.size()) + " numbers)");
    }
    const Wrench command(wrench.data());
    const std::string error =
        withWorld(*session,
                  [&]() -> std::string
                  {
                    if (!tether().vehicleDynamic())
                    {
                      return "set_vehicle_thrust: tether '" + name() +
                             "' has no dynamic vehicle (vehicle: {model: dynamic, ...} in its description)";
                    }
                    const Status set = tether().setVehicleThrust(command);
                    if (set.ok)
                    {
                      session->stepper->releaseVehicle(index);  // the command is the caller's from now on
                    }
                    return set.message;
                  });
    if (!error.empty())
    {
      throw py::value_error(error);
    }
  }
};

py::list topology(Session& session)
{
  const std::vector<TopologyRecord> records = withWorld(
      session,
      [&]
      {
        std::vector<TopologyEntry> entries;
        session.world.topology(entries);
        std::vector<TopologyRecord> out;
        for (const TopologyEntry& e : entries)
        {
          const World& w = session.world;
          out.push_back({w.name(e.tether), e.object_is_tether ? w.name(e.object) : w.obstacle(e.object).name(),
                         topologyKindName(e.kind), e.object_is_tether, e.value});
        }
        return out;
      });
  py::list out;
  for (const TopologyRecord& r : records)
  {
    py::dict record;
    record["tether"] = r.tether;
    record["object"] = r.object;
    record["object_is_tether"] = r.object_is_tether;
    record["kind"] = r.kind;
    record["value"] = r.value;
    out.append(record);
  }
  return out;
}

}  // namespace
}  // namespace rov_tether::python

PYBIND11_MODULE(_core, m)
{
  using namespace rov_tether;
  using namespace rov_tether::python;
  m.doc() = "rov_tether's core: tethers, winches, obstacles and vehicles in one world (docs/python.md)";
  translateMessages();  // messages that echo a file's bytes that are not UTF-8

  py::class_<TetherView>(m, "Tether", "One tether of a World (a view: it keeps the world alive)")
      .def_property_readonly("name", &TetherView::name)
      .def_property_readonly("positions", &TetherView::positions,
                             "Deployed particles, spool first: an N x 3 array [m] in the world frame (z up), a copy")
      .def_property_readonly("segment_tension", &TetherView::tensions,
                             "Axial force of each deployed segment, spool first [N]: an array of N - 1")
      .def_property_readonly(
          "tension_spool", [](const TetherView& t) { return t.summary().tension_spool; },
          "Tension in the segment at the spool [N]")
      .def_property_readonly(
          "tension_vehicle", [](const TetherView& t) { return t.summary().tension_vehicle; },
          "Tension in the segment at the vehicle (or the free end) [N]")
      .def_property_readonly(
          "deployed_length", [](const TetherView& t) { return t.summary().deployed_length; }, "Cable off the spool [m]")
      .def_property_readonly("time", &TetherView::time, "Its time [s]")
      .def("add_vehicle_sample", &TetherView::addVehicleSample, py::arg("t"), py::arg("position"),
           "Where the vehicle end is at time t [s]: [x, y, z] [m] (only for a tether without a scenario path)")
      .def_property_readonly("winch", &TetherView::winch,
                             "The winch: mode, deployed_length [m], speed [m/s] (pay-out over the last step, negative "
                             "reeling in), target_length [m] (speed mode; NaN: none), outrun (the vehicle outruns it)")
      .def("set_target_length", &TetherView::setTargetLength, py::arg("length"),
           "In speed mode, pays out or reels in towards `length` [m] and holds it (NaN clears it)")
      .def("set_param", &TetherView::setParam, py::arg("name"), py::arg("value"),
           "Changes one model parameter between steps, as rov_tether_run --set name=value does")
      .def_property_readonly(
          "vehicle", &TetherView::vehicle,
          "The dynamic vehicle's state, or None for a kinematic end: position [m] and orientation "
          "[x, y, z, w] (body to world), velocity [u, v, w, p, q, r] in the body frame [m/s, rad/s], "
          "thrust applied [N, N m] (body frame, within its limits)")
      .def("set_vehicle_thrust", &TetherView::setVehicleThrust, py::arg("wrench"),
           "The dynamic vehicle's body-frame thrust command [Fx, Fy, Fz, Mx, My, Mz] [N, N m], held until changed; "
           "from the first call on it replaces the scenario's controller or thrust schedule")
      .def("__repr__", [](const TetherView& t) { return "<rov_tether.Tether '" + t.name() + "'>"; });

  py::class_<Session, std::shared_ptr<Session>>(m, "World",
                                                "Tethers, obstacles and vehicles, built from the runner's "
                                                "description of a world (a dict, or World.from_scenario(path))")
      .def(py::init(&fromDict), py::arg("description"))
      .def_static("from_scenario", &fromScenario, py::arg("path"),
                  "A runner scenario file (YAML), its vehicle paths included")
      .def(
          "advance_to", [](Session& s, double t) { advance(s, t, false); }, py::arg("t"),
          "Steps every tether to its last whole step at or before time t [s] along the scenario's paths (the GIL "
          "released meanwhile)")
      .def(
          "step", [](Session& s, double dt) { advance(s, dt, true); }, py::arg("dt"),
          "advance_to(the time last asked for + dt): steps shorter than a time step add up")
      .def_property_readonly(
          "time", [](Session& s) { return withWorld(s, [&] { return s.world.time(); }); }, "The world's time [s]")
      .def_property_readonly("tethers",
                             [](const std::shared_ptr<Session>& s)
                             {
                               std::vector<TetherView> views;
                               for (std::size_t i = 0; i < s->world.size(); ++i)
                               {
                                 views.push_back(TetherView{s, i});
                               }
                               return views;
                             })
      .def(
          "tether",
          [](const std::shared_ptr<Session>& s, const std::string& name)
          {
            const std::size_t i = s->world.find(name);
            if (i == World::npos)
            {
              throw py::key_error("no tether named '" + name + "'");
            }
            return TetherView{s, i};
          },
          py::arg("name"))
      .def("topology", &topology,
           "Wrap turns and angles, contact angles, capstan ratios and linking numbers: the ~topology fields");
}
