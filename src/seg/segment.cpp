#include "seg/segment.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "layout/divide_split.hpp"
#include "seg/geodesic.hpp"

namespace isoquad {

void measure_geodesic_lengths(const TriMesh& m, const FaceData<uint32_t>& labels, MetaMesh& mm) {
  // Independent searches: in parallel, each meta-edge's result its own.
  tbb::parallel_for(std::size_t(0), mm.edges.size(), [&](std::size_t i) {
    MetaEdge& e = mm.edges[i];
    const double d = geodesic_distance(m, e.vertices.front(), e.vertices.back(), [&](uint32_t f) {
      return labels[f] == e.left || labels[f] == e.right;
    });
    e.geodesic = d < INFINITY ? std::min(d, e.length) : e.length;
  });
}

SegmentResult segment(const TriMesh& mesh, const EdgeData<char>& feature,
                      const SegmentOptions& options) {
  SegmentResult r;
  if (options.vsa_labels) {
    r.vsa_labels = *options.vsa_labels;
    r.vsa_patches = compact_labels(r.vsa_labels);
  } else {
    Segmentation vsa = segment_vsa(mesh, feature, options.vsa);
    r.vsa_patches = vsa.num_patches();
    r.energy_log = std::move(vsa.energy_log);
    r.vsa_labels = std::move(vsa.face_patch);
  }
  r.labels = r.vsa_labels;
  r.num_patches = make_disk_patches(mesh, r.labels, r.repair, options.piecewise_disks);
  if (!options.tips.empty()) {
    split_patches_at_tips(mesh, options.tips, r.labels, r.num_patches, r.tip_split);
    r.num_patches = make_disk_patches(mesh, r.labels, r.repair, options.piecewise_disks);
  }
  if (options.straighten) straighten_seams(mesh, r.labels, r.num_patches, feature, r.straighten);
  MetaMeshOptions first = options.meta;
  first.forced.insert(first.forced.end(), r.tip_split.boundary.begin(), r.tip_split.boundary.end());
  const MetaMesh before_split = build_meta_mesh(mesh, r.labels, r.num_patches, feature, first);

  r.refined = identity_refinement(mesh);
  r.feature = feature;
  r.dividing_splits = split_dividing_edges(r.refined, r.labels, r.feature);
  // Splitting keeps vertex ids and seams, so the same meta-vertices (inserted ones forced).
  MetaMeshOptions again = options.meta;
  again.forced = before_split.inserted_vertices;  // with the boundary tips
  r.meta = build_meta_mesh(r.refined.mesh, r.labels, r.num_patches, r.feature, again);
  r.meta.inserted = before_split.inserted;
  check_meta_mesh(r.refined.mesh, r.labels, r.meta);
  measure_geodesic_lengths(r.refined.mesh, r.labels, r.meta);
  return r;
}

}  // namespace isoquad
