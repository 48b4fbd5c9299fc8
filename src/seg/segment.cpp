#include "seg/segment.hpp"

namespace isoquad {

SegmentResult segment(const TriMesh& mesh, const EdgeData<char>& feature, const SegmentOptions& options) {
  SegmentResult r;
  Segmentation vsa = segment_vsa(mesh, feature, options.vsa);
  r.vsa_patches = vsa.num_patches();
  r.energy_log = std::move(vsa.energy_log);
  r.labels = std::move(vsa.face_patch);
  r.num_patches = make_disk_patches(mesh, r.labels, r.repair);
  if (options.straighten) straighten_seams(mesh, r.labels, r.num_patches, feature, r.straighten);
  r.meta = build_meta_mesh(mesh, r.labels, r.num_patches, feature, options.meta);
  check_meta_mesh(mesh, r.labels, r.meta);
  return r;
}

}  // namespace isoquad
