#pragma once
// What a Python World is (src/python/module.cpp), shared with the camera module (camera_module.cpp), which
// takes a World as this type: pybind11 shares registered types between the modules of one build.

#include <pybind11/pybind11.h>

#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

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
  /// The time last asked for [s]: advance_to's t, or step's target. The world ends an advance at its last whole step
  /// at or before it, and step(dt) goes on from here, so steps shorter than a time step add up.
  double asked = 0.0;
  /// How much simulated time an advance steps with the lock held before it lets Python check its signals [s]: sized
  /// as it goes to take about kChunkSeconds of wall time (module.cpp, advance).
  double chunk = kFirstChunk;
  /// Parameter changes made (set_param): one checked in one turn of the lock and made in the next is applied anew
  /// when another came between them.
  std::uint64_t param_changes = 0;
  static constexpr double kChunkSeconds = 0.05;
  static constexpr double kFirstChunk =
      0.01;  ///< [s] of simulated time: the first chunk, and the first after set_param
  static constexpr double kShortestChunk = 1e-6;
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

/// Python's text of a C++ string, UTF-8 with every byte that is not UTF-8 read as U+FFFD: a reader's message may
/// echo a file's bytes as they are (a Latin-1 key), which pybind11's strict conversion refuses (UnicodeDecodeError,
/// or for an exception's message an empty ValueError('')).
inline pybind11::str pythonText(const std::string& text)
{
  PyObject* decoded = PyUnicode_DecodeUTF8(text.data(), static_cast<Py_ssize_t>(text.size()), "replace");
  if (decoded == nullptr)
  {
    throw pybind11::error_already_set();
  }
  return pybind11::reinterpret_steal<pybind11::str>(decoded);
}

/// Raises Python's `type` with `message` (pythonText): for a message that is no exception type of pybind11's.
[[noreturn]] inline void raisePython(PyObject* type, const std::string& message)
{
  PyErr_SetObject(type, pythonText(message).ptr());
  throw pybind11::error_already_set();
}

/// For the module being defined: the exceptions its functions throw reach Python as pybind11 makes them (the same
/// types), with their messages read by pythonText. Any other exception is left to pybind11.
inline void translateMessages()
{
  pybind11::register_local_exception_translator(
      [](std::exception_ptr thrown)
      {
        try
        {
          std::rethrow_exception(thrown);
        }
        catch (const pybind11::key_error& e)
        {
          PyErr_SetObject(PyExc_KeyError, pythonText(e.what()).ptr());
        }
        catch (const pybind11::value_error& e)
        {
          PyErr_SetObject(PyExc_ValueError, pythonText(e.what()).ptr());
        }
        catch (const pybind11::type_error& e)
        {
          PyErr_SetObject(PyExc_TypeError, pythonText(e.what()).ptr());
        }
        catch (const std::invalid_argument& e)
        {
          PyErr_SetObject(PyExc_ValueError, pythonText(e.what()).ptr());
        }
      });
}

}  // namespace rov_tether::python
