#include "warp/mean_value.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unsupported/Eigen/AutoDiff>

#include "common/vector_math.h"

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

/// Barycentric coordinates on triangle t of a point on it: sin(theta_i) d_(i-1) d_(i+1).
template <class T>
void on_triangle(const std::array<std::uint32_t, 3>& t, const T* sin_theta, const std::vector<T>& d, std::vector<T>& w) {
  std::fill(w.begin(), w.end(), T(0.0));
  T sum(0.0);
  for (int i = 0; i < 3; ++i) {
    w[t[i]] = sin_theta[i] * d[t[(i + 2) % 3]] * d[t[(i + 1) % 3]];
    sum += w[t[i]];
  }
  for (int i = 0; i < 3; ++i) w[t[i]] /= sum;
}

/// asin, and sin and cos, of every element: SLEEF's vector functions for doubles, the
/// scalar ones (which carry derivatives) for automatic-differentiation scalars.
void asin_each(std::vector<double>& x) { asin_all(x.data(), x.data(), x.size()); }
void sincos_each(const std::vector<double>& x, std::vector<double>& s, std::vector<double>& c) {
  s.resize(x.size()), c.resize(x.size());
  sincos_all(x.data(), s.data(), c.data(), x.size());
}
template <class D>
void asin_each(std::vector<Eigen::AutoDiffScalar<D>>& x) {
  for (auto& v : x) v = asin(v);
}
template <class D>
void sincos_each(const std::vector<Eigen::AutoDiffScalar<D>>& x, std::vector<Eigen::AutoDiffScalar<D>>& s,
                 std::vector<Eigen::AutoDiffScalar<D>>& c) {
  s.resize(x.size()), c.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) s[i] = sin(x[i]), c[i] = cos(x[i]);
}

/// Per-point scratch of the coordinates, reused across calls on a thread.
template <class T>
struct Scratch {
  std::vector<T> d, inv_d;                     // |p_j - x| and its reciprocal
  std::vector<Eigen::Matrix<T, 3, 1>> u;       // (p_j - x) / d_j
  std::vector<T> half, theta, sin_e, cos_e;    // per edge: sin(theta / 2), theta, sin, cos
  std::vector<T> inv_sin_e;                    // per edge: 1 / sin(theta)
  std::vector<T> h, sin_h, cos_h;              // per triangle
};

/// d, u of every cage vertex; the vertex x is on, or -1.
template <class T>
long vertex_terms(const MeanValueCage& cage, const Eigen::Matrix<T, 3, 1>& x, Scratch<T>& s) {
  const std::size_t m = static_cast<std::size_t>(cage.points.cols());
  s.d.resize(m), s.inv_d.resize(m), s.u.resize(m);
  for (std::size_t j = 0; j < m; ++j) {
    const Eigen::Matrix<T, 3, 1> e = cage.points.col(static_cast<Eigen::Index>(j)).cast<T>() - x;
    s.d[j] = e.norm();
    if (value_of(s.d[j]) < kOnVertex * cage.diagonal) return static_cast<long>(j);
    s.inv_d[j] = 1.0 / s.d[j];
    s.u[j] = e * s.inv_d[j];
  }
  return -1;
}

/// The angle theta each edge subtends at x, with sin and cos, from the chord l = |u_a - u_b|:
/// theta = 2 asin(l / 2), sin(theta) = l sqrt(1 - l^2 / 4), cos(theta) = 1 - l^2 / 2.
template <class T>
void edge_terms(const MeanValueCage& cage, Scratch<T>& s) {
  using std::sqrt;
  const std::size_t n = cage.edges.size();
  s.half.resize(n), s.sin_e.resize(n), s.cos_e.resize(n), s.inv_sin_e.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const T l = (s.u[cage.edges[k][0]] - s.u[cage.edges[k][1]]).norm();
    const T half = value_of(l) >= 2 ? T(1.0) : T(l / 2.0);
    s.half[k] = half;
    s.sin_e[k] = 2.0 * half * sqrt(1.0 - half * half);
    s.cos_e[k] = 1.0 - 2.0 * half * half;
    s.inv_sin_e[k] = 1.0 / s.sin_e[k];  // inf where x is on the edge's line: that triangle is on-plane
  }
  s.theta = s.half;
  asin_each(s.theta);
  for (T& t : s.theta) t *= 2.0;
}

/// Adds triangle f's unnormalized weights to w and total; nothing when x is in its plane
/// outside it.
template <class T>
void triangle_weights(const MeanValueCage& cage, std::size_t f, const Scratch<T>& s, std::vector<T>& w, T& total) {
  using std::sqrt;
  const auto& t = cage.triangles[f];
  const auto& e = cage.opposite_edges[f];
  const double det = value_of(s.u[t[0]]).dot(value_of(s.u[t[1]]).cross(value_of(s.u[t[2]])));
  const double sign = det < 0 ? -1.0 : 1.0;
  T c[3], sv[3];
  for (int i = 0; i < 3; ++i) {
    // sin(h - theta_i) = sin h cos theta_i - cos h sin theta_i
    const T sin_h_theta = s.sin_h[f] * s.cos_e[e[i]] - s.cos_h[f] * s.sin_e[e[i]];
    c[i] = 2.0 * s.sin_h[f] * sin_h_theta * s.inv_sin_e[e[(i + 1) % 3]] * s.inv_sin_e[e[(i + 2) % 3]] - 1.0;
    const T one_minus = 1.0 - c[i] * c[i];
    sv[i] = sign * sqrt(value_of(one_minus) > 0 ? one_minus : T(0.0));
    if (!(std::abs(value_of(sv[i])) > kInPlane)) return;  // NaN too: x on an edge's line
  }
  const T inv_all = 1.0 / (sv[0] * sv[1] * sv[2]);  // 1 / s_p = (the other two) * inv_all
  for (int i = 0; i < 3; ++i) {
    const int n = (i + 1) % 3, p = (i + 2) % 3;
    const T inv_s_p = sv[i] * sv[n] * inv_all;
    const T wi = (s.theta[e[i]] - c[n] * s.theta[e[p]] - c[p] * s.theta[e[n]]) * s.inv_d[t[i]] * s.inv_sin_e[e[n]] * inv_s_p;
    w[t[i]] += wi;
    total += wi;
  }
}

/// The winding number from the unit vectors and the edges' angles already at hand: each
/// triangle's signed solid angle is 2 atan2(det[u0 u1 u2], 1 + cos theta_0 + cos theta_1 +
/// cos theta_2) (Van Oosterom and Strackee, with u_a . u_b = cos theta).
template <class T>
double winding_from_angles(const MeanValueCage& cage, const Scratch<T>& s) {
  const std::size_t F = cage.triangles.size();
  thread_local std::vector<double> num, den, angle;
  num.resize(F), den.resize(F), angle.resize(F);
  for (std::size_t f = 0; f < F; ++f) {
    const auto& t = cage.triangles[f];
    const auto& e = cage.opposite_edges[f];
    num[f] = value_of(s.u[t[0]]).dot(value_of(s.u[t[1]]).cross(value_of(s.u[t[2]])));
    den[f] = 1 + value_of(s.cos_e[e[0]]) + value_of(s.cos_e[e[1]]) + value_of(s.cos_e[e[2]]);
  }
  atan2_all(num.data(), den.data(), angle.data(), F);
  double sum = 0;
  for (double a : angle) sum += a;
  return sum / (2 * kPi);
}

/// The coordinates in `w` (normalized) of x: Ju et al.'s figure 4, for a scalar type T
/// that is double or an automatic-differentiation scalar, in passes over the vertices,
/// the edges and the triangles (each edge's angle is shared by its two triangles, and the
/// transcendental calls run over whole arrays).
template <class T>
void coordinates(const MeanValueCage& cage, const Eigen::Matrix<T, 3, 1>& x, std::vector<T>& w, double* winding) {
  thread_local Scratch<T> s;
  w.assign(static_cast<std::size_t>(cage.points.cols()), T(0.0));
  if (winding) *winding = 1;  // on the cage: not outside
  const long on_vertex = vertex_terms(cage, x, s);
  if (on_vertex >= 0) {
    w[static_cast<std::size_t>(on_vertex)] = T(1.0);
    return;
  }
  edge_terms(cage, s);
  const std::size_t F = cage.triangles.size();
  s.h.resize(F);
  for (std::size_t f = 0; f < F; ++f) {
    const auto& e = cage.opposite_edges[f];
    s.h[f] = (s.theta[e[0]] + s.theta[e[1]] + s.theta[e[2]]) / 2.0;
    if (kPi - value_of(s.h[f]) < kOnTriangle) {  // x on the triangle: its barycentric coordinates
      const T sin_theta[3] = {s.sin_e[e[0]], s.sin_e[e[1]], s.sin_e[e[2]]};
      on_triangle(cage.triangles[f], sin_theta, s.d, w);
      return;
    }
  }
  sincos_each(s.h, s.sin_h, s.cos_h);
  T total(0.0);
  for (std::size_t f = 0; f < F; ++f) triangle_weights(cage, f, s, w, total);
  for (T& wi : w) wi /= total;
  if (winding) *winding = winding_from_angles(cage, s);
}

}  // namespace

MeanValueCage mean_value_cage(Eigen::Matrix3Xd points, std::vector<std::array<std::uint32_t, 3>> triangles) {
  MeanValueCage cage;
  cage.points = std::move(points);
  cage.triangles = std::move(triangles);
  if (cage.points.cols() > 0)
    cage.diagonal = (cage.points.rowwise().maxCoeff() - cage.points.rowwise().minCoeff()).norm();
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> index;
  for (const auto& t : cage.triangles) {
    std::array<std::uint32_t, 3> opposite{};
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = std::min(t[(i + 1) % 3], t[(i + 2) % 3]), b = std::max(t[(i + 1) % 3], t[(i + 2) % 3]);
      const auto [at, fresh] = index.emplace(std::make_pair(a, b), static_cast<std::uint32_t>(cage.edges.size()));
      if (fresh) cage.edges.push_back({a, b});
      opposite[i] = at->second;
    }
    cage.opposite_edges.push_back(opposite);
  }
  return cage;
}

void mean_value_coordinates(const MeanValueCage& cage, const Eigen::Vector3d& x, Eigen::VectorXd& w,
                            Eigen::Matrix3Xd* gradient, double* winding) {
  const Eigen::Index m = cage.points.cols();
  w.resize(m);
  if (!gradient) {
    thread_local std::vector<double> out;
    coordinates<double>(cage, x, out, winding);
    for (Eigen::Index j = 0; j < m; ++j) w[j] = out[static_cast<std::size_t>(j)];
    return;
  }
  using Dual = Eigen::AutoDiffScalar<Eigen::Vector3d>;
  Eigen::Matrix<Dual, 3, 1> xd;
  for (int a = 0; a < 3; ++a) xd[a] = Dual(x[a], Eigen::Vector3d::Unit(a));
  thread_local std::vector<Dual> out;
  coordinates<Dual>(cage, xd, out, winding);
  gradient->resize(3, m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const Dual& o = out[static_cast<std::size_t>(j)];
    w[j] = o.value();
    gradient->col(j) = o.derivatives().size() ? Eigen::Vector3d(o.derivatives()) : Eigen::Vector3d::Zero();
  }
}

double winding_number(const MeanValueCage& cage, const Eigen::Vector3d& x) {
  const std::size_t F = cage.triangles.size();
  thread_local std::vector<double> num, den, angle;
  num.resize(F), den.resize(F), angle.resize(F);
  for (std::size_t f = 0; f < F; ++f) {
    const auto& t = cage.triangles[f];
    const Eigen::Vector3d a = cage.points.col(t[0]) - x, b = cage.points.col(t[1]) - x, c = cage.points.col(t[2]) - x;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    num[f] = a.dot(b.cross(c));
    den[f] = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
  }
  atan2_all(num.data(), den.data(), angle.data(), F);
  double sum = 0;
  for (double a : angle) sum += 2 * a;
  return sum / (4 * kPi);
}

}  // namespace ffd
