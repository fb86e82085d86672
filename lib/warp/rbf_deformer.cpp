#include "warp/rbf_deformer.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/errors.h"
#include "common/numbers.h"
#include "common/supernodal_cholesky.h"
#include "warp/point_tree.h"

namespace ffd {
namespace {

/// Below this reciprocal condition number the system is refused as singular.
constexpr double kMinRcond = 1e-15;
/// Control points per block of the vectorized kernel sums (the arrays live on the stack).
constexpr int kBlock = 128;
using BlockArray = Eigen::Array<double, Eigen::Dynamic, 1, 0, kBlock, 1>;

/// s^k log s and, in `over_r`, its derivative by r over r (s = r / R), both 0 at s = 0.
double power_log(double s, int k, double R, double* over_r) {
  if (s <= 0) {
    if (over_r) *over_r = 0;
    return 0;
  }
  const double log_s = std::log(s);
  if (over_r) *over_r = std::pow(s, k - 2) * (k * log_s + 1) / (R * R);
  return std::pow(s, k) * log_s;
}

/// Entries `ids[b..b+m)` of `column`, or, when `ids` is null, entries b..b+m.
void gather(const double* column, const std::uint32_t* ids, Eigen::Index b, Eigen::Index m, BlockArray& out) {
  if (!ids) {
    out = Eigen::Map<const BlockArray>(column + b, m);
    return;
  }
  out.resize(m);
  for (Eigen::Index t = 0; t < m; ++t) out[t] = column[ids[b + t]];
}

/// s^k for a small integer k (negative: of 1 / s), by multiplication: vectorizes, unlike pow.
BlockArray power(const BlockArray& s, int k) {
  const BlockArray base = k < 0 ? BlockArray(s.inverse()) : s;
  BlockArray out = BlockArray::Ones(s.size());
  for (int i = 0; i < std::abs(k); ++i) out *= base;
  return out;
}

/// phi and, when `over_r` is given, phi'(r) / r of a block of squared distances: the
/// vectorized form of rbf_kernel (Eigen's packet exp, log and sqrt, inlined: SLEEF's
/// vector exp and log, called per four lanes, made 5k x 1M evaluations 20-25% slower).
void kernel_block(const RbfOptions& o, const BlockArray& r2, BlockArray& phi, BlockArray* over_r) {
  // Divisions by R as products with its reciprocals: a vector division costs several products.
  const double R2 = o.radius * o.radius, inv_R = 1 / o.radius, inv_R2 = 1 / R2;
  switch (o.kernel) {
    case RbfKernel::Gaussian:
      phi = (r2 * -inv_R2).exp();
      if (over_r) *over_r = -2 * inv_R2 * phi;
      return;
    case RbfKernel::MultiQuadratic:
      phi = (r2 + R2).sqrt();
      if (over_r) *over_r = phi.inverse();
      return;
    case RbfKernel::InvMultiQuadratic:
      phi = (r2 + R2).rsqrt();
      if (over_r) *over_r = -phi * phi * phi;
      return;
    case RbfKernel::Wendland: {
      const BlockArray s = r2.sqrt() * inv_R, t = (1 - s).max(0.0), t3 = t * t * t;
      phi = t3 * t * (4 * s + 1);
      if (over_r) *over_r = -20 * inv_R2 * t3;
      return;
    }
    case RbfKernel::Polyharmonic:
      if (o.k % 2 == 1) {
        const BlockArray s = r2.sqrt() * inv_R;
        phi = power(s, o.k);
        if (over_r) *over_r = (r2 > 0).select(o.k * inv_R2 * power(s, o.k - 2), 0.0);
        return;
      }
      [[fallthrough]];
    case RbfKernel::ThinPlate: {
      // s^k log s, log s = log(s^2) / 2; 0 at s = 0, where s^2 is raised to the smallest
      // normal double so that the log stays finite (phi is then 0 times a finite number;
      // phi'/r there only ever multiplies x - x_i = 0). Even k: s^k = (s^2)^(k/2), no root.
      const BlockArray s2 = r2 * inv_R2, log_s = 0.5 * s2.max(std::numeric_limits<double>::min()).log();
      if (o.k == 2) {  // the classical thin-plate spline, without the powers
        phi = s2 * log_s;
        if (over_r) *over_r = (2 * log_s + 1) * inv_R2;
        return;
      }
      const BlockArray s_k2 = o.k % 2 == 0 ? power(s2, o.k / 2 - 1) : BlockArray(power(s2.sqrt(), o.k - 2));
      phi = (r2 > 0).select(s_k2 * s2 * log_s, 0.0);
      if (over_r) *over_r = (r2 > 0).select(s_k2 * (o.k * log_s + 1) * inv_R2, 0.0);
      return;
    }
  }
}

}  // namespace

double rbf_kernel(const RbfOptions& o, double r, double* over_r) {
  const double R = o.radius, s = r / R;
  double d = 0, phi = 0;
  switch (o.kernel) {
    case RbfKernel::Gaussian:
      phi = std::exp(-s * s);
      d = -2 * phi / (R * R);
      break;
    case RbfKernel::MultiQuadratic:
      phi = std::sqrt(r * r + R * R);
      d = 1 / phi;
      break;
    case RbfKernel::InvMultiQuadratic: {
      const double q = std::sqrt(r * r + R * R);
      phi = 1 / q;
      d = -phi / (q * q);
      break;
    }
    case RbfKernel::ThinPlate:
      return power_log(s, o.k, R, over_r);
    case RbfKernel::Wendland:
      if (s < 1) {
        const double t = 1 - s;
        phi = t * t * t * t * (4 * s + 1);
        d = -20 * t * t * t / (R * R);
      }
      break;
    case RbfKernel::Polyharmonic:
      // PyGeM's even-k formula, s^(k-1) log(s^s) below 1 and s^k log s above, is s^k log s.
      if (o.k % 2 == 0) return power_log(s, o.k, R, over_r);
      phi = std::pow(s, o.k);
      d = s > 0 ? o.k * std::pow(s, o.k - 2) / (R * R) : 0;
      break;
  }
  if (over_r) *over_r = d;
  return phi;
}

/// The factorized system H = [Phi P; P^T 0]: a dense LU for global kernels. For the
/// compact kernel, whose Phi is sparse and positive definite (Wendland's C2 function is,
/// in up to three dimensions), the supernodal Cholesky of Phi and the 4 x 4 Schur
/// complement S = P^T Phi^-1 P: for [r; q], y = Phi^-1 r, a = S^-1 (P^T y - q),
/// gamma = y - Phi^-1 P a. Also the interface Eigen's 1-norm condition estimator
/// (Hager/Higham, the one PartialPivLU::rcond uses) needs: solve, and adjoint() solving
/// with H^T = H.
struct RbfDeformer::System {
  using MatrixType = Eigen::MatrixXd;
  using Scalar = double;
  using RealScalar = double;
  Eigen::PartialPivLU<Eigen::MatrixXd> dense;
  SupernodalCholesky phi;
  Eigen::MatrixXd P, phi_inv_P;  // n x 4: [1 x y z] per point, and Phi^-1 P
  Eigen::PartialPivLU<Eigen::Matrix4d> schur;
  bool is_sparse = false;
  Eigen::Index size = 0;

  Eigen::Index rows() const { return size; }
  Eigen::Index cols() const { return size; }
  const System& adjoint() const { return *this; }  // H is symmetric
  Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const {
    if (!is_sparse) return dense.solve(rhs);
    const Eigen::Index n = size - 4;
    const Eigen::MatrixXd y = phi.solve(rhs.topRows(n));
    const Eigen::MatrixXd a = schur.solve(P.transpose() * y - rhs.bottomRows(4));
    Eigen::MatrixXd out(size, rhs.cols());
    out.topRows(n) = y - phi_inv_P * a;
    out.bottomRows(4) = a;
    return out;
  }
};

RbfDeformer::RbfDeformer(std::vector<Eigen::Vector3d> rest, const RbfOptions& options)
    : ScatteredDeformer(std::move(rest), "control points"), options_(options), system_(std::make_unique<System>()) {
  check_layout();
  const Eigen::Index n = static_cast<Eigen::Index>(rest_.size());
  rest_columns_.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) rest_columns_.row(i) = rest_[static_cast<std::size_t>(i)].transpose();
  if (options_.kernel == RbfKernel::Wendland) {
    tree_ = std::make_unique<PointTree>(rest_);
    factorize_sparse();
  } else {
    factorize_dense();
  }
  coefficients_ = Eigen::MatrixXd::Zero(n + 4, 3);
}

RbfDeformer::~RbfDeformer() = default;

Eigen::MatrixXd RbfDeformer::polynomial_rows() const {
  Eigen::MatrixXd P(rest_columns_.rows(), 4);
  P.col(0).setOnes();
  P.rightCols(3) = rest_columns_;
  return P;
}

void RbfDeformer::factorize_dense() {
  const Eigen::Index n = rest_columns_.rows();
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n + 4, n + 4);
  Eigen::VectorXd row(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    kernel_values(rest_[static_cast<std::size_t>(i)], nullptr, n, row.data());
    H.row(i).head(n) = row.transpose();
  }
  const Eigen::MatrixXd P = polynomial_rows();
  H.topRightCorner(n, 4) = P;
  H.bottomLeftCorner(4, n) = P.transpose();
  entries_ = static_cast<std::size_t>(H.size());
  system_->size = n + 4;
  system_->dense.compute(H);
  check_condition(H.cwiseAbs().colwise().sum().maxCoeff(), true);
}

void RbfDeformer::factorize_sparse() {
  const Eigen::Index n = rest_columns_.rows();
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<std::uint32_t> ids;
  std::vector<double> values;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d& x = rest_[static_cast<std::size_t>(i)];
    tree_->within(x, options_.radius, ids);
    values.resize(ids.size());
    kernel_values(x, ids.data(), static_cast<Eigen::Index>(ids.size()), values.data());
    for (std::size_t t = 0; t < ids.size(); ++t) entries.emplace_back(i, ids[t], values[t]);
  }
  entries_ = entries.size() + 8 * static_cast<std::size_t>(n);  // with the polynomial's
  Eigen::SparseMatrix<double> phi(n, n);
  phi.setFromTriplets(entries.begin(), entries.end());
  System& s = *system_;
  s.size = n + 4;
  s.is_sparse = true;
  s.P = polynomial_rows();
  bool factorized = s.phi.compute(phi);
  if (factorized) {
    s.phi_inv_P = s.phi.solve(s.P);
    s.schur.compute(s.P.transpose() * s.phi_inv_P);
    factorized = s.schur.rcond() > kMinRcond;
  }
  // H's 1-norm: the largest column sum of |Phi| plus its polynomial rows, or of P's columns.
  double norm = s.P.cwiseAbs().colwise().sum().maxCoeff();
  for (Eigen::Index j = 0; j < phi.outerSize(); ++j)
    norm = std::max(norm, phi.col(j).cwiseAbs().sum() + s.P.row(j).cwiseAbs().sum());
  check_condition(norm, factorized);
}

void RbfDeformer::check_condition(double norm, bool factorized) {
  const double rcond = factorized ? Eigen::internal::rcond_estimate_helper(norm, *system_) : 0;
  condition_ = rcond > 0 ? 1 / rcond : std::numeric_limits<double>::infinity();
  if (!(rcond >= kMinRcond))
    throw InputError("the RBF system of these control points is singular (estimated condition number " +
                         format_number(condition_) + ")",
                     {"points"});
}

void RbfDeformer::check_layout() const {
  const std::size_t n = rest_.size();
  if (n < 4) throw InputError("an RBF needs at least 4 control points (it has " + std::to_string(n) + ")", {"points"});
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : rest_) centroid += p / static_cast<double>(n);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : rest_) scatter += (p - centroid) * (p - centroid).transpose();
  const Eigen::Vector3d eig = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();
  if (!(eig[0] > 1e-24 * eig[2]))
    throw InputError("the control points lie in one plane (or on one line): the RBF's linear polynomial needs them "
                     "to span 3D",
                     {"points"});
}

void RbfDeformer::update_after_move() {
  const Eigen::Index n = static_cast<Eigen::Index>(rest_.size());
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n + 4, 3);
  for (Eigen::Index i = 0; i < n; ++i)
    rhs.row(i) = (current_[static_cast<std::size_t>(i)] - rest_[static_cast<std::size_t>(i)]).transpose();
  coefficients_ = moved() ? system_->solve(rhs) : Eigen::MatrixXd::Zero(n + 4, 3);
}

void RbfDeformer::kernel_values(const Eigen::Vector3d& x, const std::uint32_t* ids, Eigen::Index count,
                                double* out) const {
  BlockArray e[3], phi;
  for (Eigen::Index b = 0; b < count; b += kBlock) {
    const Eigen::Index m = std::min<Eigen::Index>(kBlock, count - b);
    for (int a = 0; a < 3; ++a) {
      gather(rest_columns_.col(a).data(), ids, b, m, e[a]);
      e[a] = x[a] - e[a];
    }
    kernel_block(options_, e[0] * e[0] + e[1] * e[1] + e[2] * e[2], phi, nullptr);
    std::copy(phi.data(), phi.data() + m, out + b);
  }
}

Eigen::VectorXd RbfDeformer::basis_row(const Eigen::Vector3d& x) const {
  const Eigen::Index n = static_cast<Eigen::Index>(rest_.size());
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n + 4);
  if (tree_) {
    std::vector<std::uint32_t> ids;
    tree_->within(x, options_.radius, ids);
    std::vector<double> values(ids.size());
    kernel_values(x, ids.data(), static_cast<Eigen::Index>(ids.size()), values.data());
    for (std::size_t t = 0; t < ids.size(); ++t) b[ids[t]] = values[t];
  } else {
    kernel_values(x, nullptr, n, b.data());
  }
  b[n] = 1;
  b.tail<3>() = x;
  return b;
}

void RbfDeformer::movable_weights(int, const Eigen::Vector3d& x, PointWeights& out) const {
  out.clear();
  const Eigen::VectorXd w = system_->solve(basis_row(x));  // H^-1 b(x) = H^-T b(x): H is symmetric
  for (std::size_t i = 0; i < rest_.size(); ++i)
    if (w[static_cast<Eigen::Index>(i)] != 0) out.emplace_back(i, w[static_cast<Eigen::Index>(i)]);
}

void RbfDeformer::add_terms(const Eigen::Vector3d& x, const std::uint32_t* ids, Eigen::Index count, Eigen::Vector3d& d,
                            Eigen::Matrix3d* jacobian) const {
  // D(x) += sum gamma_i phi(r_i); dD/dx += sum gamma_i (phi'/r)(x - x_i)^T, per block.
  BlockArray e[3], g[3], phi, over_r;
  for (Eigen::Index b = 0; b < count; b += kBlock) {
    const Eigen::Index m = std::min<Eigen::Index>(kBlock, count - b);
    for (int a = 0; a < 3; ++a) {
      gather(rest_columns_.col(a).data(), ids, b, m, e[a]);
      e[a] = x[a] - e[a];
      gather(coefficients_.col(a).data(), ids, b, m, g[a]);
    }
    const BlockArray r2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
    kernel_block(options_, r2, phi, jacobian ? &over_r : nullptr);
    for (int a = 0; a < 3; ++a) d[a] += (phi * g[a]).sum();
    if (!jacobian) continue;
    for (int a = 0; a < 3; ++a) {
      const BlockArray og = over_r * g[a];
      for (int c = 0; c < 3; ++c) (*jacobian)(a, c) += (og * e[c]).sum();
    }
  }
}

Eigen::Vector3d RbfDeformer::apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const {
  if (jacobian) jacobian->setIdentity();
  const Eigen::Index n = static_cast<Eigen::Index>(rest_.size());
  if (!moved()) return x;  // unmoved: the identity, bit for bit
  // The polynomial part c + Q x, then the kernel terms.
  Eigen::Vector3d d = coefficients_.row(n).transpose() + coefficients_.bottomRows<3>().transpose() * x;
  if (jacobian) *jacobian += coefficients_.bottomRows<3>().transpose();
  if (tree_) {
    thread_local std::vector<std::uint32_t> ids;
    tree_->within(x, options_.radius, ids);
    add_terms(x, ids.data(), static_cast<Eigen::Index>(ids.size()), d, jacobian);
  } else {
    add_terms(x, nullptr, n, d, jacobian);
  }
  return x + d;
}

}  // namespace ffd
