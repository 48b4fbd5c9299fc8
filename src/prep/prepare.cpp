#include "prep/prepare.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <optional>

#include "isoquad/error.hpp"
#include "prep/steps.hpp"

namespace isoquad {

bool InputReport::has_errors() const {
  return std::any_of(issues.begin(), issues.end(),
                     [](const InputIssue& i) { return i.severity == InputIssue::Severity::error; });
}

namespace {

using Severity = InputIssue::Severity;

void note(InputReport& r, Severity severity, const char* code, uint32_t count,
          const std::string& msg) {
  if (count > 0) r.issues.push_back({severity, code, msg, count});
}

[[noreturn]] void reject(ErrorKind kind, const char* code, const std::string& msg,
                         std::initializer_list<uint32_t> vertices = {}) {
  ErrorContext ctx;
  ctx.vertices = vertices;
  throw Error(kind, code, msg, ctx);
}

// A NaN or infinite coordinate (which the readers reject, E013, but a library caller may pass)
// makes every derived value NaN: it is rejected, naming the first such vertex. False when
// diagnosing and the vertex is recorded instead.
bool check_finite(const PolyMesh& input, const PrepOptions& options, InputReport& report) {
  for (uint32_t v = 0; v < input.num_vertices(); ++v) {
    const Vec3 p = input.positions[v];
    if (is_finite(p)) continue;
    const std::string msg =
        fmt::format("vertex {} has a NaN or infinite coordinate ({}, {}, {})", v, p.x, p.y, p.z);
    if (!options.diagnose) reject(ErrorKind::invalid_input, "E013", msg, {v});
    report.issues.push_back({Severity::error, "E013", msg, 1});
    return false;
  }
  return true;
}

// Angle and area statistics of a kept component, in its normalized coordinates; the area is
// reported in input units, normalized / scale^2 times 4^to_input (inf or 0 where that is
// beyond the double range: a sphere of radius 1e300).
void shape_statistics(const std::vector<Vec3>& positions, const std::vector<Tri>& tris,
                      double scale, int to_input, ComponentReport& r) {
  double min_angle = std::numbers::pi;
  double area = 0;
  for (const Tri& t : tris) {
    const Vec3 &p0 = positions[t[0]], &p1 = positions[t[1]], &p2 = positions[t[2]];
    const double a = 0.5 * norm(cross(p1 - p0, p2 - p0));
    area += a;
    for (int i = 0; i < 3; ++i) {
      const Vec3 u = positions[t[(i + 1) % 3]] - positions[t[i]];
      const Vec3 v = positions[t[(i + 2) % 3]] - positions[t[i]];
      min_angle = std::min(min_angle, angle_between(u, v));
    }
  }
  r.area = std::ldexp(area / (scale * scale), 2 * to_input);
  r.min_angle_deg = min_angle * 180.0 / std::numbers::pi;
}

// Welding boundary vertices may close a hole or merge two boundary loops (a mesh with 106 holes
// had 105 after it): such a weld is a change of topology, done only with `repair` (or for STL
// soups, which share no vertex at all). Otherwise the vertices stay apart, with a warning.
void hold_topology_changing_weld(const PolyMesh& soup, const PrepOptions& options,
                                 std::vector<uint32_t>& weld, InputReport& report) {
  if (report.welded_vertices == 0 || options.weld_all || options.repair) return;
  std::vector<uint32_t> apart(weld.size());
  std::iota(apart.begin(), apart.end(), 0u);
  const prep::WeldTopology before = prep::weld_topology(soup, apart),
                           after = prep::weld_topology(soup, weld);
  if (before == after) return;
  note(report, Severity::warning, "W112", report.welded_vertices,
       fmt::format("kept {} coincident boundary vertices apart: welding them would change the "
                   "topology (Euler characteristic {} -> {}, boundary loops {} -> {}); --repair "
                   "welds them",
                   report.welded_vertices, before.euler, after.euler, before.boundary_loops,
                   after.boundary_loops));
  weld = std::move(apart);
  report.welded_vertices = 0;
}

// A component with (near) no area for its extent has no surface to lay quads on: its faces are
// collinear or coincident, or a vertex far from the rest stretches it so that the rest shrinks
// to a point (a sphere with one vertex at 1e20 or 1e100). The stages cannot parametrize it
// (remesh crashed or failed far downstream on both), so preparation rejects it, naming the
// vertex farthest from the component's centroid. Working units: products of two coordinates
// stay finite (kSafeExponent).
constexpr double kNoAreaRatio = 1e-12;  // area over the squared bounding-box diagonal
struct NoArea {
  std::string message;
  uint32_t vertex = 0;  // input vertex farthest from the centroid
};
std::optional<NoArea> without_area(const PolyMesh& input, const prep::Soup& s,
                                   const std::vector<uint32_t>& tris, std::size_t c) {
  Box3 box;
  double area = 0;
  Vec3 centroid;
  std::vector<uint32_t> vertices;
  for (const uint32_t t : tris) {
    const Tri& tri = s.tris[t];
    const Vec3 &p0 = s.positions[tri[0]], &p1 = s.positions[tri[1]], &p2 = s.positions[tri[2]];
    area += 0.5 * norm(cross(p1 - p0, p2 - p0));
    for (const uint32_t v : tri) vertices.push_back(v);
  }
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  for (const uint32_t v : vertices) {
    box.add(s.positions[v]);
    centroid += s.positions[v] / double(vertices.size());
  }
  const double diagonal = box.diagonal();
  if (area > kNoAreaRatio * diagonal * diagonal) return std::nullopt;
  if (!(diagonal > 0))
    return NoArea{fmt::format("component {} has zero extent (all its vertices coincide)", c),
                  s.vertex_input[vertices[0]]};
  uint32_t far = vertices[0];
  for (const uint32_t v : vertices)
    if (norm(s.positions[v] - centroid) > norm(s.positions[far] - centroid)) far = v;
  const uint32_t in = s.vertex_input[far];
  const Vec3 p = input.positions[in];
  const std::string msg = fmt::format(
      "component {} has no area for its size ({:.3g} of its bounding-box diagonal squared): its "
      "faces are degenerate (collinear vertices), or vertices far from the rest shrink the rest "
      "to a point (the farthest from its centroid: input vertex {} at ({:.6g}, {:.6g}, {:.6g}))",
      c, area / (diagonal * diagonal), in, p.x, p.y, p.z);
  return NoArea{msg, in};
}

}  // namespace

PreparedMesh prepare(const PolyMesh& input, const PrepOptions& options) {
  PreparedMesh out;
  InputReport& report = out.report;
  report.input_vertices = uint32_t(input.num_vertices());
  report.input_faces = uint32_t(input.num_faces());
  for (std::size_t f = 0; f < input.num_faces(); ++f)
    if (input.face(f).size() > 3) ++report.input_polygons;
  if (!check_finite(input, options, report)) return out;
  for (const Vec3& p : input.positions) report.bounding_box.add(p);

  // Everything below squares coordinates (distances, areas, cross products), which overflows
  // from about 1e154 and underflows below 1e-154: a mesh that far out is scaled by a power of
  // two first, exactly, so it gives the same quads as the mesh at unit scale.
  const int exponent = magnitude_exponent(input.positions);
  const bool rescale = std::abs(exponent) > kSafeExponent;
  PolyMesh rescaled;
  if (rescale) {
    rescaled = input;
    for (Vec3& p : rescaled.positions) p = ldexp(p, -exponent);
  }
  const PolyMesh& soup = rescale ? rescaled : input;
  const int to_input = rescale ? exponent : 0;  // working units times 2^to_input: input units

  Box3 box;
  for (const Vec3& p : soup.positions) box.add(p);
  const double weld_eps = options.weld_epsilon * box.diagonal();
  auto weld = prep::weld_map(soup, options.weld_all, weld_eps, report.welded_vertices);
  hold_topology_changing_weld(soup, options, weld, report);
  prep::Soup s = prep::triangulate(soup, weld, report);
  note(report, Severity::repaired, "W104", report.welded_vertices,
       fmt::format("welded {} coincident vertices", report.welded_vertices));
  note(report, Severity::repaired, "W105", report.degenerate_faces,
       fmt::format("dropped {} faces that collapsed to fewer than 3 distinct vertices",
                   report.degenerate_faces));
  note(report, Severity::warning, "W108", report.unused_vertices,
       fmt::format("ignored {} vertices that no face uses", report.unused_vertices));
  prep::drop_duplicate_faces(s, report);
  note(report, Severity::repaired, "W106", report.duplicate_faces,
       fmt::format("dropped {} duplicate faces", report.duplicate_faces));
  prep::make_manifold(s, options, report);
  auto comps = prep::orient_components(s, report);
  note(report, Severity::repaired, "W107", report.flipped_faces,
       fmt::format("flipped {} faces to orient every component consistently{}",
                   report.flipped_faces, " (closed components outward)"));

  // Decide what is kept, then normalize over the kept components together.
  Box3 kept_box;
  for (std::size_t c = 0; c < comps.size(); ++c) {
    ComponentReport r = prep::combinatorial_topology(s, comps[c].tris);
    r.orientable = comps[c].orientable;
    if (!r.orientable) {
      report.orientable = false;
      r.kept = false;
      r.genus = 2 - r.euler - r.boundary_loops;  // non-orientable genus (crosscaps)
      const std::string msg = fmt::format(
          "component {} is non-orientable (orientation conflict at the edge between input "
          "vertices {} and {}); quad layouts need an orientable surface",
          c, comps[c].conflict_a, comps[c].conflict_b);
      if (!options.diagnose)
        reject(ErrorKind::unsupported_topology, "E102", msg,
               {comps[c].conflict_a, comps[c].conflict_b});
      report.issues.push_back({Severity::error, "E102", msg, 1});
    } else {
      r.genus = (2 - r.euler - r.boundary_loops) / 2;
      if (const auto none = without_area(input, s, comps[c].tris, c)) {
        r.kept = false;
        if (!options.diagnose)
          reject(ErrorKind::invalid_input, "E103", none->message, {none->vertex});
        report.issues.push_back({Severity::error, "E103", none->message, 1});
      }
    }
    if (r.kept)
      for (uint32_t t : comps[c].tris)
        for (uint32_t v : s.tris[t]) kept_box.add(s.positions[v]);
    report.components.push_back(r);
  }
  const bool any_kept = std::any_of(report.components.begin(), report.components.end(),
                                    [](const ComponentReport& r) { return r.kept; });
  if (!any_kept || !(kept_box.diagonal() > 0)) {
    const std::string msg = !any_kept ? "nothing is left to remesh after preparation"
                                      : "the mesh has zero extent (all vertices coincide)";
    if (!options.diagnose) reject(ErrorKind::invalid_input, "E103", msg);
    report.issues.push_back({Severity::error, "E103", msg, 1});
    return out;
  }
  const Normalization working{kept_box.center(), 1.0 / kept_box.diagonal()};
  out.normalization.center = ldexp(working.center, to_input);
  out.normalization.scale = std::ldexp(working.scale, -to_input);

  std::vector<uint32_t> local(s.positions.size(), kInvalid);
  for (std::size_t c = 0; c < comps.size(); ++c) {
    ComponentReport& r = report.components[c];
    if (!r.kept) continue;
    std::vector<Vec3> positions;
    std::vector<uint32_t> vin, fin;
    std::vector<Tri> tris;
    for (uint32_t t : comps[c].tris) {
      Tri tri = s.tris[t];
      for (uint32_t& v : tri) {
        if (local[v] == kInvalid) {
          local[v] = uint32_t(positions.size());
          positions.push_back(working.apply(s.positions[v]));
          vin.push_back(s.vertex_input[v]);
        }
        v = local[v];
      }
      tris.push_back(tri);
      fin.push_back(s.tri_input[t]);
    }
    shape_statistics(positions, tris, working.scale, to_input, r);
    const prep::ZeroAreaRepair zero = prep::repair_zero_area(positions, tris, vin, fin);
    r.zero_area_collapsed = zero.collapsed;
    r.zero_area_flipped = zero.flipped;
    r.zero_area_dropped = zero.dropped;
    r.zero_area_faces = zero.left;
    if (options.flip_flat)
      r.flat_flips = prep::flip_flat_edges(positions, tris, prep::kFlatTolerance);
    PreparedComponent pc;
    pc.mesh = TriMesh(std::move(positions), std::move(tris));
    pc.input_vertex = VertexData<uint32_t>(std::move(vin));
    pc.input_face = FaceData<uint32_t>(std::move(fin));
    pc.feature = prep::mark_features(pc.mesh, options.feature_angle_deg);
    pc.report_index = uint32_t(c);
    r.feature_edges = uint32_t(std::count(pc.feature.begin(), pc.feature.end(), 1));
    std::vector<std::string> how;
    if (zero.collapsed > 0)
      how.push_back(
          fmt::format("collapsed {} edges shorter than a thousandth of their "
                      "triangle's longest (the surface moved {:.3g} at most)",
                      zero.collapsed, std::ldexp(zero.moved / working.scale, to_input)));
    if (zero.flipped > 0) how.push_back(fmt::format("flipped {} edges", zero.flipped));
    if (zero.dropped > 0) how.push_back(fmt::format("removed {} on the boundary", zero.dropped));
    note(report, Severity::repaired, "W116", zero.collapsed + zero.flipped + zero.dropped,
         fmt::format("component {}: zero-area triangles repaired, the topology kept: {}", c,
                     fmt::join(how, "; ")));
    note(report, Severity::warning, "W110", r.zero_area_faces,
         fmt::format("component {} has {} faces of (near-)zero area", c, r.zero_area_faces));
    note(report, Severity::repaired, "W111", r.flat_flips,
         fmt::format("component {}: flipped {} edges inside flat regions to Delaunay (needle "
                     "triangles; the surface is unchanged)",
                     c, r.flat_flips));
    out.components.push_back(std::move(pc));
  }
  return out;
}

}  // namespace isoquad
