#include "extract/surface_guard.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "extract/surface_walk.hpp"
#include "metrics/quality.hpp"

namespace isoquad {

namespace {

// How far the scaled Jacobian against the corners' own face normals may fall below the bound
// before a move is rejected without the exact value: a prefilter (no search), since most
// rejected moves fold a quad outright. The two differ where a corner's face is not the one just
// inside the quad (at a crease, across a triangle edge).
constexpr double kRoughMargin = 0.5;

Box3 quad_box(const QuadMesh& qm, uint32_t f) {
  Box3 b;
  for (const uint32_t w : qm.quads[f]) b.add(qm.positions[w]);
  return b;
}

double box_distance(const Box3& b, const Vec3& x) {
  double d2 = 0;
  for (int i = 0; i < 3; ++i) {
    const double d = std::max({b.lo[i] - x[i], 0.0, x[i] - b.hi[i]});
    d2 += d * d;
  }
  return std::sqrt(d2);
}

}  // namespace

// Every surface vertex's closest quad, from scratch. The queries are independent (in
// parallel); the lists are filled in vertex order.
SurfaceGuard::SurfaceGuard(QuadMesh& quads, const TriMesh& base, const AabbTree& surface,
                           double tolerance, double min_sj)
    : qm_(quads), base_(base), surface_(surface), tolerance_(tolerance), min_sj_(min_sj) {
  around_.resize(qm_.positions.size());
  for (uint32_t f = 0; f < qm_.quads.size(); ++f)
    for (const uint32_t v : qm_.quads[f]) around_[v].push_back(f);
  const AabbTree quad_tree(fan_triangles(qm_));
  const uint32_t nb = base_.num_vertices();
  closest_.resize(nb);
  distance_.resize(nb);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, nb, 1024), [&](const auto& r) {
    for (uint32_t b = r.begin(); b < r.end(); ++b) {
      const AabbTree::Hit hit = quad_tree.closest(base_.position(b));
      closest_[b] = hit.triangle / 2;
      distance_[b] = hit.distance;
    }
  });
  assigned_.assign(qm_.quads.size(), {});
  for (uint32_t b = 0; b < nb; ++b) assigned_[closest_[b]].push_back(b);
  exact_sj_.assign(qm_.quads.size(), NAN);
  samples_.assign(qm_.quads.size(), NAN);
}

double SurfaceGuard::Local::worst() const {
  double w = samples;
  for (const double d : dist) w = std::max(w, d);
  return w;
}

double SurfaceGuard::quad_distance(uint32_t f, const Vec3& x) const {
  const auto& q = qm_.quads[f];
  const auto& p = qm_.positions;
  return std::min(norm(closest_point_on_triangle(x, p[q[0]], p[q[1]], p[q[2]]) - x),
                  norm(closest_point_on_triangle(x, p[q[0]], p[q[2]], p[q[3]]) - x));
}

// Lowers dist[i] (and sets near[i]) where quad f is closer to verts[i].
void SurfaceGuard::closer(uint32_t f, const std::vector<uint32_t>& verts, std::vector<double>& dist,
                          std::vector<uint32_t>& near) const {
  const Box3 box = quad_box(qm_, f);
  for (std::size_t i = 0; i < verts.size(); ++i) {
    const Vec3& x = base_.position(verts[i]);
    if (box_distance(box, x) >= dist[i]) continue;
    const double d = quad_distance(f, x);
    if (d < dist[i]) dist[i] = d, near[i] = f;
  }
}

// The smallest scaled Jacobian of quad f's corners against the surface normal just inside each
// corner (as `isoquad quality` takes it); with `rough`, against the normal of the face each
// corner is on (kRoughMargin).
double SurfaceGuard::surface_sj(uint32_t f, bool rough) const {
  return quad_corner_sj(qm_, f, [&](uint32_t v, const Vec3& inside) {
    return rough ? face_normal(base_, qm_.surface[v].face)
                 : surface_.normal_at_closest(inside, qm_.surface[v].face);
  });
}

// Quad f's scaled Jacobian against its own (Newell) normal, as `isoquad quality` counts it.
double SurfaceGuard::own_sj(uint32_t f) const {
  const auto& q = qm_.quads[f];
  const auto& p = qm_.positions;
  return quad_scaled_jacobian({p[q[0]], p[q[1]], p[q[2]], p[q[3]]});
}

SurfaceGuard::Shape SurfaceGuard::shape(uint32_t v) const {
  Shape s;
  for (const uint32_t g : around_[v]) {
    s.rough.push_back(surface_sj(g, true));
    s.own.push_back(own_sj(g));
  }
  return s;
}

SurfaceGuard::Local SurfaceGuard::local(uint32_t v, uint32_t tip) const {
  Local l;
  l.changed = around_[v];
  std::vector<uint32_t> ring;
  for (const uint32_t f : l.changed) {
    for (const uint32_t w : qm_.quads[f])
      ring.insert(ring.end(), around_[w].begin(), around_[w].end());
    l.verts.insert(l.verts.end(), assigned_[f].begin(), assigned_[f].end());
  }
  std::sort(ring.begin(), ring.end());
  ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
  if (tip != kInvalid) l.verts.push_back(tip);
  std::sort(l.verts.begin(), l.verts.end());
  l.verts.erase(std::unique(l.verts.begin(), l.verts.end()), l.verts.end());
  // A vertex closest to a quad that stays keeps that distance at most.
  l.others.assign(l.verts.size(), INFINITY);
  l.others_near.assign(l.verts.size(), kInvalid);
  for (std::size_t i = 0; i < l.verts.size(); ++i)
    if (std::find(l.changed.begin(), l.changed.end(), closest_[l.verts[i]]) == l.changed.end()) {
      l.others[i] = distance_[l.verts[i]];
      l.others_near[i] = closest_[l.verts[i]];
    }
  for (const uint32_t f : ring)
    if (std::find(l.changed.begin(), l.changed.end(), f) == l.changed.end())
      closer(f, l.verts, l.others, l.others_near);
  return l;
}

void SurfaceGuard::measure_vertices(Local& l) const {
  l.near = l.others_near;
  l.dist = l.others;
  for (const uint32_t f : l.changed) closer(f, l.verts, l.dist, l.near);
}

double SurfaceGuard::quad_samples(uint32_t f, double limit) const {
  const auto& q = qm_.quads[f];
  const auto& p = qm_.positions;
  double most = 0;
  // A grid of step 1/3 on each of the quad's two triangles, as the metric sees the quad.
  for (const auto& [a, b, c] : {std::array<uint32_t, 3>{q[0], q[1], q[2]}, {q[0], q[2], q[3]}})
    for (int i = 0; i <= 3; ++i)
      for (int j = 0; i + j <= 3; ++j) {
        if (i == 3 || j == 3 || i + j == 0) continue;  // the corners are on the surface
        const Vec3 x = (i * p[a] + j * p[b] + (3 - i - j) * p[c]) / 3.0;
        const uint32_t near = i >= j && i >= 3 - i - j ? a : j >= 3 - i - j ? b : c;
        most = std::max(most, surface_.distance(x, qm_.surface[near].face));
        if (most > limit) return most;
      }
  return most;
}

// The quads' shape is checked first: it is cheap and fails most often.
bool SurfaceGuard::try_move(uint32_t v, uint32_t tip, const SurfacePoint& s, Shape& shape,
                            std::optional<Local>& before, bool improve) {
  const Vec3 old_p = qm_.positions[v];
  const SurfacePoint old_s = qm_.surface[v];
  auto place = [&](const Vec3& p, const SurfacePoint& sp) {
    qm_.positions[v] = p;
    qm_.surface[v] = sp;
  };
  const auto& around = around_[v];
  for (const uint32_t f : around)
    if (std::isnan(exact_sj_[f])) exact_sj_[f] = surface_sj(f);
  place(position_of(base_, s), s);
  bool ok = true;
  for (std::size_t i = 0; ok && i < around.size(); ++i)
    ok = surface_sj(around[i], true) >= std::min(shape.rough[i], min_sj_) - kRoughMargin &&
         own_sj(around[i]) >= std::min(shape.own[i], min_sj_);
  std::vector<double>&sj_after = sj_after_, &samples_after = samples_after_;
  sj_after.assign(around.size(), 0);
  samples_after.assign(around.size(), 0);
  for (std::size_t i = 0; ok && i < around.size(); ++i) {
    sj_after[i] = surface_sj(around[i]);
    ok = sj_after[i] >= std::min(exact_sj_[around[i]], min_sj_);
  }
  Local after;
  if (ok) {
    if (!before) {
      place(old_p, old_s);
      before = local(v, tip);
      measure_vertices(*before);
      before->samples = 0;
      for (const uint32_t f : around) {
        if (std::isnan(samples_[f])) samples_[f] = quad_samples(f);
        before->samples = std::max(before->samples, samples_[f]);
      }
      place(position_of(base_, s), s);
    }
    after = *before;
    measure_vertices(after);
    for (std::size_t i = 0; ok && i < before->verts.size(); ++i)
      ok = after.dist[i] <= std::max(before->dist[i], tolerance_);
    // The samples are a grid: a quad's farthest point lies between them and may go farther
    // while they come closer. So without `improve` (a move that is not to bring the quads
    // closer) the samples must end within the tolerance: quads farther already stay as they
    // are. A sample beyond the bound rejects the move at once.
    const double bound = improve ? std::max(before->samples, tolerance_) : tolerance_;
    after.samples = 0;
    for (std::size_t i = 0; ok && i < around.size(); ++i) {
      samples_after[i] = quad_samples(around[i], improve ? INFINITY : bound);
      after.samples = std::max(after.samples, samples_after[i]);
      ok = after.samples <= bound;
    }
    ok = ok && (!improve || after.worst() < before->worst() * (1 - 1e-6));
  }
  if (!ok) {
    place(old_p, old_s);
    return false;
  }
  for (std::size_t i = 0; i < after.verts.size(); ++i) {
    const uint32_t b = after.verts[i];
    if (after.near[i] != closest_[b]) {
      auto& from = assigned_[closest_[b]];
      from.erase(std::find(from.begin(), from.end(), b));
      assigned_[after.near[i]].push_back(b);
      closest_[b] = after.near[i];
    }
    distance_[b] = after.dist[i];
  }
  for (std::size_t i = 0; i < around.size(); ++i) {
    exact_sj_[around[i]] = sj_after[i];
    samples_[around[i]] = samples_after[i];
  }
  return true;
}

}  // namespace isoquad
