#include "warp/mean_value.h"

#include <cmath>
#include <unsupported/Eigen/AutoDiff>

namespace ffd {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kOnVertex = 1e-12;    // |x - p_j| over the cage's diagonal
constexpr double kOnTriangle = 1e-10;  // pi - h
constexpr double kInPlane = 1e-10;     // |s_i|

double value_of(double t) { return t; }
template <class D>
double value_of(const Eigen::AutoDiffScalar<D>& t) { return t.value(); }
template <class T>
Eigen::Vector3d value_of(const Eigen::Matrix<T, 3, 1>& v) {
  return {value_of(v[0]), value_of(v[1]), value_of(v[2])};
}

/// The coordinates in `w` (normalized) of x: Ju et al.'s figure 4, for a scalar type T
/// that is double or an automatic-differentiation scalar.
template <class T>
void coordinates(const MeanValueCage& cage, const Eigen::Matrix<T, 3, 1>& x, std::vector<T>& w) {
  using std::asin, std::sin, std::sqrt;
  const Eigen::Index m = cage.points.cols();
  w.assign(static_cast<std::size_t>(m), T(0.0));
  std::vector<T> d(static_cast<std::size_t>(m));
  std::vector<Eigen::Matrix<T, 3, 1>> u(static_cast<std::size_t>(m));
  for (Eigen::Index j = 0; j < m; ++j) {
    const Eigen::Matrix<T, 3, 1> e = cage.points.col(j).cast<T>() - x;
    d[j] = e.norm();
    if (value_of(d[j]) < kOnVertex * cage.diagonal) {
      w.assign(static_cast<std::size_t>(m), T(0.0));
      w[j] = T(1.0);
      return;
    }
    u[j] = e / d[j];
  }
  T total(0.0);
  for (const auto& t : cage.triangles) {
    T theta[3], c[3], s[3];
    for (int i = 0; i < 3; ++i) {
      const T l = (u[t[(i + 1) % 3]] - u[t[(i + 2) % 3]]).norm();
      theta[i] = 2.0 * asin(value_of(l) >= 2 ? T(1.0) : T(l / 2.0));
    }
    const T h = (theta[0] + theta[1] + theta[2]) / 2.0;
    if (kPi - value_of(h) < kOnTriangle) {  // x on the triangle: its barycentric coordinates
      w.assign(static_cast<std::size_t>(m), T(0.0));
      T sum(0.0);
      for (int i = 0; i < 3; ++i) {
        w[t[i]] = sin(theta[i]) * d[t[(i + 2) % 3]] * d[t[(i + 1) % 3]];
        sum += w[t[i]];
      }
      for (int i = 0; i < 3; ++i) w[t[i]] /= sum;
      return;
    }
    const double det = value_of(u[t[0]]).dot(value_of(u[t[1]]).cross(value_of(u[t[2]])));
    const double sign = det < 0 ? -1.0 : 1.0;
    bool in_plane = false;
    for (int i = 0; i < 3; ++i) {
      c[i] = 2.0 * sin(h) * sin(h - theta[i]) / (sin(theta[(i + 1) % 3]) * sin(theta[(i + 2) % 3])) - 1.0;
      const T one_minus = 1.0 - c[i] * c[i];
      s[i] = sign * sqrt(value_of(one_minus) > 0 ? one_minus : T(0.0));
      in_plane = in_plane || std::abs(value_of(s[i])) <= kInPlane;
    }
    if (in_plane) continue;
    for (int i = 0; i < 3; ++i) {
      const int n = (i + 1) % 3, p = (i + 2) % 3;
      const T wi = (theta[i] - c[n] * theta[p] - c[p] * theta[n]) / (d[t[i]] * sin(theta[n]) * s[p]);
      w[t[i]] += wi;
      total += wi;
    }
  }
  for (T& wi : w) wi /= total;
}

}  // namespace

void mean_value_coordinates(const MeanValueCage& cage, const Eigen::Vector3d& x, Eigen::VectorXd& w,
                            Eigen::Matrix3Xd* gradient) {
  const Eigen::Index m = cage.points.cols();
  w.resize(m);
  if (!gradient) {
    thread_local std::vector<double> out;
    coordinates<double>(cage, x, out);
    for (Eigen::Index j = 0; j < m; ++j) w[j] = out[static_cast<std::size_t>(j)];
    return;
  }
  using Dual = Eigen::AutoDiffScalar<Eigen::Vector3d>;
  Eigen::Matrix<Dual, 3, 1> xd;
  for (int a = 0; a < 3; ++a) xd[a] = Dual(x[a], Eigen::Vector3d::Unit(a));
  thread_local std::vector<Dual> out;
  coordinates<Dual>(cage, xd, out);
  gradient->resize(3, m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const Dual& o = out[static_cast<std::size_t>(j)];
    w[j] = o.value();
    gradient->col(j) = o.derivatives().size() ? Eigen::Vector3d(o.derivatives()) : Eigen::Vector3d::Zero();
  }
}

double winding_number(const MeanValueCage& cage, const Eigen::Vector3d& x) {
  double sum = 0;
  for (const auto& t : cage.triangles) {
    const Eigen::Vector3d a = cage.points.col(t[0]) - x, b = cage.points.col(t[1]) - x, c = cage.points.col(t[2]) - x;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double det = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    sum += 2 * std::atan2(det, den);
  }
  return sum / (4 * kPi);
}

}  // namespace ffd
