#pragma once
// What a Python World is (src/python/module.cpp), shared with the camera module (camera_module.cpp), which
// takes a World as this type: pybind11 shares registered types between the modules of one build.

#include <pybind11/pybind11.h>

#include <memory>
#include <mutex>

#include "rov_tether/core/world.hpp"
#include "rov_tether/scenario/scenario.hpp"
#include "rov_tether/scenario/scenario_stepper.hpp"

namespace rov_tether::python
{

/// A scenario, the world built from it and its stepper: shared by the World object and its tethers' views.
/// `mutex` is held by whatever reads, changes or steps the world, always through withWorld().
struct Session
{
  Scenario scenario;
  World world;
  std::unique_ptr<ScenarioStepper> stepper;
  std::mutex mutex;
};

/// Runs f() on the session's world with the GIL released and the world's lock held, and returns what f returns,
/// which must be plain C++ values: no Python object is made or touched under the lock, so no Python code (a
/// finalizer, another thread given the GIL) runs while it is held, and a thread waiting for it lets the others
/// run Python. The callers make their Python objects from what it returns.
template <class F>
auto withWorld(Session& session, F&& f)
{
  const pybind11::gil_scoped_release released;
  const std::lock_guard<std::mutex> lock(session.mutex);
  return f();
}

}  // namespace rov_tether::python
