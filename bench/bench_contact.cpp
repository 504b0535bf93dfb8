// Speed of contact (Google Benchmark, in rov_tether_bench; scripts/bench.sh --benchmark_filter=Contact):
//   BM_ContactWorldStep/0      one World step of 8 tethers x 200 segments lying on a 100,000-triangle mesh
//                              seabed among 100 primitives (the goal: <= 1 ms); /1 the same with
//                              contact between tethers and of each with itself off (obstacles only);
//   BM_ContactOff/BM_ContactAlone  the same 8 tethers in a World with contact off and no obstacles, against
//                              8 independent Tether::step (should cost the same);
//   BM_ContactBroadPhase/N     one World step with N = 10, 100, 1000 spheres at one density (the area grows
//                              with N), the tethers in the middle: what the broad phase adds per obstacle;
//   BM_ContactMeshPush/T/F     one mesh query on the 100,000-triangle seabed, touching (T = 0) or 1 m above
//                              (T = 1), by MeshObstacle::push (F = 0, its grid), FCL's collide query (F = 1)
//                              or push's own walk of FCL's tree (F = 2), with the operator new calls per query
//                              (allocs_per_query);
//   BM_ContactPrimitive*       one capsule query by hand (obstacle.cpp's closed forms) and through FCL 0.7.
// See docs/benchmarks.md.
#include <benchmark/benchmark.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "rov_tether/core/world.hpp"
#include "rov_tether/geometry/make_obstacle.hpp"
#include "rov_tether/geometry/mesh_obstacle.hpp"

// Every operator new of the binary is counted (then served by malloc), so a benchmark can report the
// allocations its loop makes.
namespace
{
std::atomic<long> g_allocations{0};
}
__attribute__((noinline)) void* operator new(std::size_t size)
{
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size))
  {
    return p;
  }
  throw std::bad_alloc();
}
// Not inlined (new above neither): GCC would otherwise see free() meet new at every delete (-Wmismatched-new-delete).
__attribute__((noinline)) void operator delete(void* p) noexcept { std::free(p); }
__attribute__((noinline)) void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace
{

using rov_tether::makeObstacle;
using rov_tether::Obstacle;
using rov_tether::ObstacleSpec;
using rov_tether::Position;
using rov_tether::Push;
using rov_tether::ShapeType;
using rov_tether::Status;
using rov_tether::Tether;
using rov_tether::TetherParams;
using rov_tether::World;

constexpr double kSeabedZ = -20.0;

/// A rolling heightfield around z = -20 m, n x n cells over `width` metres, front up: 2 n^2 triangles.
rov_tether::TriangleMesh heightfield(int n, double width)
{
  rov_tether::TriangleMesh mesh;
  const double cell = width / n;
  for (int i = 0; i <= n; ++i)
  {
    for (int j = 0; j <= n; ++j)
    {
      const double x = -0.5 * width + i * cell, y = -0.5 * width + j * cell;
      mesh.vertices.emplace_back(x, y, kSeabedZ + 0.4 * std::sin(x / 3.0) * std::cos(y / 4.0));
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

/// 224 x 224 cells over 60 m: 100,352 triangles of 0.27 m.
std::unique_ptr<Obstacle> seabedMesh()
{
  ObstacleSpec spec;
  spec.name = "seabed";
  spec.type = ShapeType::Mesh;
  spec.file = "(generated)";
  return std::make_unique<rov_tether::MeshObstacle>(spec, heightfield(224, 60.0));
}

/// Where tether k's spool is, and where its vehicle ends up: on the seabed 16 m away.
Position spoolOf(int k) { return Position(-7.0 + 2.0 * k, -8.0, kSeabedZ + 4.0); }
Position restOf(int k) { return Position(-6.5 + 2.0 * k, 8.0, kSeabedZ + 0.3); }

/// A tether of 200 segments of 0.1 m, 1 N/m in water, laid out straight up from its spool (laid out slack
/// between spool and vehicle, it would hang 2.8 m through the seabed: docs/limitations.md).
/// lowerVehicle brings the vehicle down to the seabed, so most of the cable sinks onto it.
std::unique_ptr<Tether> tether(int k)
{
  TetherParams params;
  params.segment_length = 0.1;
  params.cable_length = 20.0;
  params.initial_deployed_length = 20.0;
  params.weight_in_water = 1.0;
  params.winch_mode = rov_tether::WinchMode::kLocked;
  return std::make_unique<Tether>(params, spoolOf(k), spoolOf(k) + Position(0.0, 0.0, params.cable_length));
}

/// How long the vehicles take to come down [s], and how long a contact scene settles before it is timed
/// [s]: the cables have landed and come to rest.
constexpr double kDescent = 6.0;
constexpr double kSettle = kDescent + 3.0;

/// Tether k's vehicle, from straight over its spool down to the seabed over kDescent (easing in and out).
/// The first refused sample, if any.
Status lowerVehicle(Tether& tether, int k)
{
  const Position above = tether.particle(tether.deployedParticleCount() - 1);
  for (int i = 1; i <= 10 * kDescent; ++i)
  {
    const double s = 0.5 - 0.5 * std::cos(3.14159265358979 * i / (10.0 * kDescent));
    const Status status = tether.addVehicleSample(0.1 * i, above + s * (restOf(k) - above));
    if (!status.ok)
    {
      return status;
    }
  }
  return Status::success();
}

/// Whether `status` is a refusal; if so the benchmark is skipped, naming `what` was refused.
bool refused(benchmark::State& state, const Status& status, const std::string& what)
{
  if (!status.ok)
  {
    state.SkipWithError((what + ": " + status.message).c_str());
  }
  return !status.ok;
}

/// Whether `obstacle` stays 5 cm clear of every segment of the tethers as they are built.
bool clearOfTethers(const Obstacle& obstacle, const std::vector<std::unique_ptr<Tether>>& tethers)
{
  for (const auto& tether : tethers)
  {
    const rov_tether::Cable& cable = tether->state();
    for (std::size_t j = cable.first; j + 1 < cable.size(); ++j)
    {
      Push push;
      if (obstacle.push(cable.position(j), cable.position(j + 1), 0.5 * tether->params().diameter + 0.05, &push))
      {
        return false;
      }
    }
  }
  return true;
}

/// `count` primitives (spheres, boxes, cylinders in turn) on the seabed at random over a square of `side`
/// metres around the origin, none through the tethers as they start (a cable laid out through an obstacle
/// is thrown out of it in one step: docs/limitations.md), so the cables fall onto them (seeded: the
/// same scene every run).
std::vector<std::unique_ptr<Obstacle>> primitives(int count, double side,
                                                  const std::vector<std::unique_ptr<Tether>>& tethers)
{
  std::vector<std::unique_ptr<Obstacle>> made;
  std::uint64_t state = 12345;
  auto uniform = [&state]()
  {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  for (int i = 0; static_cast<int>(made.size()) < count; ++i)
  {
    ObstacleSpec spec;
    spec.name = "rock" + std::to_string(i);
    spec.type = i % 3 == 0 ? ShapeType::Sphere : i % 3 == 1 ? ShapeType::Box : ShapeType::Cylinder;
    spec.position = Position(side * (uniform() - 0.5), side * (uniform() - 0.5), kSeabedZ);
    spec.orientation = Position(0.0, 0.0, 3.0 * uniform());
    spec.radius = 0.2 + 0.4 * uniform();
    spec.length = 0.5 + uniform();
    spec.size = Position(0.3 + 0.5 * uniform(), 0.3 + 0.5 * uniform(), 0.3 + 0.5 * uniform());
    rov_tether::Status status;
    std::unique_ptr<Obstacle> rock = makeObstacle(spec, &status);
    if (clearOfTethers(*rock, tethers))
    {
      made.push_back(std::move(rock));
    }
  }
  return made;
}

/// The 8 tethers of every scene here, as built.
std::vector<std::unique_ptr<Tether>> eightTethers()
{
  std::vector<std::unique_ptr<Tether>> made;
  for (int k = 0; k < 8; ++k)
  {
    made.push_back(tether(k));
  }
  return made;
}

/// The tethers and `obstacles` in one World, settled for `settle` seconds; nullptr, with the benchmark skipped
/// and the reason, when a step of this is refused. (A World is not moved: its tethers' contacts point into it.)
std::unique_ptr<World> scene(benchmark::State& state, std::vector<std::unique_ptr<Tether>> tethers,
                             std::vector<std::unique_ptr<Obstacle>> obstacles, bool contact, double settle)
{
  auto world = std::make_unique<World>();
  world->setContactBetweenTethers(contact);
  for (std::size_t k = 0; k < tethers.size(); ++k)
  {
    const std::string name = "tether" + std::to_string(k);
    if (refused(state, lowerVehicle(*tethers[k], static_cast<int>(k)), "lowering " + name) ||
        refused(state, world->add(name, std::move(tethers[k])), "adding " + name))
    {
      return nullptr;
    }
  }
  if (refused(state, world->setObstacles(std::move(obstacles)), "placing the obstacles") ||
      refused(state, world->advanceTo(settle), "settling the scene"))
  {
    return nullptr;
  }
  return world;
}

/// World steps: each iteration advances every tether one step (time_step 5 ms).
void runWorld(benchmark::State& state, World& world)
{
  const double step = 0.005;
  double t = world.time();
  const long before = g_allocations.load();
  for (auto _ : state)
  {
    t += step;
    const Status status = world.advanceTo(t);
    if (!status.ok)
    {
      state.SkipWithError(("a step: " + status.message).c_str());
      break;
    }
  }
  state.counters["allocs_per_step"] =
      static_cast<double>(g_allocations.load() - before) / static_cast<double>(state.iterations());
  std::size_t touching = 0;
  for (std::size_t i = 0; i < world.size(); ++i)
  {
    for (const int o : world.contacts(i).obstacle)
    {
      touching += o >= 0 ? 1 : 0;
    }
  }
  state.counters["segments_on_obstacles"] = static_cast<double>(touching);
  double substeps = 0.0;
  for (std::size_t i = 0; i < world.size(); ++i)
  {
    substeps += world.tether(i).lastSubsteps();
  }
  state.counters["substeps"] = substeps / static_cast<double>(world.size());  // per tether, last step
}

/// Argument 0: all contact (the case); 1: obstacles only (contact between tethers and of each with
/// itself off), to show what each part costs.
void BM_ContactWorldStep(benchmark::State& state)
{
  const bool between_tethers = state.range(0) == 0;
  state.SetLabel(between_tethers ? "all contact" : "obstacles only");
  // Built and settled once per process (kSettle of simulated time: the vehicles come down and the cables
  // land), then shared by the repetitions.
  static std::unique_ptr<World> settled[2];
  std::unique_ptr<World>& world = settled[between_tethers ? 0 : 1];
  if (!world)
  {
    std::vector<std::unique_ptr<Tether>> tethers = eightTethers();
    std::vector<std::unique_ptr<Obstacle>> obstacles = primitives(100, 20.0, tethers);
    obstacles.push_back(seabedMesh());
    world = scene(state, std::move(tethers), std::move(obstacles), between_tethers, kSettle);
    if (!world)
    {
      return;
    }
  }
  runWorld(state, *world);
}

void BM_ContactOff(benchmark::State& state)
{
  const std::unique_ptr<World> world = scene(state, eightTethers(), {}, false, kSettle);
  if (world)
  {
    runWorld(state, *world);
  }
}

void BM_ContactAlone(benchmark::State& state)
{
  std::vector<std::unique_ptr<Tether>> alone;
  for (int k = 0; k < 8; ++k)
  {
    alone.push_back(tether(k));
    if (refused(state, lowerVehicle(*alone.back(), k), "lowering tether " + std::to_string(k)) ||
        refused(state, alone.back()->advance(kSettle), "settling tether " + std::to_string(k)))
    {
      return;
    }
  }
  for (auto _ : state)
  {
    for (auto& t : alone)
    {
      t->step();
    }
  }
}

/// N primitives at one per 16 m^2 (a square of side 4 sqrt(N) m), a flat plane as seabed.
void BM_ContactBroadPhase(benchmark::State& state)
{
  const int n = static_cast<int>(state.range(0));
  std::vector<std::unique_ptr<Tether>> tethers = eightTethers();
  std::vector<std::unique_ptr<Obstacle>> obstacles = primitives(n, 4.0 * std::sqrt(static_cast<double>(n)), tethers);
  ObstacleSpec bed;
  bed.name = "seabed";
  bed.type = ShapeType::Plane;
  bed.position = Position(0.0, 0.0, kSeabedZ);
  obstacles.push_back(makeObstacle(bed, nullptr));
  const std::unique_ptr<World> world = scene(state, std::move(tethers), std::move(obstacles), true, kSettle);
  if (world)
  {
    runWorld(state, *world);
  }
}

/// One query of a 0.1 m segment of a 1 cm cable on the 100,000-triangle seabed: first argument 0 touching
/// (axis 5 mm up), 1 a metre above it (inside its bounds, touching nothing); second argument 0 through
/// MeshObstacle::push (its grid), 1 through FCL's collide query (pushThroughFclCollide), 2 through push's
/// own walk of FCL's tree (pushThroughTree).
void BM_ContactMeshPush(benchmark::State& state)
{
  const std::unique_ptr<Obstacle> made = seabedMesh();
  const auto& bed = dynamic_cast<const rov_tether::MeshObstacle&>(*made);
  const int way = static_cast<int>(state.range(1));
  state.SetLabel(way == 0 ? "grid (push)" : way == 1 ? "FCL collide" : "own walk of FCL's tree");
  auto query = [&](const Position& a, const Position& b, Push* push)
  {
    return way == 0   ? bed.push(a, b, 0.01, push)
           : way == 1 ? bed.pushThroughFclCollide(a, b, 0.01, push)
                      : bed.pushThroughTree(a, b, 0.01, push);
  };
  const double up = state.range(0) == 0 ? 0.005 : 1.0;
  std::vector<std::pair<Position, Position>> segments;
  for (int k = 0; k < 256; ++k)
  {
    const double x = -20.0 + 40.0 * std::fmod(0.618034 * k, 1.0), y = -20.0 + 40.0 * std::fmod(0.414214 * k, 1.0);
    const double z = kSeabedZ + 0.4 * std::sin(x / 3.0) * std::cos(y / 4.0) + up;
    segments.emplace_back(Position(x, y, z), Position(x + 0.1, y, z));
  }
  Push push;
  std::size_t k = 0;
  long hits = 0;
  query(segments[0].first, segments[0].second, &push);  // warm: the kept result's capacity
  const long before = g_allocations.load();
  for (auto _ : state)
  {
    const auto& s = segments[k++ & 255];
    hits += query(s.first, s.second, &push) ? 1 : 0;
    benchmark::DoNotOptimize(push);
  }
  state.counters["allocs_per_query"] =
      static_cast<double>(g_allocations.load() - before) / static_cast<double>(state.iterations());
  state.counters["hit_fraction"] = static_cast<double>(hits) / static_cast<double>(state.iterations());
}

/// Segment pairs a few centimetres apart, crossing at random angles.
struct CapsulePairs
{
  std::vector<Position> a, b, c, d;
  CapsulePairs()
  {
    for (int k = 0; k < 256; ++k)
    {
      const double phi = 0.7 * k, psi = 1.3 * k;
      a.emplace_back(-0.5 * std::cos(phi), -0.5 * std::sin(phi), 0.0);
      b.emplace_back(0.5 * std::cos(phi), 0.5 * std::sin(phi), 0.0);
      c.emplace_back(-0.5 * std::cos(psi), 0.1 * std::sin(3.0 * k), 0.01 + 0.02 * std::fmod(0.618 * k, 1.0));
      d.emplace_back(0.5 * std::cos(psi), 0.5 * std::sin(psi), 0.01 + 0.02 * std::fmod(0.618 * k, 1.0));
    }
  }
};

fcl::Transform3d capsulePose(const Position& a, const Position& b)
{
  fcl::Transform3d pose = fcl::Transform3d::Identity();
  pose.translation() = 0.5 * (a + b);
  pose.linear() = Eigen::Quaterniond::FromTwoVectors(Position::UnitZ(), b - a).toRotationMatrix();
  return pose;
}

void BM_ContactPrimitiveCapsuleByHand(benchmark::State& state)
{
  const CapsulePairs pairs;
  Push push;
  std::size_t k = 0;
  for (auto _ : state)
  {
    const std::size_t i = k++ & 255;
    benchmark::DoNotOptimize(
        rov_tether::pushCapsule(pairs.a[i], pairs.b[i], 0.01, pairs.c[i], pairs.d[i], 0.01, &push));
    benchmark::DoNotOptimize(push);
  }
}

/// FCL's capsule-capsule distance (closed form in FCL too), the capsules' poses built from the segments as
/// MeshObstacle builds them.
void BM_ContactPrimitiveCapsuleFcl(benchmark::State& state)
{
  const CapsulePairs pairs;
  fcl::DistanceRequestd request(true);
  request.gjk_solver_type = fcl::GST_INDEP;
  fcl::DistanceResultd result;
  std::size_t k = 0;
  for (auto _ : state)
  {
    const std::size_t i = k++ & 255;
    const fcl::Capsuled one(0.01, (pairs.b[i] - pairs.a[i]).norm()), other(0.01, (pairs.d[i] - pairs.c[i]).norm());
    result.clear();
    benchmark::DoNotOptimize(fcl::distance(&one, capsulePose(pairs.a[i], pairs.b[i]), &other,
                                           capsulePose(pairs.c[i], pairs.d[i]), request, result));
  }
}

/// A 1 x 2 x 0.5 m box turned about z, segments passing a few centimetres over its top face or edges.
struct BoxCase
{
  ObstacleSpec spec;
  std::vector<Position> a, b;
  BoxCase()
  {
    spec.name = "box";
    spec.type = ShapeType::Box;
    spec.size = Position(1.0, 2.0, 0.5);
    spec.orientation = Position(0.0, 0.0, 0.4);
    for (int k = 0; k < 256; ++k)
    {
      const double phi = 0.7 * k, h = 0.25 + 0.005 + 0.01 * std::fmod(0.618 * k, 1.0);
      const Position centre(0.8 * std::sin(1.7 * k), 1.2 * std::cos(2.3 * k), h);
      a.push_back(centre - 0.05 * Position(std::cos(phi), std::sin(phi), 0.0));
      b.push_back(centre + 0.05 * Position(std::cos(phi), std::sin(phi), 0.0));
    }
  }
};

void BM_ContactPrimitiveBoxByHand(benchmark::State& state)
{
  const BoxCase box;
  const std::unique_ptr<Obstacle> obstacle = makeObstacle(box.spec, nullptr);
  Push push;
  std::size_t k = 0;
  for (auto _ : state)
  {
    const std::size_t i = k++ & 255;
    benchmark::DoNotOptimize(obstacle->push(box.a[i], box.b[i], 0.01, &push));
    benchmark::DoNotOptimize(push);
  }
}

/// FCL: capsule against box, distance (GJK, independent solver) with nearest points.
void BM_ContactPrimitiveBoxFcl(benchmark::State& state)
{
  const BoxCase box;
  const fcl::Boxd shape(box.spec.size);
  fcl::Transform3d box_pose = fcl::Transform3d::Identity();
  box_pose.linear() = Eigen::AngleAxisd(box.spec.orientation.z(), Position::UnitZ()).toRotationMatrix();
  fcl::DistanceRequestd request(true);
  request.gjk_solver_type = fcl::GST_INDEP;
  fcl::DistanceResultd result;
  std::size_t k = 0;
  for (auto _ : state)
  {
    const std::size_t i = k++ & 255;
    const fcl::Capsuled capsule(0.01, (box.b[i] - box.a[i]).norm());
    result.clear();
    benchmark::DoNotOptimize(
        fcl::distance(&shape, box_pose, &capsule, capsulePose(box.a[i], box.b[i]), request, result));
  }
}

}  // namespace

BENCHMARK(BM_ContactWorldStep)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ContactOff)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ContactAlone)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ContactBroadPhase)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ContactMeshPush)->ArgsProduct({{0, 1}, {0, 1, 2}})->Unit(benchmark::kNanosecond);
BENCHMARK(BM_ContactPrimitiveCapsuleByHand)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_ContactPrimitiveCapsuleFcl)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_ContactPrimitiveBoxByHand)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_ContactPrimitiveBoxFcl)->Unit(benchmark::kNanosecond);
