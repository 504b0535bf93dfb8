#pragma once
// What a Python World is (src/python/module.cpp), shared with the camera module (camera_module.cpp), which
// takes a World as this type: pybind11 shares registered types between the modules of one build.

#include <memory>
#include <mutex>

#include "rov_tether/core/world.hpp"
#include "rov_tether/scenario/scenario.hpp"
#include "rov_tether/scenario/scenario_stepper.hpp"

namespace rov_tether::python
{

/// A scenario, the world built from it and its stepper: shared by the World object and its tethers' views.
/// `mutex` is held by whatever reads or steps the world (stepping runs without the GIL).
struct Session
{
  Scenario scenario;
  World world;
  std::unique_ptr<ScenarioStepper> stepper;
  std::mutex mutex;
};

}  // namespace rov_tether::python
