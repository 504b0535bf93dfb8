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
    diagonal_ = false;
    inverse_.head<3>() = a.diagonal().head<3>().cwiseInverse();
    upper_ = a.topRightCorner<3, 3>();
    lower_ = a.bottomLeftCorner<3, 3>() * inverse_.head<3>().asDiagonal();  // A21 A11^-1
    schur_.compute(a.bottomRightCorner<3, 3>() - lower_ * upper_);
  }

  /// Factors [diag(d1), -S(p); -S(p), diag(d2) - S(q)] given d1^-1 = `inverse_d1` (d1 positive; not checked),
  /// S(a) b = a x b: M + h/2 C for a diagonal M, Fossen's Coriolis matrix C at M nu = [p1; p2] being [0, -S(p1);
  /// -S(p1), -S(p2)], so p = h/2 p1 and q = h/2 p2 (VehicleBody's Cayley step, which takes d1^-1 from its
  /// step's start). The same factorisation as compute() without building the 6 x 6 matrix.
  void computeGyroscopic(const Eigen::Vector3d& inverse_d1, const Eigen::Vector3d& d2, const Eigen::Vector3d& p,
                         const Eigen::Vector3d& q)
  {
    diagonal_ = false;
    inverse_.head<3>() = inverse_d1;
    upper_ = minusSkew(p);
    lower_ = upper_ * inverse_d1.asDiagonal();
    Eigen::Matrix3d a22 = minusSkew(q);
    a22.diagonal() = d2;  // diag(d2) - S(q)
    schur_.compute(a22 - lower_ * upper_);
  }

  /// Factors the diagonal matrix diag(d) (d positive; not checked): solve() is then six multiplications. M + h D
  /// of a body whose origin is its centre of gravity (VehicleBody::startStep).
  void computeDiagonal(const Eigen::Matrix<double, 6, 1>& d)
  {
    diagonal_ = true;
    inverse_ = d.cwiseInverse();
  }

  /// x with A x = b, for each column of b. Always inlined: GCC left it out of line, a call through the shared
  /// library's PLT for each of a dynamic vehicle end's solves (docs/benchmarks.md, "A dynamic vehicle end").
  template <int Cols>
  [[gnu::always_inline]] Eigen::Matrix<double, 6, Cols> solve(const Eigen::Matrix<double, 6, Cols>& b) const
  {
    if (diagonal_)
    {
      return inverse_.asDiagonal() * b;
    }
    Eigen::Matrix<double, 6, Cols> x;
    x.template bottomRows<3>() =
        schur_.solve(Eigen::Matrix<double, 3, Cols>(b.template bottomRows<3>() - lower_ * b.template topRows<3>()));
    x.template topRows<3>() =
        inverse_.head<3>().asDiagonal() * (b.template topRows<3>() - upper_ * x.template bottomRows<3>());
    return x;
  }

 private:
  /// -S(v): -S(v) b = b x v.
  static Eigen::Matrix3d minusSkew(const Eigen::Vector3d& v)
  {
    Eigen::Matrix3d m;
    m << 0.0, v.z(), -v.y(), -v.z(), 0.0, v.x(), v.y(), -v.x(), 0.0;
    return m;
  }

  bool diagonal_ = false;  ///< computeDiagonal(): A = diag(d), A^-1 = diag(inverse_)
  Eigen::Matrix<double, 6, 1> inverse_ = Eigen::Matrix<double, 6, 1>::Ones();  ///< A11^-1 (head), or diag(d)^-1
  Eigen::Matrix3d upper_ = Eigen::Matrix3d::Zero();                            ///< A12
  Eigen::Matrix3d lower_ = Eigen::Matrix3d::Zero();                            ///< A21 A11^-1
  PositiveRealLu<3> schur_;                                                    ///< S = A22 - A21 A11^-1 A12
};

}  // namespace rov_tether
