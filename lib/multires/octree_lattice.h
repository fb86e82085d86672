// OctreeLattice: Ono et al.'s multiresolution lattices as a space warp.
//
// Levels 0..L: level 0 is the box (one cell); level l+1 is the octree subdivision of
// level l (section 2.1) with the cells that hold no region vertex cut. Every level is a
// GridComplex at resolution 2^l. With `shrink`, each level's boundary points are moved
// toward the region along each axis, keeping the offset (section 2.2).
//
// The deformation (section 3.2, as an exact function of the lattice state):
//   F(x) = x + sum over levels l of  sum_c w_c(u) D_l^k(c)
// where (k, cell, u) is where x lies in C^k(R_l), the k-th Catmull-Clark subdivision of
// level l's rest lattice R_l (the finest k <= cc_steps whose lattice holds x: the
// "minimal cell"), w_c are the trilinear weights of that hexahedral cell's corners, and
// D_l^k = C^k(delta_l) is the subdivision of the user's moves at level l. By linearity of
// the rules, x + sum w_c D(c) is exactly the relocation of x in C^k(R_l + delta_l) with
// its parameters from C^k(R_l): the paper's pairs L_A and L_B.
//
// Hierarchical editing (section 4.1): level l's points as shown and moved are
//   R_l + O(shown_{l-1} - R_{l-1}) + delta_l,
// the octree subdivision O of the coarser level's deformation plus the level's own moves.
// Each level's moves act through parameters of the undeformed model, so moving a finer
// level after a coarser one adds its field to the coarser one's and changing level does
// not move the model at all. This is the exact equivalent of the paper's lookup table:
// F_{l+1}(x) = F_l(x) + [G(x; O(L_l') + delta) - G(x; O(L_l'))], and G is linear.
//
// Locality (section 3.2): moving points S at level l re-subdivides only the cells of
// N_{S,3}, which is exact (the paper takes N_{S,4}; see update_displacements), or, on a
// small level, multiplies again the rows of the steps' matrices that read what changed,
// and marks the cells of N_{S,3}:
// changed_points() reports only the vertices there; every other vertex is untouched.
// Points outside every cell of every moved level are never changed, bit for bit. The rest
// lattice's subdivisions C^k(R_l) are local too: a level of more than kBuiltLevelCells
// cells builds no C^k topology (StepGrid implies it from the level's grid), and a level's
// first move subdivides the rest positions only in the cells it marks (and the cells
// where locating a vertex walks, which the batch apply subdivides together after its
// other vertices), into fields that stay untouched memory elsewhere, so a first move
// costs about what a later one does.
//
// Local subdivision (section 2.2, Figure 3): subdivide() adds a level made of chosen cells
// of a level split by the octree rules (a SubdividedLevel, of general topology), shown
// from that level's deformation and moved like any other.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "common/zeroed_array.h"
#include "multires/cell_coordinates.h"
#include "multires/grid_complex.h"
#include "multires/step_grid.h"
#include "multires/subdivided_level.h"
#include "multires/volume_subdivision.h"
#include "warp/deformer.h"
#include "warp/parallelepiped.h"

namespace ffd {

struct OctreeOptions {
  int levels = 3;        // octree subdivisions of the box
  int cc_steps = 2;      // Catmull-Clark volume subdivisions n
  double shrink = -1;    // offset of shrunk boundary points from the region; < 0: no shrink
  /// Levels with at most this many cells move by their Catmull-Clark steps' matrices,
  /// C^k(delta) = S_k C^(k-1)(delta), each row summed as the whole matrix's product sums
  /// it; the rows are built where moves reach and kept, so a later move near the same
  /// points only multiplies. Larger levels subdivide each move's change over N_{S,3} and
  /// add it (equal to rounding). When the whole matrices were built on a level's first
  /// move, measured on refined_elephant, one thread: a move at 175 cells took 0.34 ms by
  /// matrices against 2.3 by N_{S,3}, at 751 cells 1.5 against 3.1, at 2,994 cells 7.1
  /// against 2.4. 512 keeps the outputs of the levels that moved by matrices then.
  std::size_t whole_level_cells = 512;
};

/// What one move of a level did.
struct OctreeMove {
  std::size_t points_moved = 0;
  std::size_t cells_subdivided = 0;  // cells of the level that were Catmull-Clark subdivided
  std::size_t cells_marked = 0;      // cells of N_{S,3}, whose vertices are relocated
};

/// "the corners of level 2's cells, grid nodes [i, j, k] in [0, 4]", for messages
/// (`resolution`: 2^level, or a local level's).
std::string octree_points_text(int level, int resolution);

class OctreeLattice : public Deformer {
public:
  /// Builds the levels on `box` around the region points (columns of `region`, in the
  /// warp's input space). Region points outside the box are ignored.
  OctreeLattice(const Parallelepiped& box, const Eigen::Matrix3Xd& region, const OctreeOptions& options);

  const Parallelepiped& box() const { return box_; }
  const OctreeOptions& options() const { return options_; }
  /// The octree levels 0..options().levels, then one per local subdivision.
  int num_levels() const override { return static_cast<int>(levels_.size() + local_.size()); }
  int num_grid_levels() const { return static_cast<int>(levels_.size()); }
  /// Whether `level` was made by local subdivision (subdivide()).
  bool is_local(int level) const { return level >= num_grid_levels(); }
  const SubdividedLevel& local(int level) const { return *local_[static_cast<std::size_t>(level - num_grid_levels())].level; }
  /// The grid of an octree level (not a local one).
  const GridComplex& complex(int level) const { return levels_[level].sub[0]; }
  /// Cells of refine(level - 1) cut because they hold no region vertex (0 at level 0).
  std::size_t cut_cells(int level) const { return is_local(level) ? 0 : levels_[level].cut; }
  std::size_t num_points(int level) const override;
  std::size_t num_cells(int level) const;
  /// Grid nodes per axis of the level's point indices, minus one (2^level; twice the
  /// source's for a local level).
  int resolution(int level) const;
  /// Each edge of the level's cells once, as pairs of point indices.
  std::vector<std::array<std::int32_t, 2>> edges(int level) const;
  /// Subdivides the cells `cells` (indices into complex(level).cells) of octree level
  /// `level` by the octree rules, as a new level made from the level as shown (global to
  /// local, so nothing moves); returns its index. \throw std::invalid_argument for a local level.
  int subdivide(int level, const std::vector<std::int32_t>& cells);
  /// Rest positions of the level's points (columns, in `complex(level).points` order).
  const Eigen::Matrix3Xd& rest_points(int level) const {
    return is_local(level) ? local(level).rest() : levels_[level].rest;
  }
  /// The level's points as shown and moved: rest + O(coarser deformation) + own moves.
  Eigen::Matrix3Xd points(int level) const override;
  using Deformer::points;
  /// Index of the level's point at grid node `node`, or -1.
  std::int32_t point_index(int level, const GridIndex& node) const {
    return is_local(level) ? local(level).point_index(node) : complex(level).point(node);
  }

  /// Moves the level's points `ids` to `targets` (shown positions) and brings the
  /// subdivided displacement fields up to date (N_{S,3}), marking N_{S,3} as changed.
  OctreeMove move_level_points(int level, const std::vector<std::int32_t>& ids,
                               const std::vector<Eigen::Vector3d>& targets);
  /// The weights at x of the level's points: F(x) changes by sum w_j d_j when point j's
  /// shown position moves by d_j. Empty when x lies in no cell of the level.
  void point_weights(int level, const Eigen::Vector3d& x, std::vector<std::pair<std::int32_t, double>>& out) const;
  /// "the corners of level 2's cells, grid nodes [i, j, k] in [0, 4]", for messages.
  std::string movable_text(int level) const override;

  // Deformer: ids are the level's point indices; every point is movable.
  std::string kind() const override { return "octree"; }
  bool has_levels() const override { return true; }
  std::optional<std::size_t> find_point(int level, const PointIndex& index) const override;
  std::string missing_point(int level, const PointIndex& index) const override;
  PointIndex point_index(int level, std::size_t id) const override;
  /// move_level_points; the report counts cells_subdivided and cells_relocated.
  MoveReport move_points(int level, const std::vector<std::size_t>& ids,
                         const std::vector<Eigen::Vector3d>& targets) override;
  /// point_weights, which are the weights of the movable points (all of them).
  void movable_weights(int level, const Eigen::Vector3d& x, PointWeights& out) const override;
  std::vector<std::array<std::uint32_t, 2>> net_edges(int level) const override;
  double scale() const override { return box_.extents().norm(); }

  /// Bytes held by the levels and their Catmull-Clark subdivisions.
  std::size_t bytes() const;
  /// Vertices the batch apply has located in a level's subdivided rest lattices so far
  /// (a vertex is located once per level, when a move first marks its cell).
  std::size_t vertices_located() const { return located_.load(); }
  /// Cells of grid level `level` whose rest lattice has been Catmull-Clark subdivided.
  std::size_t rest_cells_subdivided(int level) const;

  // Warp
  Eigen::Vector3d apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const override;
  void apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
             const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
             Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const override;
  /// The positions and counts apply() gives, without the normals' cofactor products: a
  /// run that needs no normals (their pages then stay untouched).
  bool apply_without_normals(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const std::vector<std::uint32_t>& ids,
                             Eigen::Ref<Eigen::Matrix3Xd> out_pos, WarpCounts& counts) const override;
  void changed_points(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, std::vector<std::uint32_t>& ids) const override;
  bool has_changes() const override { return any_changed_; }
  void clear_changes() override;
  bool can_act_on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const override;
  double feature_size() const override;

  /// Where x lies in level `level`'s subdivided rest lattices: step k, cell, coordinates.
  struct Location {
    int step = -1;
    std::int32_t cell = -1;
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
  };
  /// False when x lies in no cell of C^k(R_level) for any k.
  bool locate(int level, const Eigen::Vector3d& x, Location& where) const;
  /// The same for x at box coordinates t (box().to_local(x)); dx_du, when given, receives
  /// the rest cell's Jacobian d x / d u there.
  bool locate(int level, const Eigen::Vector3d& x, const Eigen::Vector3d& t, Location& where,
              Eigen::Matrix3d* dx_du = nullptr) const;
  /// The k-th Catmull-Clark subdivision of the level's rest lattice (k = 0: the level),
  /// built on first use, and its points' positions (the whole level subdivided). A level
  /// of more than kBuiltLevelCells cells never builds its C^k topology itself (StepGrid):
  /// for it these are built on the call, for inspection (tests, benchmarks), and kept
  /// beside the lattice's own data.
  const GridComplex& subdivided(int level, int k) const;
  const Eigen::Matrix3Xd& subdivided_rest(int level, int k) const;
  /// C^k(delta), the k-th subdivision of the grid level's own moves, on the points of
  /// subdivided(level, k), for inspection (tests).
  Eigen::Matrix3Xd subdivided_moves(int level, int k) const;

private:
  /// A level's marks over the cells of its grid (a local level: of its node grid), dense:
  /// the cells of N_{S,3} since clear_changes(), where its displacement may be non-zero
  /// (never cleared), and how many marks each cell had (a tag's part is for one count).
  struct Marks {
    int resolution = 1;
    std::vector<std::uint8_t> changed, active;
    std::vector<std::uint32_t> epochs;
    bool any_changed = false;  // some cell is in `changed`
    std::size_t active_cells = 0;
    explicit Marks(int res = 1);
    void mark(std::size_t cell) {
      active_cells += !active[cell];
      changed[cell] = active[cell] = 1, ++epochs[cell], any_changed = true;
    }
    bool all_active() const { return active_cells == active.size(); }
    void clear_changes();
    std::size_t bytes() const { return changed.size() + active.size() + sizeof(std::uint32_t) * epochs.size(); }
  };
  /// A 3 x n field over the points (or slots) of C^k, zero until written (ZeroedArray).
  struct Field {
    ZeroedArray<double> values;
    Eigen::Index cols = 0;
    explicit Field(Eigen::Index n = 0) : values(3 * static_cast<std::size_t>(n)), cols(n) {}
    Eigen::Map<Eigen::Matrix3Xd> map() { return {values.data(), 3, cols}; }
    Eigen::Map<const Eigen::Matrix3Xd> map() const { return {values.data(), 3, cols}; }
  };
  /// Levels of at most this many cells (4^3: levels 0-2 of a full octree) build the
  /// topology of their C^k (ensure_subdivided says why).
  static constexpr std::size_t kBuiltLevelCells = 64;
  struct Level {
    // sub[k] = C^k topology; sub[0] the level itself. Only levels of at most
    // kBuiltLevelCells cells build k >= 1: another level's C^k is implied by its grid
    // (StepGrid), and fine[k], disp[k] and row_of[k - 1] are over its slots.
    std::vector<GridComplex> sub;
    std::vector<Eigen::Matrix3Xd> fine;    // fine[k] = C^k(R_l) positions, where `ready` says
    // Levels subdivide their rest lattice where it is needed (section 3.2: a move
    // subdivides N_{S,3}, not the level): per cell of the level's grid (dense), whether
    // fine[k] holds C^k(R_l) at every point of the cell's subdivisions, for every k; and per
    // step k >= 1 and point (or slot) of C^k, whether fine[k] holds it. Null `ready`: the
    // level is not subdivided yet (ensure_subdivided).
    std::unique_ptr<std::atomic<std::uint8_t>[]> ready;
    std::vector<ZeroedArray<std::uint8_t>> written;
    std::vector<Field> disp;               // disp[k] = C^k(delta_l)
    // Levels of at most options_.whole_level_cells cells, which move by their steps'
    // matrices: per step k >= 1, the rows of S_k built so far, and per point (or slot) of
    // C^k, 1 + its row there (0: not built yet). Empty: a level that moves by N_{S,3}.
    std::vector<SubdivisionRows> rows;
    std::vector<ZeroedArray<std::int32_t>> row_of;
    Eigen::Matrix3Xd rest, delta;
    Marks marks;
    std::size_t cut = 0;
    bool moved = false;
    bool stepped = false;  // the Catmull-Clark steps are set up (ensure_subdivided)
    /// C^k as the lattice reads it (a built complex for k = 0 and for levels of at most
    /// kBuiltLevelCells cells).
    StepGrid step_grid(int k) const {
      return {&sub[0], static_cast<std::size_t>(k) < sub.size() ? &sub[static_cast<std::size_t>(k)] : nullptr, k};
    }
  };
  struct Local {  // a local level and its marks on its node grid's cells
    std::unique_ptr<SubdividedLevel> level;
    Marks marks;
  };
  void build_levels(const Eigen::Matrix3Xd& region);
  OctreeMove move_local(int level, const std::vector<std::int32_t>& ids, const Eigen::Matrix3Xd& change);
  void shrink_level(int level, const Eigen::Matrix3Xd& box_coords);
  void ensure_subdivided(int level) const;
  /// Makes fine[k] hold C^k(R_level) on the given cells of the level's grid (existing
  /// ones), by subdividing them and cc_steps rings around them (what the rules read);
  /// thread-safe, and each point is written once, so readers of ready cells never race.
  void ensure_rest(int level, const std::vector<GridIndex>& cells) const;
  bool rest_ready(int level, const GridIndex& cell) const;
  void update_displacements(int level, const std::vector<std::int32_t>& ids, const Eigen::Matrix3Xd& change,
                            OctreeMove& report);
  /// A small level's update: the rows of S_k that read a point whose C^(k-1)(delta)
  /// changed, multiplied again, step by step from the moved points `ids`.
  void update_by_rows(int level, const std::vector<std::int32_t>& ids);
  void mark_changed(int level, const std::vector<std::int32_t>& ids, OctreeMove& report);
  /// The grid level's displacement at `where`; `jacobian`, when given, gains its gradient
  /// (the level's part of dF/dx - I); `bound2`, when given, receives the square of a bound
  /// of that gradient's 2-norm from the rest cell's Jacobian `dx_du` there.
  /// `corner`, when given, holds the cell's corners (else they are looked up).
  Eigen::Vector3d displacement(int level, const Location& where, Eigen::Matrix3d* jacobian,
                               const Eigen::Matrix3d* dx_du = nullptr, double* bound2 = nullptr,
                               const std::int32_t* corner = nullptr) const;
  /// F(x) - x summed over the moved levels, and whether x lies in a cell where some
  /// level's displacement may be non-zero (if not, F(x) = x exactly).
  bool displacement(const Eigen::Vector3d& x, Eigen::Vector3d& d, Eigen::Matrix3d* jacobian) const;
  bool moved(int level) const { return is_local(level) ? local(level).moved() : levels_[level].moved; }
  const Marks& marks(int level) const {
    return is_local(level) ? local_[static_cast<std::size_t>(level - num_grid_levels())].marks : levels_[level].marks;
  }
  /// Delta_l of grid level l: the octree rules' image of the coarser deformation plus its moves.
  const Eigen::MatrixXd& deformation(int level) const;
  void size_cache(Eigen::Index vertices) const;
  /// Gives a tag to each vertex of `ids` (inside the box) that lies in a cell a moved level
  /// marked active and has none there yet, and every tag room for its Jacobian part when
  /// asked; serial, before the parallel apply. Returns, per level, the index of its first
  /// new tag (its number of tags before).
  std::vector<std::size_t> assign_tags(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                       const std::vector<std::uint32_t>& ids, bool with_jacobians) const;
  /// Where locate()'s tries at the finest step found x, when they did: the batch apply
  /// locates the new tags of a block of vertices four at a time (TrilinearLanes) before
  /// applying them.
  struct Located {
    bool found = false;
    Location where;
    Eigen::Matrix3d dx_du;
    std::int32_t corner[8];  // the cell's corners (StepGrid::corners), read by displacement()
  };
  /// The cell of C^k (grid level `level`) at grid cell `c` of its resolution, its rest
  /// lattice subdivided there, and the guess of x's coordinates in it from box coordinates
  /// t (exact on a regular grid); -1 when C^k has no such cell. Where its level cell's rest
  /// lattice is not subdivided yet: subdivided first, or, without `subdivide`, kUnready.
  std::int32_t ready_cell(int level, int k, const GridIndex& c, const Eigen::Vector3d& t, Eigen::Vector3d& guess,
                          bool subdivide = true) const;
  static constexpr std::int32_t kUnready = -2;
  /// Vertices whose walk reached a level cell whose rest lattice is not subdivided yet:
  /// parked[i] by vertex of the block prelocate is given, and, kept over the blocks, the
  /// vertices (indices into the mesh) and those cells, by level.
  struct Parking {
    std::vector<std::uint8_t> parked;
    std::vector<std::uint32_t> vertices;
    std::vector<std::pair<int, GridIndex>> cells;
  };
  /// For the vertices ids[0..n), at box coordinates t[0..n), whose tag at grid level `level`
  /// is new (index >= first_new), locate()'s tries at the finest step (the vertex's grid
  /// cell, then the walk from it), solved four at a time: out[i * stride] says where the
  /// vertex lies if they find it (found), and is not found otherwise (locate() then starts
  /// again). With `parking`, a walk into a cell whose rest lattice is not subdivided yet
  /// parks its vertex (left not found) instead of subdividing the cell on the spot.
  void prelocate(int level, const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const std::uint32_t* ids,
                 const Eigen::Vector3d* t, std::ptrdiff_t n, std::size_t first_new, Located* out, int stride,
                 Parking* parking = nullptr) const;
  struct Tag;
  /// A moved level and its tags, for the batch apply: its tag_index_, cache_ and jacobians_
  /// arrays (jacobians null when the apply carries no normals).
  struct TagStream {
    int level;
    const std::uint32_t* index;
    Tag* tags;
    Eigen::Matrix3d* jacobians;
  };
  /// The moved levels' streams, in level order.
  std::vector<TagStream> tag_streams(bool with_jacobians) const;
  /// Asks the memory for vertex v's tags (and their Jacobian parts) at every moved level at
  /// once, before apply_vertex reads them one level after another.
  static void prefetch_tags(const std::vector<TagStream>& streams, std::uint32_t v);
  /// apply_points for vertex v at box coordinates t, through the moved levels' `streams`:
  /// its position, and its Jacobian in `jacobian` when given (an apply with normals);
  /// `located`: its prelocated places by level, or null. False when the vertex is in no cell
  /// where a level moved (position copied, `jacobian` not written); `folded` is set when its
  /// Jacobian's determinant is <= 0.
  bool apply_vertex(std::uint32_t v, const Eigen::Vector3d& t, const std::vector<TagStream>& streams,
                    const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, Eigen::Ref<Eigen::Matrix3Xd>& out_pos,
                    Eigen::Matrix3d* jacobian, const Located* located, bool& folded) const;
  /// What apply_points sets up for its passes over the vertices: per level, the index of
  /// its first new tag; the levels that locate new tags; the moved levels' tag streams.
  struct BatchApply {
    std::vector<std::size_t> first_new;
    std::vector<int> locating;
    std::vector<TagStream> streams;
  };
  /// apply_points' pass over `ids`, block by block; with `parked`, vertices that prelocate
  /// parks are left alone and appended to its vertices, and the cells that parked them to
  /// its cells.
  void apply_blocks(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm,
                    const std::vector<std::uint32_t>& ids, const BatchApply& batch, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                    Eigen::Ref<Eigen::Matrix3Xd>* out_nrm, WarpCounts& counts, Parking* parked) const;
  /// apply(), and apply_without_normals() when in_nrm and out_nrm are null.
  void apply_points(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm,
                    const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                    Eigen::Ref<Eigen::Matrix3Xd>* out_nrm, WarpCounts& counts) const;
  bool tagged_grid_part(int level, const Eigen::Vector3d& x, const Eigen::Vector3d& t, Tag& tag,
                        Eigen::Matrix3d* jacobian, const Located* located) const;
  bool tagged_local_part(int level, const Eigen::Vector3d& x, Tag& tag, Eigen::Matrix3d* jacobian) const;
  /// One level's part of F(x) - x (tag.d), at x with box coordinates t, through the
  /// vertex's tag (`same`: the tag is for x; a fresh tag computes it from scratch), and of
  /// dF/dx - I: a bound of its norm, squared (tag.bound2), and the part itself in
  /// `jacobian` when given (its tag.jacobian says whether it already holds it); false (d,
  /// part zero) when the level leaves x alone: not moved, or not near x. `located`, when
  /// given, is where prelocate() found x at a grid level, if it did.
  bool tagged_part(int level, const Eigen::Vector3d& x, const Eigen::Vector3d& t, bool same, Tag& tag,
                   Eigen::Matrix3d* jacobian, const Located* located = nullptr) const;
  /// The level's part of F(x) - x at a located tag, and `jacobian` gains its part of
  /// dF/dx - I when given: the grid or local level's displacement at the tag's place.
  /// `corner`: a grid level's cell's eight point indices when the caller has them (the
  /// prelocated cell's), else looked up.
  Eigen::Vector3d part_at(int level, const Tag& tag, Eigen::Matrix3d* jacobian, const std::int32_t* corner = nullptr) const;
  /// tag.d, and tag.bound2 from the Jacobian part itself, which `jacobian` receives when
  /// given (the part computed exactly, not bounded from the locate).
  void exact_part(int level, Tag& tag, Eigen::Matrix3d* jacobian, const std::int32_t* corner = nullptr) const;
  /// The level's part of dF/dx - I at a located tag, computed again.
  Eigen::Matrix3d jacobian_part(int level, const Tag& tag) const;
  /// Whether I + the sum of the levels' Jacobian parts at vertex v (those of its tags whose
  /// `inside` is set, in level order) has a determinant <= 0; `bound2`, the square of a
  /// bound of that sum's 2-norm, decides it without the parts when it is small enough.
  bool jacobian_folded(std::uint32_t v, double bound2) const;

  Parallelepiped box_;
  OctreeOptions options_;
  mutable std::vector<Level> levels_;
  struct Inspected {  // subdivided() and subdivided_rest() of a level that built no C^k
    GridComplex complex;
    Eigen::Matrix3Xd rest;
  };
  mutable std::map<std::pair<int, int>, Inspected> inspected_;
  mutable std::mutex rest_mutex_;  // ensure_rest: one subdivision at a time
  mutable std::atomic<std::size_t> located_{0};
  std::vector<Local> local_;
  mutable std::vector<Eigen::MatrixXd> deformation_;  // grid levels' Delta_l since the last move; empty: not yet
  bool any_changed_ = false;
  // The batch apply's tags (section 3.2: "each vertex is tagged with a pointer to the
  // minimal cell ... and its local coordinate in the cell"): per vertex, the input position
  // they are for, and per moved level where the vertex lies in the level's subdivided rest
  // lattices (grid levels), and the level's part of F and dF/dx with the epoch of the
  // vertex's cell it was computed at. The rest lattices never change, so a tag holds while
  // the vertex stays where it was: a move at one level recomputes only that level's parts
  // in the cells it marked, from the tags, without locating anything again.
  // One cache line a tag: a first move at a coarse level tags every vertex (blob39k's
  // run: 6,131 -> 5,890 page faults against 72 bytes), and a later apply reads a vertex's
  // tags one line each.
  struct alignas(64) Tag {
    Tag() : state(0), inside(0), jacobian(0) {}
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    std::uint32_t epoch = 0;  // of d and bound2; 0: not computed
    float bound2 = 0;         // the square of a bound of the Jacobian part's 2-norm (to float precision)
    std::int32_t cell = -1;
    std::int8_t step = -1;
    // A local level's tetrahedron (u: its lambda 1..3): its face by place among the cell's
    // faces (SubdividedLevel::face_place), and the face's edge.
    std::uint8_t face = 0;
    std::int8_t slot = -1;
    std::uint8_t state : 2;     // 0: not located yet, 1: in a cell, 2: in none
    std::uint8_t inside : 1;    // d is a part
    std::uint8_t jacobian : 1;  // the tag's entry in jacobians_ holds the Jacobian part of this epoch
  };
  static_assert(sizeof(Tag) == 64, "a tag is one cache line");
  // Tags exist only where a level can move a vertex: per level, per vertex, 1 + the index
  // of its tag in cache_[level], or 0 when it has none (its cell was not active there when
  // it was last applied; the level's part is zero). A first move at a fine level tags the
  // few vertices of its marked cells, not every vertex.
  mutable Eigen::Matrix3Xd cache_key_;
  mutable std::vector<std::vector<std::uint32_t>> tag_index_;
  mutable std::vector<std::vector<Tag, HugePageAllocator<Tag>>> cache_;
  // The tags' Jacobian parts, by the same index, for the applies that carry normals: an
  // apply without normals needs only the parts' bounds, and its tags are half the size.
  mutable std::vector<std::vector<Eigen::Matrix3d, HugePageAllocator<Eigen::Matrix3d>>> jacobians_;
};

}  // namespace ffd
