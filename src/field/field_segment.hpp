// The field-aligned segmentation (FIELD_LAYOUT.md §4, §6): the cross field's separatrices,
// traced as a motorcycle graph, are embedded in the mesh by splitting the faces they cross; the
// faces between traces, features and the boundary are the patches, and the meta-vertices where a
// patch turns by a quarter are its corners. The result is a SegmentResult like VSA's, with the
// corners given, for layout/ to take as they are.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "field/cross_field.hpp"
#include "field/trace.hpp"
#include "layout/layout.hpp"
#include "seg/segment.hpp"

namespace isoquad {

// Layouts the coarse layout traces at most, to choose the traces it deletes.
inline constexpr uint32_t kCoarseEvaluations = 10;
// By how much a deletion must lower the misfit to be kept: less is within what the later
// stages (the quad count's tuning, refinement) move the quads by anyway.
inline constexpr double kCoarseGain = 0.005;

struct FieldLayoutLog {
  uint32_t singularities = 0;        // singular vertices of the field
  uint32_t nodes = 0, traces = 0;    // emitters and their traces
  uint32_t t_junctions = 0;          // traces ending on another trace
  uint32_t connections = 0;          // separatrices from node to node, laid first
  uint32_t deleted = 0, rounds = 0;  // traces deleted beside parallel tracks; graphs traced
  uint32_t seeds = 0;                // seed vertices for patches the traces left not disks
  uint32_t patches = 0;
  // Patches the traces leave without four corners, or that the disk repair (seg/disk_patches)
  // had to split, merge or relabel: their corners are left to the layout's corner program.
  uint32_t repaired_patches = 0, free_corner_patches = 0;
  uint32_t angle_corner_patches = 0;  // patches whose corners were read from their angles
  // The coarse layout: rays deleted, layouts traced to choose them, and the misfit (the
  // area-weighted mean |log| of the charts' stretch under the integer lengths) before and after.
  uint32_t coarse_deleted = 0, coarse_evaluations = 0;
  uint32_t patches_traced = 0, free_corner_patches_traced = 0;  // before the coarse layout
  double misfit_traced = 0, misfit = 0;
  double field_seconds = 0, trace_seconds = 0, embed_seconds = 0, coarse_seconds = 0;
  std::string failure;  // why the layout cannot be used (empty: it can)
};

struct FieldSegmentation {
  SegmentResult seg;
  // Per patch, the cycle items (MetaFace::cycle indices, increasing) that are its corners;
  // kFreeCorners where the traces do not say (layout/ chooses them).
  std::vector<std::array<uint32_t, 4>> corners;
  // Per patch, 1 where its corners were read from its angles, not from the traces' rules: a
  // preference for layout/ (LayoutOptions::preferred_corners).
  std::vector<char> preferred;
  // Per meta-vertex, the quads the field puts there (LayoutOptions::field_quarter_turns).
  std::vector<int> quarter_turns;
};

// The field-aligned patches of `mesh` for a target quad edge h (mesh units). Where a trace finds
// no end, a patch is not a disk or does not have exactly four corners, log.failure says why and
// the result holds what was built up to there (for pictures): the caller falls back to VSA.
FieldSegmentation field_segment(const TriMesh& mesh, const EdgeData<char>& feature, double h,
                                FieldLayoutLog& log);

}  // namespace isoquad
