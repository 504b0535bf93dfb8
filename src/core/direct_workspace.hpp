#pragma once
// What the direct solver's two Newton methods (direct_dual.hpp, direct_primal.hpp) share: the step being
// solved, its segment geometry, the active set, and what the last step leaves the next. Not installed: only
// DirectSolver's front (direct_solver.cpp) and the two methods see it. Sized once (reserve); a step never
// allocates.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "rov_tether/core/constraint_solver.hpp"
#include "rov_tether/core/spool_drum.hpp"

namespace rov_tether
{

/// Where a Newton method (DualNewton, PrimalNewton) stopped.
struct NewtonResult
{
  int iterations = 0;
  int rounds = 0;  ///< Linear solves of the active-set rounds.
  /// Largest relative residual where it stopped [-] (the primal's: infinite when no iteration was made).
  double residual = 0.0;
};

struct DirectWorkspace
{
  /// Sizes every buffer for a cable of n particles (once: pay-out never allocates).
  void reserve(std::size_t n);
  /// Sets up the step of the deployed particles [cable.first, n) (n >= first + 2): its compliances, the
  /// predicted positions x~ (the cable's positions now), its geometry and the drum's piece; moves the
  /// multipliers to warm_lambda and clears them.
  void begin(const Cable& cable, Multipliers& lambda, const SolverSettings& settings);
  /// Ends the step: the drum's pay-out, and what the next step starts from (the correction this step made,
  /// the segments taut now, and how hard the chain is pulled). `lambda` points at segment first's multiplier.
  void end(const Cable& cable, double* lambda);
  /// Forgets what the last step left (a cable laid out anew).
  void forget();
  /// Segment geometry at the current positions: n_k, |d_k|, C_k.
  void geometry(const Cable& cable);
  /// Saves the deployed particles' positions (sx, sy, sz), and puts them back.
  void save(const Cable& cable);
  void restore(Cable& cable) const;

  // The step being solved (deployed particles l = 0..m, segments k = 0..m-1, joints j = 0..m-2).
  std::size_t first = 0;
  std::size_t m = 0;
  bool bending = false;
  bool unilateral = true;
  double nominal = 0.1;                 ///< Nominal segment length, the scale of the position tolerance [m].
  SpoolDrum* drum = nullptr;            ///< The winch's drum in this step, or none.
  std::vector<double> xt, yt, zt;       ///< Predicted positions x~ [m].
  std::vector<double> sx, sy, sz;       ///< Saved positions (rejected steps, line search).
  std::vector<double> nx, ny, nz, len;  ///< Unit vector and length of segment k.
  std::vector<double> c;                ///< C_k = |d_k| - L_k - s_k [m] (s_k: axial damping's shift, else 0).
  std::vector<double> alpha;            ///< alpha_k = L_k / (EA h^2 + BA h) [1/kg].
  /// L_k + s_k [m]: the rest length plus, with axial damping BA, the shift s_k = BA / (h EA + BA) C_k(start)
  /// that makes C - s = alpha lambda the Kelvin-Voigt law (DirectWorkspace::begin).
  std::vector<double> stop;
  /// A cable segment slack at the step's start, with axial damping: its dashpot pulls before it is taut (a
  /// slack segment pulled straight), so its law has a middle piece (DirectWorkspace::begin). In C's units,
  /// `kink` where the segment becomes taut (above: C / alpha), `dashpot` the middle piece's slope [1/kg]
  /// (0: none, and kink 0: the law max(C, 0) / alpha), `zero` where the middle piece's force reaches 0.
  std::vector<double> kink, dashpot, zero;
  bool dashpots = false;  ///< Some segment has a middle piece: the primal path takes the step.
  /// Segment k's force (multiplier) at C = c by its law: C / alpha (two-sided for a rod); a cable's, with
  /// the dashpot's middle piece, never below 0.
  double law(std::size_t k, double c) const
  {
    if (!unilateral || c >= kink[k])
    {
      return unilateral ? std::max(c, 0.0) / alpha[k] : c / alpha[k];
    }
    return c > zero[k] ? middleForce(k, c) : 0.0;
  }
  /// The spool segment's residual against the drum's law, relative to its rest length, for its force lambda0 and
  /// `mobility` (the inverse masses of its two particles): as a rod's segment is measured against its law, how far
  /// its stretch is from one at which the law gives lambda0 (C - alpha lambda, the rod's law inverted), or, as a
  /// slack segment's, the move its force's error would make, whichever is less (no stretch gives a force below 0;
  /// a slack segment's force off by little is far from the law's stretch).
  double drumResidual(double lambda0, double mobility) const
  {
    const double move = std::abs(lambda0 - drum->force(c[0])) * mobility;
    return std::min(move, drum->stretchOff(c[0], lambda0)) * inv_rest[0];
  }
  /// The law's middle piece of segment k (a slack segment's dashpot) at C = c: kink / alpha + slope (c - kink).
  double middleForce(std::size_t k, double c) const { return kink[k] / alpha[k] + dashpot[k] * (c - kink[k]); }
  std::vector<double> inv_rest;   ///< 1 / L_k [1/m].
  std::vector<double> gamma;      ///< Compliance of bending joint j [1/(kg m^2)].
  std::vector<double> inv_gamma;  ///< 1 / gamma_j: the joint's stiffness, 0 at a hinge.
  /// The active set (dual) or the model's segments (primal), 1 or 0, padded with a zero before row 0 and
  /// after row m - 1 (on() points at row 0).
  std::vector<double> on_padded;
  double* on() { return on_padded.data() + 1; }
  const double* on() const { return on_padded.data() + 1; }

  // What the last step leaves the next, by particle index.
  std::vector<double> warm_lambda;  ///< Its multipliers: the first estimate.
  /// Its correction x - x~ of each particle [m]: the primal path's first guess.
  std::vector<double> correction_x, correction_y, correction_z;
  std::vector<unsigned char> taut;  ///< Its segments that ended taut: the first active set.
  double tension_ratio = 0.0;       ///< Its largest h^2 T (w_a + w_b) / |d| [-].
};

}  // namespace rov_tether
