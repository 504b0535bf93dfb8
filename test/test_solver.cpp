// Constraint solvers on their own, and the promise that a step allocates nothing.
#include <atomic>
#include <cstdlib>
#include <new>

#include "rov_tether/core/pbd_solver.hpp"
#include "rov_tether/core/world.hpp"
#include "rov_tether/geometry/make_obstacle.hpp"
#include "rov_tether/geometry/mesh_obstacle.hpp"
#include "test_helpers.hpp"

namespace
{
std::atomic<long> g_allocations{0};
}  // namespace

// Counts every allocation of this test binary.
__attribute__((noinline)) void* operator new(std::size_t size)
{
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1))
  {
    return p;
  }
  throw std::bad_alloc();
}
// Not inlined (new above neither): GCC would otherwise see free() meet new at every delete (-Wmismatched-new-delete).
__attribute__((noinline)) void operator delete(void* p) noexcept { std::free(p); }
__attribute__((noinline)) void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace rov_tether::test
{
namespace
{

/// A chain of `particles` particles laid out in a zig-zag, ends (and the deployed particles `pinned`, counted from
/// the first) pinned, rest length 0.8.
Cable zigzag(std::size_t particles, std::size_t first, const std::vector<std::size_t>& pinned = {})
{
  Cable state;
  state.resize(first + particles);
  state.first = first;
  for (std::size_t i = 0; i < state.size(); ++i)
  {
    const double k = static_cast<double>(i);
    state.place(i, Position(0.7 * k, (i % 2) ? 0.4 : -0.3, 0.1 * (i % 3)));
    state.inv_mass[i] = (i <= first || i + 1 == state.size()) ? 0.0 : 1.0 + 0.1 * (i % 5);
  }
  for (const std::size_t k : pinned)
  {
    state.inv_mass[first + k] = 0.0;
  }
  for (std::size_t j = 0; j + 1 < state.size(); ++j)
  {
    state.rest[j] = 0.8;
    const double w = state.inv_mass[j] + state.inv_mass[j + 1];
    state.stretch_weight[j] = w > 0 ? 1.0 / w : 0.0;
  }
  for (std::size_t j = 0; j + 2 < state.size(); ++j)
  {
    state.bend_rest[j] = 1.6;
    const double w = state.inv_mass[j] + state.inv_mass[j + 2];
    state.bend_weight[j] = w > 0 ? 1.0 / w : 0.0;
  }
  return state;
}

/// One solve of the chain alone (no contacts), with the solver's multipliers sized for the cable.
void solveOnce(ConstraintSolver& solver, Cable& state, const SolverSettings& settings)
{
  if (solver.multipliers().stretch.size() + 1 != state.size())
  {
    solver.multipliers().resize(state.size());
  }
  solver.solve(state, settings, Contacts{}, state.size());
}

double worstStretchError(const Cable& state)
{
  double worst = 0.0;
  for (std::size_t j = state.first; j + 1 < state.size(); ++j)
  {
    worst = std::max(worst, std::abs((state.position(j + 1) - state.position(j)).norm() - state.rest[j]));
  }
  return worst;
}

// Every chain length (all four residues mod 4, and the shortest chains) converges, pinned particles
// and the particles on the spool never move, for both orderings. From 6 particles on, two neighbours in
// the chain are pinned as well (deployed particles 2 and 3), so a constraint between two pinned
// particles sits between loaded ones, where a wrong multiplier would show in the tension readout.
TEST(Solver, EveryChainLengthConvergesAndPinnedParticlesStay)
{
  for (SolverType type : {SolverType::kPbd, SolverType::kPbdSequential})
  {
    for (std::size_t particles = 2; particles <= 13; ++particles)
    {
      const std::vector<std::size_t> inner_pins =
          particles >= 6 ? std::vector<std::size_t>{2, 3} : std::vector<std::size_t>{};
      Cable state = zigzag(particles, 3, inner_pins);
      const Cable initial = state;
      SolverSettings settings;
      settings.iterations = 2000;
      settings.bending = false;
      const auto solver = makeSolver(type);
      solveOnce(*solver, state, settings);
      int pinned_pairs = 0;
      for (std::size_t j = state.first; j + 1 < state.size(); ++j)
      {
        const bool both_pinned = state.inv_mass[j] == 0.0 && state.inv_mass[j + 1] == 0.0;
        const double error = std::abs((state.position(j + 1) - state.position(j)).norm() - state.rest[j]);
        if (!both_pinned)  // two pinned particles cannot move to meet their constraint
        {
          EXPECT_LT(error, 1e-9) << particles << " particles, segment " << j << ", " << toString(type);
        }
        // Multipliers: pbd's rigid projection of a constraint between two pinned particles has no weight
        // (1 / (0 + 0) is taken as 0), so it records none, by the method's convention, though that
        // constraint is violated (0.8 m rest, the zig-zag's 0.8 m or more apart); the others are finite.
        const double lambda = solver->multipliers().stretch[j];
        EXPECT_TRUE(std::isfinite(lambda));
        if (both_pinned)
        {
          EXPECT_GT(error, 1e-3) << "the pinned pair must violate its constraint for the check to mean anything";
          EXPECT_EQ(lambda, 0.0) << "pinned-pinned segment " << j << ", " << particles << " particles";
          ++pinned_pairs;
        }
      }
      EXPECT_EQ(pinned_pairs, particles == 2 || particles >= 6 ? 1 : 0) << particles << " particles";
      for (std::size_t i = 0; i < state.size(); ++i)
      {
        if (initial.inv_mass[i] == 0.0)
        {
          EXPECT_EQ(state.position(i), initial.position(i)) << "pinned particle " << i;
        }
      }
    }
  }
}

// With bending, both orderings reach the same straight chain from a stretched straight start.
TEST(Solver, BothOrderingsAgreeOnAConsistentProblem)
{
  for (std::size_t particles = 3; particles <= 11; ++particles)
  {
    Cable a = zigzag(particles, 0);
    for (std::size_t i = 0; i < a.size(); ++i)
    {
      a.place(i, Position(0.9 * static_cast<double>(i), 0.0, 0.0));  // straight, stretched 12.5%
    }
    a.place(a.size() - 1, Position(0.8 * static_cast<double>(a.size() - 1), 0.0, 0.0));  // feasible ends
    Cable b = a;
    SolverSettings settings;
    settings.iterations = 3000;
    solveOnce(*makeSolver(SolverType::kPbd), a, settings);
    solveOnce(*makeSolver(SolverType::kPbdSequential), b, settings);
    EXPECT_LT(worstStretchError(a), 1e-9) << particles;
    for (std::size_t i = 0; i < a.size(); ++i)
    {
      EXPECT_NEAR((a.position(i) - b.position(i)).norm(), 0.0, 1e-8) << particles << " particles, " << i;
    }
  }
}

// The red-black solver keeps copies of rest lengths, masses and weights and refreshes only what the
// state marks dirty: after changes near the spool it must match a solver that copies everything.
TEST(Solver, CachedConstraintDataMatchesAFreshCopy)
{
  Cable cached = zigzag(41, 5);
  Cable fresh = cached;
  PbdSolver persistent(false, 0);  // always the blocked path
  SolverSettings settings;
  settings.iterations = 7;
  for (int k = 0; k < 60; ++k)
  {
    for (Cable* state : {&cached, &fresh})
    {
      const std::size_t f = state->first;
      state->rest[f] = 0.6 + 0.005 * k;  // the spool segment grows, as during pay-out
      state->bend_rest[f] = state->rest[f] + state->rest[f + 1];
      state->inv_mass[f + 1] = 1.0 / (0.5 * (state->rest[f] + state->rest[f + 1]));
      const double w = state->inv_mass[f + 1] + state->inv_mass[f + 2];
      state->stretch_weight[f + 1] = 1.0 / w;
      state->markDirty(f, f + 3);
    }
    solveOnce(persistent, cached, settings);
    PbdSolver fresh_solver(false, 0);
    solveOnce(fresh_solver, fresh, settings);
    for (std::size_t i = 0; i < cached.size(); ++i)
    {
      ASSERT_EQ(cached.position(i), fresh.position(i)) << "step " << k << ", particle " << i;
    }
  }
}

// Short cables are projected in place (no blocked copies) in the same order: both paths give the same
// positions and multipliers bit for bit, for pbd and xpbd, with and without bending.
TEST(Solver, InPlacePathMatchesTheBlockedPath)
{
  for (bool compliant : {false, true})
  {
    for (bool bending : {false, true})
    {
      Cable blocked = zigzag(37, 3);
      Cable direct = blocked;
      SolverSettings settings;
      settings.iterations = 9;
      settings.bending = bending;
      settings.axial_stiffness = 50.0;
      settings.bending_stiffness = 0.02;
      PbdSolver blocked_solver(compliant, 0);
      PbdSolver direct_solver(compliant, 1000);
      solveOnce(blocked_solver, blocked, settings);
      solveOnce(direct_solver, direct, settings);
      const Multipliers& blocked_lambda = blocked_solver.multipliers();
      const Multipliers& direct_lambda = direct_solver.multipliers();
      for (std::size_t i = 0; i < blocked.size(); ++i)
      {
        ASSERT_EQ(blocked.position(i), direct.position(i)) << compliant << bending << " particle " << i;
      }
      for (std::size_t j = blocked.first; j + 1 < blocked.size(); ++j)
      {
        ASSERT_EQ(blocked_lambda.stretch[j], direct_lambda.stretch[j]) << j;
      }
      for (std::size_t j = blocked.first; bending && j + 2 < blocked.size(); ++j)
      {
        ASSERT_EQ(blocked_lambda.bend[j], direct_lambda.bend[j]) << j;
      }
    }
  }
}

/// A thousand steps of a tether with pay-out (`params`' winch), then tension and shape reads: counts what
/// they allocate (0 expected), and checks they ran clean with particles released.
void expectStepsAllocateNothing(const TetherParams& params, const std::string& label)
{
  Tether sim(params, Position::Zero(), Position(1.0, 1.0, -1.0));
  ASSERT_TRUE(succeeded(sim.addVehicleSample(10.0, Position(5.0, 2.0, -2.0))));
  std::vector<double> tensions;
  std::vector<Position> shape;
  sim.step();
  sim.computeSegmentTensions(tensions);
  tensions.reserve(params.segmentCount());
  shape.reserve(params.segmentCount() + 1);
  const std::size_t first_before = sim.state().first;
  const long before = g_allocations.load();
  for (int k = 0; k < 1000; ++k)
  {
    sim.step();
  }
  sim.computeSegmentTensions(tensions);
  sim.copyPositions(shape);
  const TetherSummary summary = sim.summary();
  EXPECT_EQ(g_allocations.load() - before, 0) << label;
  EXPECT_EQ(sim.recoveryCount(), 0u) << label;
  EXPECT_LT(sim.state().first, first_before) << label << ": particles were released meanwhile";
  EXPECT_GT(summary.deployed_length, 5.0) << label;
}

// "Hot loops allocate nothing": a thousand steps with pay-out, releases, noise and tension reads.
TEST(Allocation, StepsAllocateNothing)
{
  for (SolverType solver : {SolverType::kPbd, SolverType::kPbdSequential, SolverType::kXpbd, SolverType::kLumpedMass})
  {
    TetherParams params;
    params.solver = solver;
    params.winch_mode = WinchMode::kSpeed;
    params.winch_speed = 0.8;
    params.weight_in_water = 0.5;
    // The water model too: Morison drag, a varying current, a seabed.
    const bool water = solver == SolverType::kXpbd || solver == SolverType::kLumpedMass;
    params.drag_model = water ? DragModel::kMorison : DragModel::kDamping;
    params.current = {0.1, 0.0, 0.0};
    params.current_variation = water ? 0.05 : 0.0;
    params.seabed_z = -1.5;
    params.substeps = solver == SolverType::kLumpedMass ? 60 : 1;  // below the critical step
    expectStepsAllocateNothing(params, toString(solver));
  }
}

// The default solver, `direct`, under the same load as the others: pay-out at 0.8 m/s (the first segment
// grows and particles are released), Morison drag, a varying current and a seabed, with its default
// bending (EI 0.2 N m^2: the primal path) and without (EI 0: the dual path), and a stiff cable (EA 1e9 N)
// whose steps take several Newton iterations.
TEST(Allocation, DirectStepsAllocateNothing)
{
  struct Case
  {
    const char* name;
    double bending_stiffness;
    double axial_stiffness;
  };
  for (const Case& c : {Case{"EI 0", 0.0, 1e4}, Case{"EI 0.2", 0.2, 1e4}, Case{"EI 0.2, EA 1e9", 0.2, 1e9}})
  {
    TetherParams params;
    params.solver = SolverType::kDirect;
    params.bending_stiffness = c.bending_stiffness;
    params.axial_stiffness = c.axial_stiffness;
    params.winch_mode = WinchMode::kSpeed;
    params.winch_speed = 0.8;
    params.weight_in_water = 0.5;
    params.drag_model = DragModel::kMorison;
    params.current = {0.1, 0.0, 0.0};
    params.current_variation = 0.05;
    params.seabed_z = -1.5;
    expectStepsAllocateNothing(params, c.name);
  }
}

// A dynamic vehicle (VehicleCoupling: two body steps and a 6 x 6 solve per sub-step, fixed-size Eigen) on
// `direct`, rod (EI 0.2, the primal path) and cable (EI 0, the dual path): the BlueROV2 Heavy thrusting 40 N
// away from the spool on a locked 10 m tether, caught by it and held; its steps and the reads allocate nothing.
TEST(Allocation, ADynamicVehicleStepsAllocateNothing)
{
  for (const double bending_stiffness : {0.2, 0.0})
  {
    TetherParams params;
    params.solver = SolverType::kDirect;
    params.winch_mode = WinchMode::kLocked;
    params.cable_length = params.initial_deployed_length = 10.0;
    params.bending_stiffness = bending_stiffness;
    Tether sim(params, Position::Zero(), Position(10.0, 0.0, 0.0));
    VehicleBody body;
    ASSERT_TRUE(body.setState({10.2, 0.0, 0.0}, Eigen::Quaterniond::Identity(), Twist::Zero()).ok);
    ASSERT_TRUE(sim.attachVehicleBody(body, Eigen::Vector3d(-0.2, 0.0, 0.0)).ok);
    Wrench thrust = Wrench::Zero();
    thrust[0] = 40.0;
    ASSERT_TRUE(sim.setVehicleThrust(thrust).ok);
    std::vector<double> tensions;
    sim.step();
    sim.computeSegmentTensions(tensions);
    const long before = g_allocations.load();
    for (int k = 0; k < 1000; ++k)
    {
      sim.step();
    }
    sim.computeSegmentTensions(tensions);
    const TetherSummary summary = sim.summary();
    const Force pull = sim.vehicleForce();
    EXPECT_EQ(g_allocations.load() - before, 0) << "EI " << bending_stiffness;
    EXPECT_EQ(sim.recoveryCount(), 0u);
    EXPECT_GT(pull.norm(), 20.0) << "the tether holds the vehicle";
    EXPECT_GT(summary.tension_spool, 20.0);
  }
}

// The end's linearisation for an external simulator (Tether::vehicleEndLinearisation) on a kinematic end,
// rod (EI 0.2, primal path) and cable (EI 0, dual path), a tether falling from its laid-out V to hang from
// the vehicle: after the first call sized its workspace, steps and calls allocate nothing. (No vehicle samples
// are fed: VehicleTrack's queue allocates as it grows and shrinks.)
TEST(Allocation, TheEndLinearisationAllocatesNothing)
{
  for (const double bending_stiffness : {0.2, 0.0})
  {
    TetherParams params;
    params.solver = SolverType::kDirect;
    params.winch_mode = WinchMode::kLocked;
    params.cable_length = params.initial_deployed_length = 10.0;
    params.weight_in_water = 0.5;
    params.bending_stiffness = bending_stiffness;
    Tether sim(params, Position::Zero(), Position(6.0, 0.0, -5.0));
    EndLinearisation linearised;
    sim.step();
    ASSERT_TRUE(sim.vehicleEndLinearisation(&linearised).ok);
    const long before = g_allocations.load();
    int taut = 0;
    for (int k = 0; k < 500; ++k)
    {
      sim.step();
      ASSERT_TRUE(sim.vehicleEndLinearisation(&linearised).ok);
      taut += linearised.taut ? 1 : 0;
    }
    EXPECT_EQ(g_allocations.load() - before, 0) << "EI " << bending_stiffness;
    EXPECT_GT(taut, 400) << "the hanging tether pulls";
  }
}

/// A 3 x 3 m patch of seabed at z = -2 m in 8 x 8 cells, rolling by 5 cm: 128 triangles, front up.
TriangleMesh seabedPatch()
{
  TriangleMesh mesh = flatMesh(8, 3.0 / 8.0);
  for (Eigen::Vector3d& v : mesh.vertices)
  {
    v.z() = -2.0 + 0.05 * std::sin(2.0 * v.x()) * std::cos(2.0 * v.y());
  }
  return mesh;
}

// A World stepping with every kind of contact: two tethers (direct, default bending) whose vehicles cross
// over a pillar and come down onto a mesh seabed, with contact between tethers and of each with itself on.
// Once the scene has started (the grid and the meshes' caches are sized at the first steps), its steps
// allocate nothing, whatever they touch. The vehicles keep moving while it is measured, so the cables
// keep sliding over the mesh, round the pillar and over each other (checked: contacts are made).
TEST(Allocation, AWorldWithObstaclesAMeshAndTetherContactStepsAllocateNothing)
{
  World world;
  world.setContactBetweenTethers(true);
  for (int k = 0; k < 2; ++k)
  {
    TetherParams params;
    params.segment_length = 0.1;
    params.cable_length = 4.0;
    params.initial_deployed_length = 4.0;
    params.weight_in_water = 1.0;
    params.noise = 0.0;
    params.winch_mode = WinchMode::kLocked;
    const double side = k == 0 ? -1.0 : 1.0;
    const Position spool(side, -1.2, -0.5);
    // Laid out clear of everything: 4 m of cable over 3.4 m, sagging 0.9 m, above the seabed at -2 m.
    const Position start(side, 2.2, -0.5);
    auto tether = std::make_unique<Tether>(params, spool, start);
    // Each vehicle goes across to the other side and down, so its cable sweeps onto the pillar and over
    // the other one and sinks onto the mesh, and keeps swaying while the steps are counted.
    // (The two vehicles pass 0.6 m apart in y and 0.3 m in z: Contact.TwoVehiclesThatMeet... is the
    // case where they meet.)
    for (int i = 0; i <= 100; ++i)
    {
      const double t = 0.1 * i;
      const double s = std::min(1.0, t / 4.0);
      const double sway = 0.3 * std::sin(0.8 * t);
      ASSERT_TRUE(succeeded(tether->addVehicleSample(
          t, start + s * Position(-2.0 * side + sway, k == 0 ? -1.0 : -0.4, k == 0 ? -1.1 : -0.8))));
    }
    ASSERT_TRUE(world.add("t" + std::to_string(k), std::move(tether)).ok);
  }
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  ObstacleSpec pillar;
  pillar.name = "pillar";
  pillar.type = ShapeType::Cylinder;
  pillar.position = Position(0.0, 0.0, -1.5);
  pillar.radius = 0.15;
  pillar.length = 1.5;
  Status status;
  obstacles.push_back(makeObstacle(pillar, &status));
  ASSERT_TRUE(obstacles.back() != nullptr) << status.message;
  ObstacleSpec mesh;
  mesh.name = "seabed";
  mesh.type = ShapeType::Mesh;
  mesh.file = "(generated)";
  obstacles.push_back(std::make_unique<MeshObstacle>(mesh, seabedPatch()));
  ASSERT_TRUE(world.setObstacles(std::move(obstacles)).ok);
  ASSERT_TRUE(world.advanceTo(5.0).ok);  // the vehicles have crossed and come down
  const long before = g_allocations.load();
  std::size_t on_obstacles = 0, on_tethers = 0;
  for (int k = 1; k <= 400; ++k)  // 2 s
  {
    ASSERT_TRUE(world.advanceTo(5.0 + 0.005 * k).ok);
    for (std::size_t i = 0; i < world.size(); ++i)
    {
      const ContactRecord& record = world.contacts(i);
      for (std::size_t j = 0; j < record.obstacle.size(); ++j)
      {
        on_obstacles += record.obstacle[j] >= 0 ? 1 : 0;
        on_tethers += record.tether[j] >= 0 ? 1 : 0;
      }
    }
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(on_obstacles, 0u) << "the cables lie on the mesh and the pillar";
  EXPECT_GT(on_tethers, 0u) << "the cables cross";
  for (std::size_t i = 0; i < world.size(); ++i)
  {
    EXPECT_EQ(world.tether(i).recoveryCount(), 0u) << i;
  }
}

}  // namespace
}  // namespace rov_tether::test
