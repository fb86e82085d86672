#include "bench.h"

namespace ffd::bench {

const std::vector<Suite>& suites() {
  static const std::vector<Suite> all = {
      {"ffd", "lattice FFD throughput against the straightforward triple sum", bench_ffd},
      {"remesh", "adaptive remeshing: error against the true surface, speed, memory", bench_remesh},
      {"bcm", "boundary-constraint modeling setup and per-frame cost against CGAL's fair", bench_bcm},
      {"cholesky", "the bcm k = 3 numeric factorization: lib/bcm's supernodal Cholesky against CHOLMOD's with the system BLAS",
       bench_cholesky},
      {"io", "mesh file reading and writing per format, the end-to-end run against Blender", bench_io},
      {"pictures", "glTF read/write MB/s against binary PLY; render_mesh and write_png against a z-buffer fill and a mesh read",
       bench_pictures},
      {"multires", "octree multiresolution lattices: Catmull-Clark memory and per-move time against Ono et al.'s tables and a cubic B-spline move",
       bench_multires},
      {"seam", "the Deformer seam: dx/dp of a 1M-vertex mesh against the same run's move step; lib/script's lines, "
               "kind branches and upward includes",
       bench_seam},
      {"deformers", "RBF (against PyGeM's sizes), IDW and mean-value cages: set-up and evaluation of `ffdtool run`, "
                    "a cage's pose against a B-spline move on the same mesh",
       bench_deformers},
      {"compare", "the Hausdorff compare of 100k and 1M-vertex meshes against reading them and CGAL's "
                  "approximate_Hausdorff_distance; a folder compare of CGAL's meshes against their FFD",
       bench_compare},
      {"python", "the Python module's d(points) against the C++ kernel it calls, PyGeM's FFD (PYGEM_SOURCE) and "
                 "ffdtool.run in memory against `ffdtool run` from and to files",
       bench_python},
      {"users", "what a command-line user pays per `ffdtool run` (wall, peak RSS, the stats' steps) against Blender's "
                "job and Lattice modifier, PyGeM's FFD (PYGEM_SOURCE), octree moves and bcm frames",
       bench_users},
      {"volume", "volume meshes: `ffdtool run` on a 1M-node tetrahedral mesh in VTU (base64, zlib), MSH 4.1 and SU2 (read, FFD, "
                 "guard, write, peak bytes per node) against meshio reading and writing the same files",
       bench_volume},
  };
  return all;
}

}  // namespace ffd::bench
