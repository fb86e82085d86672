// Warp: a map of 3-space onto itself with its Jacobian, the unit of the warp stack.
//
// Normals go through the covariant rule, n' = cof(J) n = det(J) J^-T n (Gain & Dodgson
// eq. 2-3, the adjoint's transpose; scale factors dropped, so the result is renormalized),
// tangents through the contravariant rule t' = J t. Both keep n'·t' = det(J) n·t = 0.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

namespace ffd {

/// Counts a warp reports for one batch evaluation.
struct WarpCounts {
  std::size_t evaluated = 0;  // points the warp actually moved or re-evaluated
  std::size_t folded = 0;     // points where det(J) <= 0: the warp folds space over
};

class Warp {
public:
  virtual ~Warp() = default;

  /// F(x), and the Jacobian dF/dx at x when `jacobian` is given.
  virtual Eigen::Vector3d apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const = 0;

  /// For each column index v in `ids`: out_pos.col(v) = F(in_pos.col(v)) and
  /// out_nrm.col(v) = unit cof(J) in_nrm.col(v) (zero normals stay zero). Other columns are
  /// left alone. Deterministic for any thread count.
  virtual void apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                     const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
                     const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                     Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const = 0;

  /// apply() for points whose normals are all zero (a run that needs no normals:
  /// Mesh::normals_deferred), when the warp can give the same positions and counts
  /// without them: out_pos as apply() writes it, normals left alone (apply() would write
  /// zeros). False: it cannot here, and wrote nothing; the caller uses apply().
  virtual bool apply_without_normals(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                     const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                                     WarpCounts& counts) const {
    return false;
  }

  /// changed_points() and then apply() on what it found, in one pass over in_pos: `ids`
  /// gets what changed_points() would append, the outputs and counts are apply()'s. With
  /// `in_nrm` and `out_nrm` null, apply_without_normals()'s instead. False: the warp has
  /// no such pass (it wrote nothing); the caller makes the two calls.
  virtual bool apply_changed(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                             const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm, std::vector<std::uint32_t>& ids,
                             Eigen::Ref<Eigen::Matrix3Xd> out_pos, Eigen::Ref<Eigen::Matrix3Xd>* out_nrm,
                             WarpCounts& counts) const {
    return false;
  }

  /// Appends to `ids` the columns of `in_pos` that lie where the warp changed since the
  /// last clear_changes() (Gain & Dodgson's bit index of altered cells).
  virtual void changed_points(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                              std::vector<std::uint32_t>& ids) const = 0;
  virtual bool has_changes() const = 0;
  virtual void clear_changes() = 0;
  /// Brings caches up to date after changes; called before batch evaluation.
  virtual void prepare() {}

  /// Whether the warp can act anywhere on the segment [a, b] of its input space (ends
  /// included). False promises F(x) = x bit for bit along the whole segment, whatever the
  /// warp's points do; ops use it to confine work to where the warps act (remesh: the
  /// Lmax rule). The default, true, is right for a warp that cannot bound where it acts.
  virtual bool can_act_on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const { return true; }
  /// The smallest length, in input-space units, over which the warp's control can vary
  /// the deformation (a lattice: its smallest cell extent); 0 when it has no such scale.
  /// Gain & Dodgson's Lmax is the smallest over the stack.
  virtual double feature_size() const { return 0; }
};

/// cof(J) n: the covariant transform of a normal, unnormalized.
inline Eigen::Vector3d cofactor_times(const Eigen::Matrix3d& J, const Eigen::Vector3d& n) {
  return J.col(1).cross(J.col(2)) * n[0] + J.col(2).cross(J.col(0)) * n[1] +
         J.col(0).cross(J.col(1)) * n[2];
}

/// unit cof(J) n: a normal through the warp (a zero result stays zero).
inline Eigen::Vector3d transformed_normal(const Eigen::Matrix3d& J, const Eigen::Vector3d& n) {
  const Eigen::Vector3d m = cofactor_times(J, n);
  const double len = m.norm();
  return len > 0 ? Eigen::Vector3d(m / len) : Eigen::Vector3d::Zero();
}

/// The cofactor matrix cof(J) = det(J) J^-T, well defined for singular J too.
inline Eigen::Matrix3d cofactor(const Eigen::Matrix3d& J) {
  Eigen::Matrix3d C;
  C.col(0) = J.col(1).cross(J.col(2));
  C.col(1) = J.col(2).cross(J.col(0));
  C.col(2) = J.col(0).cross(J.col(1));
  return C;
}

/// The contravariant transform of a tangent: J t.
inline Eigen::Vector3d transform_tangent(const Eigen::Matrix3d& J, const Eigen::Vector3d& t) {
  return J * t;
}

}  // namespace ffd
