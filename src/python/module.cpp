// rov_tether._core: the Python API over the ROS-free core (docs/python.md). A World is built from the runner's
// description of a world (a scenario file, or the same as a dict) by the same reader and builder as the runner
// (loadScenario / parseScenario, buildWorld), and stepped by the same loop (ScenarioStepper), so a scenario run
// from Python and by rov_tether_run gives the same numbers. Bad input raises ValueError with the reader's
// message; a refused advance raises RuntimeError with the runner's. The GIL is released while stepping; a
// mutex keeps readers in other threads off a world that is stepping.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "rov_tether/scenario/scenario_yaml.hpp"
#include "rov_tether/core/vehicle_body.hpp"
#include "rov_tether/scenario/world_spec.hpp"
#include "session.hpp"

namespace py = pybind11;

namespace rov_tether::python
{
namespace
{

std::shared_ptr<Session> build(const std::string& error, Scenario scenario)
{
  if (!error.empty())
  {
    throw py::value_error(error);
  }
  auto session = std::make_shared<Session>();
  session->scenario = std::move(scenario);
  const std::string built = buildWorld(worldSpecOf(session->scenario), &session->world);
  if (!built.empty())
  {
    throw py::value_error(built);
  }
  session->stepper = std::make_unique<ScenarioStepper>(session->scenario, session->world);
  return session;
}

std::shared_ptr<Session> fromScenario(const std::string& path)
{
  Scenario scenario;
  const std::string error = loadScenario(path, &scenario);
  return build(error, std::move(scenario));
}

/// A dict in the runner's scenario format, as JSON (a subset of YAML that the reader takes as it is). A dict
/// without `duration` steps as far as it is advanced: the reader is given the longest it accepts.
std::shared_ptr<Session> fromDict(const py::dict& description)
{
  py::dict copy(description);
  if (!copy.contains("duration"))
  {
    copy["duration"] = 1.0e4;
    copy["output_rate"] = 1.0;
  }
  const std::string text = py::module_::import("json").attr("dumps")(copy).cast<std::string>();
  Scenario scenario;
  const std::string error = parseScenario(text, &scenario);
  return build(error, std::move(scenario));
}

void advanceTo(Session& session, double t)
{
  if (!std::isfinite(t))
  {
    throw py::value_error("advance_to: t must be finite (got " + std::to_string(t) + ")");
  }
  std::string error;
  {
    py::gil_scoped_release released;
    const std::lock_guard<std::mutex> lock(session.mutex);
    if (t < session.world.time())
    {
      error = "advance_to: t = " + std::to_string(t) + " s is before the world's time " +
              std::to_string(session.world.time()) + " s (a world does not step back)";
    }
    else if (!session.stepper->runError().empty())
    {
      error = "advance_to: the world stopped at an earlier error: " + session.stepper->runError();
    }
    else if (!session.stepper->advance(t))
    {
      error = session.stepper->runError();
    }
  }
  if (!error.empty())
  {
    throw std::runtime_error(error);
  }
}

/// One tether of a world: a view that keeps the world alive.
struct TetherView
{
  std::shared_ptr<Session> session;
  std::size_t index = 0;

  const Tether& tether() const { return session->world.tether(index); }

  py::array_t<double> positions() const
  {
    const std::lock_guard<std::mutex> lock(session->mutex);
    const Tether& sim = tether();
    const std::size_t n = sim.deployedParticleCount();
    py::array_t<double> out({n, std::size_t{3}});
    auto view = out.mutable_unchecked<2>();
    for (std::size_t k = 0; k < n; ++k)
    {
      const Position p = sim.particle(k);
      view(k, 0) = p.x(), view(k, 1) = p.y(), view(k, 2) = p.z();
    }
    return out;
  }

  std::vector<double> tensions() const
  {
    const std::lock_guard<std::mutex> lock(session->mutex);
    std::vector<double> tensions;
    tether().computeSegmentTensions(tensions);
    return tensions;
  }

  TetherSummary summary() const
  {
    const std::lock_guard<std::mutex> lock(session->mutex);
    std::vector<double> tensions;
    tether().computeSegmentTensions(tensions);
    return tether().summarize(tensions);
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
      throw py::value_error("add_vehicle_sample: tether '" + session->world.name(index) +
                            "' follows its scenario's vehicle path; give it no `vehicle` to drive it from Python");
    }
    const std::lock_guard<std::mutex> lock(session->mutex);
    const Status added =
        session->world.tether(index).addVehicleSample(t, Position(position[0], position[1], position[2]));
    if (!added.ok)
    {
      throw py::value_error(added.message);
    }
  }

  py::dict winch() const;
  void setTargetLength(double length);
  void setParam(const std::string& name, const py::handle& value);
  py::object vehicle() const;
  void setVehicleThrust(const std::vector<double>& wrench);
};

py::dict TetherView::winch() const
{
  const std::lock_guard<std::mutex> lock(session->mutex);
  const Tether& sim = tether();
  py::dict state;
  state["mode"] = toString(sim.params().winch_mode);
  state["deployed_length"] = sim.deployedLength();
  state["speed"] = sim.winchSpeed();
  state["target_length"] = sim.targetLength();
  state["outrun"] = sim.winchOutrun();
  return state;
}

void TetherView::setTargetLength(double length)
{
  const std::lock_guard<std::mutex> lock(session->mutex);
  const Status set = session->world.tether(index).setTargetLength(length);
  if (!set.ok)
  {
    throw py::value_error(set.message);
  }
}

void TetherView::setParam(const std::string& name, const py::handle& value)
{
  const std::string assignment = name + "=" + py::str(value).cast<std::string>();
  const std::lock_guard<std::mutex> lock(session->mutex);
  Tether& sim = session->world.tether(index);
  TetherParams params = sim.params();
  const std::string error = applyAssignment(assignment, &params);
  if (!error.empty())
  {
    throw py::value_error(error);
  }
  const Status set = sim.setParams(params);
  if (!set.ok)
  {
    throw py::value_error(set.message);
  }
}

py::object TetherView::vehicle() const
{
  const std::lock_guard<std::mutex> lock(session->mutex);
  const VehicleBody* body = tether().vehicleBody();
  if (body == nullptr)
  {
    return py::none();
  }
  const Eigen::Quaterniond& q = body->attitude();
  const Twist& v = body->velocity();
  const Wrench& applied = tether().vehicleThrustUsed()->applied;
  py::dict state;
  state["position"] = std::vector<double>{body->position().x(), body->position().y(), body->position().z()};
  state["orientation"] = std::vector<double>{q.x(), q.y(), q.z(), q.w()};
  state["velocity"] = std::vector<double>(v.data(), v.data() + 6);
  state["thrust"] = std::vector<double>(applied.data(), applied.data() + 6);
  return std::move(state);
}

void TetherView::setVehicleThrust(const std::vector<double>& wrench)
{
  if (wrench.size() != 6)
  {
    throw py::value_error("set_vehicle_thrust: [Fx, Fy, Fz, Mx, My, Mz] in the body frame (got " +
                          std::to_string(wrench.size()) + " numbers)");
  }
  const std::lock_guard<std::mutex> lock(session->mutex);
  Tether& sim = session->world.tether(index);
  if (!sim.vehicleDynamic())
  {
    throw py::value_error("set_vehicle_thrust: tether '" + session->world.name(index) +
                          "' has no dynamic vehicle (vehicle: {model: dynamic, ...} in its description)");
  }
  const Status set = sim.setVehicleThrust(Wrench(wrench.data()));
  if (!set.ok)
  {
    throw py::value_error(set.message);
  }
  session->stepper->releaseVehicle(index);  // the command is the caller's from now on
}

py::dict topologyRecord(const World& world, const TopologyEntry& e)
{
  py::dict record;
  record["tether"] = world.name(e.tether);
  record["object"] = e.object_is_tether ? world.name(e.object) : world.obstacle(e.object).name();
  record["object_is_tether"] = e.object_is_tether;
  record["kind"] = topologyKindName(e.kind);
  record["value"] = e.value;
  return record;
}

}  // namespace
}  // namespace rov_tether::python

PYBIND11_MODULE(_core, m)
{
  using namespace rov_tether;
  using namespace rov_tether::python;
  m.doc() = "rov_tether's core: tethers, winches, obstacles and vehicles in one world (docs/python.md)";

  py::class_<TetherView>(m, "Tether", "One tether of a World (a view: it keeps the world alive)")
      .def_property_readonly("name", [](const TetherView& t) { return t.session->world.name(t.index); })
      .def_property_readonly("positions", &TetherView::positions,
                             "Deployed particles, spool first: an N x 3 array [m] in the world frame (z up), a copy")
      .def_property_readonly("segment_tension", &TetherView::tensions,
                             "Axial force of each deployed segment, spool first [N] (N - 1 of them)")
      .def_property_readonly("tension_spool", [](const TetherView& t) { return t.summary().tension_spool; },
                             "Tension in the segment at the spool [N]")
      .def_property_readonly("tension_vehicle", [](const TetherView& t) { return t.summary().tension_vehicle; },
                             "Tension in the segment at the vehicle (or the free end) [N]")
      .def_property_readonly("deployed_length", [](const TetherView& t) { return t.summary().deployed_length; },
                             "Cable off the spool [m]")
      .def_property_readonly("time", [](const TetherView& t) { return t.tether().time(); }, "Its time [s]")
      .def("add_vehicle_sample", &TetherView::addVehicleSample, py::arg("t"), py::arg("position"),
           "Where the vehicle end is at time t [s]: [x, y, z] [m] (only for a tether without a scenario path)")
      .def_property_readonly("winch", &TetherView::winch,
                             "The winch: mode, deployed_length [m], speed [m/s] (pay-out over the last step, negative "
                             "reeling in), target_length [m] (speed mode; NaN: none), outrun (the vehicle outruns it)")
      .def("set_target_length", &TetherView::setTargetLength, py::arg("length"),
           "In speed mode, pays out or reels in towards `length` [m] and holds it (NaN clears it)")
      .def("set_param", &TetherView::setParam, py::arg("name"), py::arg("value"),
           "Changes one model parameter between steps, as rov_tether_run --set name=value does")
      .def_property_readonly("vehicle", &TetherView::vehicle,
                             "The dynamic vehicle's state, or None for a kinematic end: position [m] and orientation "
                             "[x, y, z, w] (body to world), velocity [u, v, w, p, q, r] in the body frame [m/s, rad/s], "
                             "thrust applied [N, N m] (body frame, within its limits)")
      .def("set_vehicle_thrust", &TetherView::setVehicleThrust, py::arg("wrench"),
           "The dynamic vehicle's body-frame thrust command [Fx, Fy, Fz, Mx, My, Mz] [N, N m], held until changed; "
           "from the first call on it replaces the scenario's controller or thrust schedule")
      .def("__repr__", [](const TetherView& t)
           { return "<rov_tether.Tether '" + t.session->world.name(t.index) + "'>"; });

  py::class_<Session, std::shared_ptr<Session>>(m, "World",
                                                "Tethers, obstacles and vehicles, built from the runner's "
                                                "description of a world (a dict, or World.from_scenario(path))")
      .def(py::init(&fromDict), py::arg("description"))
      .def_static("from_scenario", &fromScenario, py::arg("path"),
                  "A runner scenario file (YAML), its vehicle paths included")
      .def("advance_to", &advanceTo, py::arg("t"),
           "Steps every tether to time t [s] along the scenario's paths (the GIL released meanwhile)")
      .def(
          "step", [](Session& s, double dt) { advanceTo(s, s.world.time() + dt); }, py::arg("dt"),
          "advance_to(time + dt)")
      .def_property_readonly("time", [](Session& s) { return s.world.time(); }, "The world's time [s]")
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
      .def(
          "topology",
          [](Session& s)
          {
            std::vector<TopologyEntry> entries;
            {
              const std::lock_guard<std::mutex> lock(s.mutex);
              s.world.topology(entries);
            }
            py::list records;
            for (const TopologyEntry& e : entries)
            {
              records.append(topologyRecord(s.world, e));
            }
            return records;
          },
          "Wrap turns and angles, contact angles, capstan ratios and linking numbers: the ~topology fields");
}
