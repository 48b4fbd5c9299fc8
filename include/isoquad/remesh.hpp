// isoquad's library entry point: a triangle mesh in, a pure quad mesh out.
//
//   Eigen::MatrixXd V;  // #V x 3 positions
//   Eigen::MatrixXi F;  // #F x 3 vertex indices (0-based, consistently oriented)
//   isoquad::RemeshResult r = isoquad::remesh(V, F, {.quads = 1500});
//   // r.V: #Vq x 3, r.Q: #Q x 4 (counter-clockwise seen from outside), r.patch: #Q
//
// Failures throw isoquad::Error (isoquad/error.hpp) with a code, a message and the elements.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>

namespace isoquad {

struct RemeshOptions {
  uint32_t patches = 0;    // K; 0: automatic
  double edge_length = 0;  // target quad edge length (input units); 0: from quads
  double quads = 0;        // target quad count (>= 1); 0: one per 8 input triangles (1,000-20,000)
  uint64_t seed = 1;
  bool paper_weights = false;      // Floater's mean value weights (default: symmetrized, SPD)
  std::string relax = "adaptive";  // adaptive, bisection or locked
  // How the surface is cut into patches: "vsa" (the paper's planar regions) or "field" (along
  // the streamlines of a smooth cross field; a component whose field layout fails falls back to
  // VSA, and the report says why).
  std::string segmentation = "vsa";
  bool local_corners = false;     // the paper's per-patch corner choice
  bool improve_corners = true;    // refine corners against the relaxed length program
  double feature_angle_deg = 60;  // dihedral angle above which edges are creases (0: none)
  bool repair = false;            // detach non-manifold edges, drop degenerate faces
  double weld_epsilon = 0;        // weld boundary vertices this close (of the diagonal; 0-0.1)
  // Weld every vertex onto another at the same position first: for STL files, whose faces each
  // have their own vertices (MeshArrays::unshared_vertices, isoquad/io.hpp).
  bool weld_all = false;
  uint32_t smooth = 3;         // tangential smoothing sweeps on the surface, last (0: off)
  bool untangle = true;        // move corners of quads folded against the surface
  bool snap = true;            // move corners onto tips the quads cut off (extract/snap.hpp)
  uint32_t fold_rounds = 2;    // more quads across patches still folded, re-solved this often
  bool split_patches = false;  // every patch four-sided first (the paper's §5 repair)
  // Where the quads are farther than 1% of the diagonal (or `tolerance`) from the surface, make
  // the surface vertices where they cut off a tip or bridge a valley patch corners and run
  // again; keep the closer run with no more folded quads.
  bool tip_split = true;
  // Where the quads are still farther than that, cut the quads there at thirds in the same map,
  // again where still far; keep that if it reaches the distance with no more folded quads.
  bool refine = true;
  // Unless --patches or --quads is given: where the result is still farther than the distance
  // target, run again with 1.5 and then 2 times the automatic patch count (the first to reach it
  // with no more folded quads is kept).
  bool patch_rounds = true;
  // Where quads still fold after every other repair, cut the patches no rectangle fits in two
  // and run the stages again (kept only if fewer quads fold).
  bool misfit_split = true;
  // At the default size (no quads, no edge length): remesh a component with more quads while its
  // quads are farther than this fraction of the bounding-box diagonal from the input (two-sided
  // Hausdorff), at most tolerance_rounds times and to 4 times the first count (0: off).
  double tolerance = 0;
  uint32_t tolerance_rounds = 2;
  // Quads whose topology (genus, boundary loops, connected pieces) differs from their input
  // component's are an error (E603) unless this is set: then a warning (W113) in the report.
  bool allow_topology_change = false;
  // A component for which no alternative gives valid quads (each at a scaled Jacobian above
  // 0.001 against its own normal) is an error (E604) unless this is set: then its best quads are
  // kept with a warning (W117) that says how many are not valid and where.
  bool allow_invalid = false;
  bool quality = true;   // measure the output against the input (in `report`)
  uint32_t threads = 0;  // worker threads at most (0: all cores); same output for any
};

// How far a run is, for a progress bar: called as each stage begins, and with each line said.
// `fraction` in [0, 1] never goes down within a run and ends at 1 (each connected component has
// a span by its share of the faces, cut by rough stage weights; the repairs' rounds move within
// what is left of it). `stage`, one of these stable names:
//   "prepare"  validation, repairs, orientation, components
//   "segment"  a component's patches: VSA, or the cross field and its traced separatrices
//   "layout"   the meta-mesh's corners (ILP) and integer side lengths
//   "map"      the seamless parametrization and its certificate
//   "extract"  the quads read off the map, and untangled
//   "repair"   the repairs of the quads (fold rounds, tips, refinement, more patches): they
//              run the stages above again, which are then reported again
//   "quality"  the measurements of the report
//   "done"     the end (fraction 1)
// For each component the first four come in that order, and "repair" after them when the quads
// are untangled (the default); a component under 12 faces runs none of them. `message` is the
// line `isoquad remesh` prints, or empty where only the stage begins.
struct Progress {
  double fraction = 0;
  std::string stage;
  std::string message;
};
// Called on the caller's thread, never from the library's worker threads. An exception thrown
// from it ends the run and propagates.
using ProgressCallback = std::function<void(const Progress&)>;

struct RemeshResult {
  Eigen::MatrixXd V;      // quad mesh vertices, on the input surface
  Eigen::MatrixXi Q;      // quads
  Eigen::VectorXi patch;  // patch id per quad
  std::string report;     // JSON: per-component stages, counts, timings; quality
};

// F is #F x 3, or #F x k for polygons (each row ends at its first -1, as read_mesh_arrays
// gives them; they are triangulated as the command line triangulates them).
// \throw Error(invalid_input) E003 an option out of its range (quads neither 0 nor at least 1,
//        a negative or non-finite edge length, both of them, a feature angle outside [0, 180],
//        ...), E020 wrong shapes or an index out of range, E013 a NaN or infinite coordinate;
//        Error(extraction) E603 a component's quads of another topology than the component
//        (unless options.allow_topology_change), E604 a component with no valid quads from any
//        alternative (unless options.allow_invalid); and the errors of the stages (README).
RemeshResult remesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                    const RemeshOptions& options = {}, const ProgressCallback& progress = {});

// Makes the C library keep freed memory for reuse instead of handing large blocks back to the
// kernel (glibc's mmap and trim thresholds; elsewhere it does nothing). A remesh allocates and
// frees hundreds of megabytes in blocks of 1-20 MB (factors, per-face arrays), and each block
// returned to the kernel is faulted in again page by page when the next one is allocated:
// bunny00 at 1,500 quads spends about 15% of its time so. Process-wide, so the library never
// calls it itself; the command line and the benchmarks do, and a program that remeshes often
// may.
void tune_allocator();

}  // namespace isoquad
