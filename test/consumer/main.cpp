// Hangs the study's S = 8 catenary (10 m, w = 1 N/m, level supports 8 m apart, docs/references.md) with the
// installed core and checks its statics: every segment carries the same horizontal tension H (no horizontal
// load on a chain in still water), and the supports' segments hold up the chain's weight. Exit 0 when both
// hold within 1%, 1 otherwise, 2 when the core refuses the set-up; prints what it measured.
#include <cmath>
#include <cstdio>
#include <vector>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/study/study.hpp"

int main()
{
  using rov_tether::Position;
  constexpr int kSegments = 20;
  constexpr double kLength = 10.0, kWeight = 1.0, kSpan = 8.0;  // the case's L [m], w [N/m] and span [m]
  rov_tether::TetherParams params = rov_tether::study::findCase("catenary_s8").base(kSegments);
  rov_tether::Tether sim(params, Position::Zero(), Position(kSpan, 0.0, 0.0));
  const rov_tether::Status settled = sim.advance(30.0);
  if (!settled)
  {
    std::printf("refused: %s\n", settled.message.c_str());
    return 2;
  }
  std::vector<double> tension;
  sim.computeSegmentTensions(tension);
  const std::size_t n = sim.deployedParticleCount();
  double h_min = INFINITY, h_max = 0.0;
  for (std::size_t k = 0; k + 1 < n; ++k)
  {
    const Position along = sim.particle(k + 1) - sim.particle(k);
    const double horizontal = tension[k] * std::abs(along.x()) / along.norm();
    h_min = std::fmin(h_min, horizontal);
    h_max = std::fmax(h_max, horizontal);
  }
  // The two end particles are the supports, which carry half a segment's weight each themselves: the two
  // end segments' vertical components hold the rest, w (L - L / N).
  const auto vertical = [&](std::size_t k)
  {
    const Position along = sim.particle(k + 1) - sim.particle(k);
    return tension[k] * std::abs(along.z()) / along.norm();
  };
  const double held = vertical(0) + vertical(n - 2);
  const double weight = kWeight * (kLength - kLength / kSegments);
  const double spread = (h_max - h_min) / h_max;
  const double weight_error = std::abs(held - weight) / weight;
  std::printf(
      "segments %zu, horizontal tension %.4f to %.4f N (spread %.2e), supports hold %.4f N of %.4f N "
      "(error %.2e)\n",
      n - 1, h_min, h_max, spread, held, weight, weight_error);
  return spread < 0.01 && weight_error < 0.01 ? 0 : 1;
}
