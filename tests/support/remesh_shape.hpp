// A shape remeshed by one run of the pipeline's stages (run_component), as the extraction,
// smoothing and repair tests need it: the prepared input, the component's run and its quads.
#pragma once

#include "pipeline/pipeline.hpp"
#include "prep/prepare.hpp"

namespace isoquad::test {

struct Remeshed {
  PreparedMesh prep;
  ComponentRun run;
  PolyMesh quads;
};

inline Remeshed remesh_shape(const PolyMesh& m, uint32_t k, double quads,
                             WeightKind weights = WeightKind::smvc, bool untangle = true,
                             bool snap = true, bool tip_split = false) {
  Remeshed r{prepare(m), {}, {}};
  PipelineOptions o;
  o.untangle = untangle;
  o.snap = snap;
  o.tip_split = tip_split;  // the stages of one run, unless asked
  o.refine = false;         // the layout's lattice quads (a fold would be cut finer)
  o.smooth = 0;             // as extracted (the smoothing tests smooth them themselves)
  o.param.weights = weights;
  o.patches = k;
  o.quads = quads;
  r.run = run_component(r.prep, 0, o);
  r.quads = merge_quads(r.prep, {r.run});
  return r;
}

inline PolyMesh component_as_poly(const TriMesh& t) {
  PolyMesh p;
  p.positions = t.positions();
  for (const Tri& f : t.faces()) p.add_face({f[0], f[1], f[2]});
  return p;
}

}  // namespace isoquad::test
