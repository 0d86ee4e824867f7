// The shape-matching projection's out-of-line steps (constraints/shape_match.hpp's svd_rotation, shape_match_math.hpp's
// cube_root), compiled once, for any x86-64: the scalar projection and the AVX2 kernel call this one copy, so they
// get the same bits.
#include "pbd/constraints/shape_match.hpp"

#include <Eigen/SVD>

#include <cmath>

namespace pbd::detail::shape_match {

template <class Real> void svd_rotation(const Real (&a)[9], Real (&r)[9]) {
  Mat3<Real> m;
  m << a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8];
  const Eigen::JacobiSVD<Mat3<Real>> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3<Real> v = svd.matrixV();
  if (svd.matrixU().determinant() * v.determinant() < Real(0)) v.col(2) = -v.col(2);  // σ3 is the smallest
  const Mat3<Real> out = svd.matrixU() * v.transpose();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[3 * i + j] = out(i, j);
}

template void svd_rotation(const float (&)[9], float (&)[9]);
template void svd_rotation(const double (&)[9], double (&)[9]);

float math::cube_root(float x) { return std::cbrt(x); }
double math::cube_root(double x) { return std::cbrt(x); }

}  // namespace pbd::detail::shape_match
