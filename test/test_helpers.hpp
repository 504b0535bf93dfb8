#pragma once
// Shared helpers for the core tests: loading shipped scenarios and measuring cable shapes.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/geometry/mesh_obstacle.hpp"
#include "rov_tether/scenario/scenario_runner.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"

namespace rov_tether::test
{

/// A Status as a gtest assertion: ASSERT_TRUE(succeeded(sim.advance(1.0))) for a call the test needs to
/// succeed, failing with the refusal's message.
inline ::testing::AssertionResult succeeded(const Status& status)
{
  return status.ok ? ::testing::AssertionSuccess() : ::testing::AssertionFailure() << status.message;
}

/// Loads scenarios/NAME.yaml from the source tree (fails the test when it does not parse).
inline Scenario shippedScenario(const std::string& name)
{
  Scenario scenario;
  const std::string error =
      loadScenario(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/" + name + ".yaml", &scenario);
  EXPECT_EQ(error, "");
  return scenario;
}

/// Sum of the deployed segments' actual lengths [m].
inline double geometricLength(const Tether& sim)
{
  double length = 0.0;
  for (std::size_t k = 0; k + 1 < sim.deployedParticleCount(); ++k)
  {
    length += (sim.particle(k + 1) - sim.particle(k)).norm();
  }
  return length;
}

/// Mean stretch of the deployed cable: geometric length / deployed length - 1 [-].
inline double meanStretch(const Tether& sim) { return geometricLength(sim) / sim.deployedLength() - 1.0; }

/// Root-mean-square distance between two shapes of equal size [m].
inline double rmsDistance(const std::vector<Position>& a, const std::vector<Position>& b)
{
  EXPECT_EQ(a.size(), b.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
  {
    sum += (a[i] - b[i]).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(a.size()));
}

inline std::vector<Position> positions(const Tether& sim)
{
  std::vector<Position> out;
  sim.copyPositions(out);
  return out;
}

/// Equality of two parameter values where NaN equals NaN (seabed_z's "absent").
inline bool sameParamValue(const ParamValue& a, const ParamValue& b)
{
  const auto* x = std::get_if<double>(&a);
  const auto* y = std::get_if<double>(&b);
  if (x != nullptr && y != nullptr && std::isnan(*x) && std::isnan(*y))
  {
    return true;
  }
  return a == b;
}

/// Runs a scenario to time t and returns the simulation.
inline Tether runTo(const Scenario& scenario, double t)
{
  PathDriver driver(scenario);
  Tether sim = driver.makeSimulation();
  EXPECT_TRUE(succeeded(driver.advanceTo(sim, t)));
  return sim;
}

/// A flat square of n x n cells of `cell` metres in the mesh's xy plane, front (counter-clockwise) up.
inline TriangleMesh flatMesh(int n, double cell)
{
  TriangleMesh mesh;
  for (int i = 0; i <= n; ++i)
  {
    for (int j = 0; j <= n; ++j)
    {
      mesh.vertices.emplace_back((i - 0.5 * n) * cell, (j - 0.5 * n) * cell, 0.0);
    }
  }
  auto at = [n](int i, int j) { return i * (n + 1) + j; };
  for (int i = 0; i < n; ++i)
  {
    for (int j = 0; j < n; ++j)
    {
      mesh.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      mesh.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
  return mesh;
}

}  // namespace rov_tether::test
