#pragma once
// The 6x6 solves of a vehicle body's step: LU by the Schur complement of a diagonal translational block.

#include <Eigen/Core>

#include "rov_tether/core/positive_real_lu.hpp"

namespace rov_tether
{

/**
 * A x = b for a 6 x 6 matrix A = [A11, A12; A21, A22] whose top-left (translational) block A11 is diagonal and
 * whose symmetric part is positive definite: the matrices of a vehicle body's step (VehicleBody). Its mass
 * matrix M's translational block is m I plus the diagonal added mass, the damping D is diagonal and Fossen's
 * Coriolis matrix C has a zero translational block, so M + h D and M + h/2 C both have a diagonal A11 (positive:
 * the symmetric part's diagonal). Eliminating it first leaves the 3 x 3 Schur complement
 * S = A22 - A21 A11^-1 A12, whose symmetric part is positive definite too (Golub and Van Loan, Matrix
 * Computations, 4th ed. 2013, sec. 4.4.4), factored without pivoting (PositiveRealLu<3>). This is the same
 * elimination as PositiveRealLu<6> in another order, without its work on A11's zeros: three independent
 * divisions and a 3 x 3 factorisation instead of six divisions in series (docs/benchmarks.md, "A dynamic
 * vehicle end"). A11 is taken as diagonal (its off-diagonal entries are not read). No allocation.
 */
class BodyLu
{
 public:
  using Matrix6 = Eigen::Matrix<double, 6, 6>;

  /// Factors `a` (A11 diagonal and positive, the symmetric part positive definite; not checked).
  void compute(const Matrix6& a)
  {
    inverse_diagonal_ = a.diagonal().head<3>().cwiseInverse();
    upper_ = a.topRightCorner<3, 3>();
    lower_ = a.bottomLeftCorner<3, 3>() * inverse_diagonal_.asDiagonal();  // A21 A11^-1
    schur_.compute(a.bottomRightCorner<3, 3>() - lower_ * upper_);
  }

  /// x with A x = b, for each column of b.
  template <int Cols>
  Eigen::Matrix<double, 6, Cols> solve(const Eigen::Matrix<double, 6, Cols>& b) const
  {
    Eigen::Matrix<double, 6, Cols> x;
    x.template bottomRows<3>() =
        schur_.solve(Eigen::Matrix<double, 3, Cols>(b.template bottomRows<3>() - lower_ * b.template topRows<3>()));
    x.template topRows<3>() =
        inverse_diagonal_.asDiagonal() * (b.template topRows<3>() - upper_ * x.template bottomRows<3>());
    return x;
  }

 private:
  Eigen::Vector3d inverse_diagonal_ = Eigen::Vector3d::Ones();  ///< A11^-1
  Eigen::Matrix3d upper_ = Eigen::Matrix3d::Zero();             ///< A12
  Eigen::Matrix3d lower_ = Eigen::Matrix3d::Zero();             ///< A21 A11^-1
  PositiveRealLu<3> schur_;                                     ///< S = A22 - A21 A11^-1 A12
};

}  // namespace rov_tether
