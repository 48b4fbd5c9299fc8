// isoquad render MESH -o out.png: a shaded picture of any mesh (triangles or quads).
#include <fmt/format.h>

#include "commands.hpp"
#include "io/read_mesh.hpp"
#include "io/write_mesh.hpp"
#include "viz/render.hpp"

namespace isoquad::cli {

namespace {
struct RenderArgs {
  std::string mesh, output;
  bool wireframe = false;
  std::vector<double> view;
  int width = 1200, height = 1000;
};
}  // namespace

Runner add_render(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  CLI::App* sub = app.add_subcommand("render", "Render a mesh to PNG (headless)");
  sub->add_option("mesh", a->mesh, "Mesh (OBJ, OFF, PLY, STL)")->required();
  sub->add_option("-o,--output", a->output, "PNG file")->required();
  sub->add_flag("--wireframe", a->wireframe, "Draw every edge");
  sub->add_option("--view", a->view,
                  "Viewing direction x y z (towards the model; default: the three-quarter view "
                  "that shows the most surface)")
      ->expected(3);
  sub->add_option("--size", a->width, "Width in pixels")
      ->check(CLI::Range(16, 8192))
      ->capture_default_str();
  return [a] {
    check_output_path(a->output);
    const ReadResult r = read_mesh(a->mesh);
    const PolyMesh& m = r.mesh;
    Box3 box;
    for (const Vec3& p : m.positions) box.add(p);
    std::vector<std::vector<uint32_t>> polys(m.num_faces());
    std::vector<std::array<Vec3, 3>> fan;
    for (std::size_t f = 0; f < m.num_faces(); ++f) {
      polys[f].assign(m.face(f).begin(), m.face(f).end());
      for (std::size_t i = 1; i + 1 < polys[f].size(); ++i)
        fan.push_back(
            {m.positions[polys[f][0]], m.positions[polys[f][i]], m.positions[polys[f][i + 1]]});
    }
    Camera cam = best_view(fan);
    if (a->view.size() == 3) cam.direction = {a->view[0], a->view[1], a->view[2]};
    Canvas canvas(a->width, a->width * 5 / 6, box, cam, &m.positions);
    canvas.fill_polygons(m.positions, polys, [&](uint32_t f) {
      return m.face_group.empty() ? Rgb{0.75, 0.78, 0.85} : [&] {
        const Rgb c = distinct_color(uint32_t(m.face_group[f]));
        return Rgb{0.55 + 0.45 * c.r, 0.55 + 0.45 * c.g, 0.55 + 0.45 * c.b};
      }();
    });
    if (a->wireframe)
      for (const auto& p : polys)
        for (std::size_t i = 0; i < p.size(); ++i)
          canvas.line(m.positions[p[i]], m.positions[p[(i + 1) % p.size()]], {0.1, 0.1, 0.15}, 0.8);
    canvas.save_png(a->output);
    return 0;
  };
}

}  // namespace isoquad::cli
