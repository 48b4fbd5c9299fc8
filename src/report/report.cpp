#include "report/report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unordered_map>

#include "io/report_json.hpp"
#include "io/write_mesh.hpp"
#include "isoquad/error.hpp"
#include "metrics/quality.hpp"
#include "viz/layout_svg.hpp"

namespace isoquad {

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t n = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 |
                       uint32_t(uint8_t(bytes[i + 2]));
    for (int k = 3; k >= 0; --k) out += kAlphabet[(n >> (6 * k)) & 63];
  }
  if (i < bytes.size()) {
    uint32_t n = uint32_t(uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(n >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

constexpr Rgb kSurface{0.80, 0.82, 0.86};
constexpr Rgb kQuadFill{0.93, 0.90, 0.84};
constexpr Rgb kFolded{0.95, 0.15, 0.10};
constexpr Rgb kLine{0.12, 0.12, 0.16};

Rgb lighten(Rgb c, double t) {
  return {c.r + t * (1 - c.r), c.g + t * (1 - c.g), c.b + t * (1 - c.b)};
}

// Singularity colours, shared by meta-vertices (patches meeting) and quad vertices (quads meeting).
Rgb valence_color(std::size_t valence) {
  switch (valence) {
    case 3:
      return {0.15, 0.35, 0.95};
    case 4:
      return {0.55, 0.55, 0.55};
    case 5:
      return {0.90, 0.15, 0.10};
    default:
      return valence < 3 ? Rgb{0.10, 0.70, 0.30} : Rgb{0.60, 0.15, 0.75};
  }
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The components' quads in input coordinates, in the order merge_quads uses.
PolyMesh merged(const PreparedMesh& prep, const std::vector<const QuadMesh*>& parts) {
  PolyMesh out;
  for (const QuadMesh* q : parts) {
    const uint32_t base = uint32_t(out.positions.size());
    for (const Vec3& p : q->positions) out.positions.push_back(prep.normalization.invert(p));
    for (const auto& v : q->quads)
      out.add_face({base + v[0], base + v[1], base + v[2], base + v[3]});
  }
  return out;
}

// Quads over the shaded surface: folded quads (scaled Jacobian <= 0 against the input's normal)
// in red, interior vertices with valence != 4 marked by valence.
void draw_quads(Canvas& canvas, const std::vector<const QuadMesh*>& parts,
                const std::vector<double>& surface_sj, double width) {
  std::size_t face_base = 0;
  for (const QuadMesh* q : parts) {
    std::vector<std::vector<uint32_t>> polys(q->quads.size());
    for (std::size_t f = 0; f < q->quads.size(); ++f)
      polys[f].assign(q->quads[f].begin(), q->quads[f].end());
    canvas.fill_polygons(q->positions, polys, [&](uint32_t f) {
      return surface_sj[face_base + f] <= 0 ? kFolded : kQuadFill;
    });
    face_base += q->quads.size();
  }
  const double line_width = std::clamp(width / 1500.0, 0.5, 1.2);
  for (const QuadMesh* q : parts) {
    std::unordered_map<uint64_t, uint32_t> edge_use;
    std::vector<uint32_t> valence(q->positions.size(), 0);
    for (const auto& quad : q->quads)
      for (int i = 0; i < 4; ++i) {
        const uint32_t a = quad[i], b = quad[(i + 1) % 4];
        ++valence[a];
        if (edge_use[(uint64_t(std::min(a, b)) << 32) | std::max(a, b)]++ == 0)
          canvas.line(q->positions[a], q->positions[b], kLine, line_width);
      }
    std::vector<char> boundary(q->positions.size(), 0);
    for (const auto& [key, n] : edge_use)
      if (n == 1) boundary[key >> 32] = boundary[key & 0xFFFFFFFFu] = 1;
    for (uint32_t v = 0; v < q->positions.size(); ++v)
      if (!boundary[v] && valence[v] != 4 && valence[v] > 0)
        canvas.point(q->positions[v], valence_color(valence[v]), std::max(2.5, width / 320.0));
  }
}

void draw_input(Canvas& canvas, const PreparedMesh& prep, double width) {
  uint64_t faces = 0;
  for (const PreparedComponent& c : prep.components) {
    canvas.fill(c.mesh, [](uint32_t) { return kSurface; });
    faces += c.mesh.num_faces();
  }
  if (faces > 20000) return;  // a wireframe would be solid black at this size
  for (const PreparedComponent& c : prep.components)
    for (uint32_t e = 0; e < c.mesh.num_edges(); ++e) {
      const uint32_t h = c.mesh.edge_halfedge(e);
      canvas.line(c.mesh.position(c.mesh.from(h)), c.mesh.position(c.mesh.to(h)),
                  {0.35, 0.36, 0.42}, std::clamp(width / 2400.0, 0.3, 0.6));
    }
}

// Patches in distinct colours, seams dark, meta-vertices as dots coloured by the number of
// patches meeting there (white when on the mesh boundary).
void draw_patches(Canvas& canvas, const std::vector<ComponentRun>& runs, double width) {
  uint32_t base = 0;
  for (const ComponentRun& r : runs) {
    canvas.fill(r.seg.refined.mesh,
                [&](uint32_t f) { return lighten(distinct_color(base + r.seg.labels[f]), 0.25); });
    base += r.seg.num_patches;
  }
  for (const ComponentRun& r : runs) {
    const TriMesh& m = r.seg.refined.mesh;
    for (const MetaEdge& e : r.seg.meta.edges)
      for (std::size_t i = 0; i + 1 < e.vertices.size(); ++i)
        canvas.line(m.position(e.vertices[i]), m.position(e.vertices[i + 1]), kLine,
                    std::max(1.2, width / 700.0));
  }
  for (const ComponentRun& r : runs)
    for (const MetaVertex& v : r.seg.meta.vertices)
      canvas.point(r.seg.refined.mesh.position(v.vertex),
                   v.on_boundary ? Rgb{1, 1, 1} : valence_color(v.wedge_patches.size()),
                   std::max(3.5, width / 220.0));
  // The layout's corners: a small black dot just inside each patch at its four corners.
  for (const ComponentRun& r : runs) {
    if (r.layout.charts.empty()) continue;
    const TriMesh& m = r.seg.refined.mesh;
    const MetaMesh& mm = r.seg.meta;
    auto step = [&](const BoundaryItem& item, bool from_start) {
      const std::vector<uint32_t>& vs = mm.edges[item.edge].vertices;
      const bool first = item.forward == from_start;  // the polyline end at the item's start
      return m.position(first ? vs[1] : vs[vs.size() - 2]);
    };
    for (uint32_t p = 0; p < r.layout.charts.size(); ++p) {
      const MetaFace& face = mm.faces[p];
      const uint32_t n = uint32_t(face.cycle.size());
      for (const uint32_t i : r.layout.charts[p].corners) {
        const Vec3 c = m.position(mm.vertices[face.start_vertex(i, mm.edges)].vertex);
        const Vec3 a = step(face.cycle[i], true), b = step(face.cycle[(i + n - 1) % n], false);
        canvas.point(c + 0.35 * ((a - c) + (b - c)), {0.05, 0.05, 0.05},
                     std::max(1.8, width / 500.0));
      }
    }
  }
}

// The integer contour lines of u and v, face by face in each face's own chart.
void draw_contours(Canvas& canvas, const std::vector<ComponentRun>& runs, double width) {
  for (const ComponentRun& r : runs)
    canvas.fill(r.seg.refined.mesh, [](uint32_t) { return kSurface; });
  const double line_width = std::clamp(width / 1400.0, 0.5, 1.2);
  for (const ComponentRun& r : runs) {
    const TriMesh& m = r.seg.refined.mesh;
    for (uint32_t f = 0; f < m.num_faces(); ++f) {
      const Tri& t = m.face(f);
      const auto& uv = r.param.map.uv[f];
      for (int axis = 0; axis < 2; ++axis) {
        const double s[3] = {uv[0][axis], uv[1][axis], uv[2][axis]};
        const double lo = std::min({s[0], s[1], s[2]}), hi = std::max({s[0], s[1], s[2]});
        for (double level = std::ceil(lo); level <= hi; level += 1) {
          Vec3 ends[2];
          int n = 0;
          for (int i = 0; i < 3 && n < 2; ++i) {
            const double a = s[i] - level, b = s[(i + 1) % 3] - level;
            if (a == 0) {
              ends[n++] = m.position(t[i]);
            } else if ((a < 0 && b > 0) || (a > 0 && b < 0)) {
              const double w = a / (a - b);
              ends[n++] = (1 - w) * m.position(t[i]) + w * m.position(t[(i + 1) % 3]);
            }
          }
          if (n == 2) canvas.line(ends[0], ends[1], {0.10, 0.20, 0.55}, line_width);
        }
      }
    }
  }
}

std::string html_escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

std::string number(const nlohmann::json& j, const char* fmt_spec = "{:.4g}") {
  if (j.is_number_integer() || j.is_number_unsigned()) return j.dump();
  if (j.is_number()) return fmt::format(fmt::runtime(fmt_spec), j.get<double>());
  return html_escape(j.dump());
}

std::string index_html(const nlohmann::json& report, const std::vector<std::string>& images,
                       const std::filesystem::path& dir, const std::string& title) {
  const nlohmann::json& q = report.at("quality");
  std::string rows;
  auto row = [&](const std::string& name, const std::string& value) {
    rows += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", name, value);
  };
  row("quads", fmt::format("<span id=\"quads\">{}</span>", report.at("quads").get<uint64_t>()));
  row("pure quad, manifold, oriented",
      fmt::format("{}, {}, {}", q.at("pure_quad").dump(), q.at("vertex_manifold").dump(),
                  q.at("oriented").dump()));
  row("same topology as the input (&chi;, components, boundary loops)",
      fmt::format("{} ({}, {}, {})", q.at("same_topology").dump(),
                  q.at("topology").at("euler").dump(), q.at("topology").at("components").dump(),
                  q.at("topology").at("boundary_loops").dump()));
  row("irregular vertices", q.at("irregular_vertices").dump());
  row("interior valences", html_escape(q.at("interior_valence").dump()));
  row("scaled Jacobian against each quad's own normal: min / mean / % below 0.5",
      fmt::format("{} / {} / {}", number(q.at("scaled_jacobian").at("min"), "{:.3f}"),
                  number(q.at("scaled_jacobian").at("mean"), "{:.3f}"),
                  number(q.at("scaled_jacobian").at("percent_below_0.5"), "{:.1f}")));
  row("quads not valid (scaled Jacobian &le; 0.001 against their own normal)",
      q.at("scaled_jacobian").at("at_most_0.001").dump());
  row("folded quads (scaled Jacobian &le; 0 against the surface normal)",
      q.at("scaled_jacobian_surface").at("nonpositive").dump());
  row("aspect ratio (opposite sides) mean / 95th percentile / % above 2; area CV",
      fmt::format("{} / {} / {}; {}", number(q.at("aspect_ratio").at("mean"), "{:.2f}"),
                  number(q.at("aspect_ratio").at("p95"), "{:.2f}"),
                  number(q.at("aspect_ratio").at("percent_above_2"), "{:.1f}"),
                  number(q.at("area").at("cv"), "{:.3f}")));
  const nlohmann::json& fc = q.at("feature_coverage");
  row(fmt::format("feature edges (dihedral &gt; {} deg) within 0.1 edge lengths of a quad edge",
                  number(fc.at("angle_deg"), "{:g}")),
      fc.at("length").get<double>() > 0 ? number(100 * fc.at("covered").get<double>(), "{:.1f}%")
                                        : std::string("no feature edge"));
  row("angle deviation mean / max (deg)",
      fmt::format("{} / {}", number(q.at("angle_deviation_deg").at("mean"), "{:.1f}"),
                  number(q.at("angle_deviation_deg").at("max"), "{:.1f}")));
  row("edge length CV", number(q.at("edge_length").at("cv"), "{:.3f}"));
  row("Hausdorff / mean distance (% of bbox diagonal)",
      fmt::format("{:.3f} / {:.4f}", 100 * q.at("hausdorff").get<double>(),
                  100 * q.at("mean_distance").get<double>()));
  for (const auto& c : report.at("components")) {
    row(fmt::format("component {}", c.at("component").get<uint32_t>()),
        fmt::format("{} patches, {} meta-vertices {}, {} quads, repairs {}, {} factorizations, "
                    "{} flipped triangles in the first solve{}",
                    c.at("patches").dump(), c.at("meta_vertices").dump(),
                    html_escape(c.at("meta_vertex_valence").dump()), c.at("quads").dump(),
                    html_escape(c.at("layout_repairs").dump()), c.at("factorizations").dump(),
                    c.at("flipped_first_solve").dump(),
                    c.at("fell_back_to_locked").get<bool>() ? ", locked map" : ""));
    const auto& s = c.at("seconds");
    row("seconds", fmt::format("segment {:.3f}, layout {:.3f}, param {:.3f}, extract {:.3f}",
                               s.at("segment").get<double>(), s.at("layout").get<double>(),
                               s.at("param").get<double>(), s.at("extract").get<double>()));
  }
  std::string figures;
  auto figure = [&](const std::string& file, const std::string& caption) {
    const std::string mime =
        file.ends_with(".svg") ? "image/svg+xml" : (file.ends_with(".png") ? "image/png" : "");
    figures += fmt::format(
        "<figure{4}><img alt=\"{0}\" src=\"data:{1};base64,{2}\"><figcaption>{0}: {3}</figcaption>"
        "</figure>\n",
        file, mime, base64(read_file(dir / file)), caption,
        file == "weights.png" || file.starts_with("layout") ? " class=\"wide\"" : "");
  };
  for (const std::string& f : images) {
    std::string caption;
    if (f == "input.png") caption = "the input triangle mesh";
    if (f == "patches.png")
      caption =
          "patches and meta-vertices by the number of patches meeting there (2 green, 3 blue, "
          "4 grey, 5 red, 6+ purple; white on the mesh boundary); a small black dot inside a "
          "patch marks each of its four layout corners";
    if (f == "contours.png") caption = "integer contour lines of u and v";
    if (f == "quads.png")
      caption =
          "the quad mesh; interior vertices of valence 3 blue, 5 red, other purple or green; "
          "folded quads red";
    if (f.starts_with("layout")) caption = "every patch as its rectangle in the lattice";
    if (f == "weights.png")
      caption = "the locked map's quads (left) next to the relaxed map's (right), as in Figure 3";
    figure(f, caption);
  }
  return fmt::format(R"(<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>isoquad report</title>
<style>
body {{ font-family: sans-serif; margin: 2em; color: #222; }}
table {{ border-collapse: collapse; margin-bottom: 2em; }}
th, td {{ border: 1px solid #ccc; padding: 0.3em 0.6em; text-align: left; vertical-align: top; }}
th {{ background: #f3f3f3; font-weight: normal; }}
.grid {{ display: grid; grid-template-columns: repeat(auto-fit, minmax(420px, 1fr)); gap: 1em; }}
figure {{ margin: 0; }}
figure.wide {{ grid-column: 1 / -1; }}
img {{ max-width: 100%; border: 1px solid #ddd; }}
#broken {{ color: #b00; font-weight: bold; }}
</style></head>
<body>
<h1>isoquad report{}</h1>
<p id="broken"></p>
<table>
{}</table>
<div class="grid">
{}</div>
<script>
window.addEventListener("load", () => {{
  const images = Array.from(document.images);
  const broken = images.filter(i => !(i.complete && i.naturalWidth > 0));
  document.body.dataset.images = (images.length - broken.length) + "/" + images.length;
  if (broken.length) document.getElementById("broken").textContent =
      broken.length + " picture(s) did not load: " + broken.map(i => i.alt).join(", ");
}});
</script>
</body></html>
)",
                     title.empty() ? "" : ": " + html_escape(title), rows, figures);
}

}  // namespace

ReportFiles write_report(const std::filesystem::path& dir, const PolyMesh& input,
                         const RemeshRun& run, const ReportOptions& options) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw Error(ErrorKind::invalid_input, "E001",
                fmt::format("cannot create the report folder {}: {}", dir.string(), ec.message()));
  nlohmann::json report = nlohmann::json::parse(run.result.report);
  if (!report.contains("quality")) report["quality"] = measure_quality(run.result.quads, &input);
  ReportFiles files;
  const int w = options.width, h = options.width * 5 / 6;
  std::vector<const TriMesh*> surfaces;
  Box3 box;
  std::vector<Vec3> fit;  // every panel frames the input's vertices alike
  for (const PreparedComponent& c : run.prep.components) {
    surfaces.push_back(&c.mesh);
    for (uint32_t v = 0; v < c.mesh.num_vertices(); ++v) {
      box.add(c.mesh.position(v));
      fit.push_back(c.mesh.position(v));
    }
  }
  Camera camera;
  if (options.view)
    camera.direction = *options.view;
  else
    camera = best_view(surfaces);

  {
    Canvas c(w, h, box, camera, &fit);
    draw_input(c, run.prep, w);
    c.save_png(dir / "input.png");
    files.names.push_back("input.png");
  }
  {
    Canvas c(w, h, box, camera, &fit);
    draw_patches(c, run.runs, w);
    c.save_png(dir / "patches.png");
    files.names.push_back("patches.png");
  }
  {
    Canvas c(w, h, box, camera, &fit);
    draw_contours(c, run.runs, w);
    c.save_png(dir / "contours.png");
    files.names.push_back("contours.png");
  }
  std::vector<const QuadMesh*> relaxed;
  for (const ComponentRun& r : run.runs) relaxed.push_back(&r.quads);
  const std::vector<double> relaxed_sj = surface_scaled_jacobians(run.result.quads, input);
  {
    Canvas c(w, h, box, camera, &fit);
    draw_quads(c, relaxed, relaxed_sj, w);
    c.save_png(dir / "quads.png");
    files.names.push_back("quads.png");
  }
  for (std::size_t k = 0; k < run.runs.size(); ++k) {
    const ComponentRun& r = run.runs[k];
    if (r.triangle_split) continue;  // no layout
    const std::string name = k == 0 ? "layout.svg" : fmt::format("layout-{}.svg", k);
    write_layout_svg(dir / name, r.seg.refined.mesh, r.seg.labels, r.layout, r.param.map,
                     r.param.certificate.bad_faces);
    files.names.push_back(name);
  }
  // Figure 3: the same layout extracted from the locked map (every seam straight).
  std::vector<QuadMesh> locked_quads;
  locked_quads.reserve(run.runs.size());
  for (const ComponentRun& r : run.runs) {
    if (r.triangle_split) {  // no map: its quads as they are
      locked_quads.push_back(r.quads);
      continue;
    }
    Param locked = r.param;
    locked.map = locked.locked;
    std::fill(locked.locked_edges.begin(), locked.locked_edges.end(), 1);
    ExtractReport er;
    locked_quads.push_back(extract_quads(r.seg.refined, r.surface.mesh, r.seg.labels, r.seg.meta,
                                         r.layout, locked, er));
  }
  {
    std::vector<const QuadMesh*> parts;
    for (const QuadMesh& q : locked_quads) parts.push_back(&q);
    const std::vector<double> locked_sj = surface_scaled_jacobians(merged(run.prep, parts), input);
    auto folded = [](const std::vector<double>& sj) {
      return std::count_if(sj.begin(), sj.end(), [](double s) { return s <= 0; });
    };
    Canvas left(w, h, box, camera, &fit), right(w, h, box, camera, &fit);
    draw_quads(left, parts, locked_sj, w);
    draw_quads(right, relaxed, relaxed_sj, w);
    left.caption(fmt::format("locked seams: {} folded quads", folded(locked_sj)));
    right.caption(fmt::format("relaxed ({}): {} folded quads",
                              report.at("options").at("relax").get<std::string>(),
                              folded(relaxed_sj)));
    Canvas::save_png_row(dir / "weights.png", {&left, &right});
    files.names.push_back("weights.png");
  }
  if (!options.title.empty()) report["input"] = options.title;
  report["view"] = {camera.direction.x, camera.direction.y, camera.direction.z};
  report["files"] = files.names;
  report["files"].push_back("report.json");
  report["files"].push_back("index.html");
  write_file_atomically(dir / "report.json",
                        [&](std::ostream& out) { out << report.dump(2) << '\n'; });
  files.names.push_back("report.json");
  const std::vector<std::string> images(files.names.begin(), files.names.end() - 1);
  const std::string html = index_html(report, images, dir, options.title);
  write_file_atomically(dir / "index.html", [&](std::ostream& out) { out << html; });
  files.names.push_back("index.html");
  return files;
}

}  // namespace isoquad
