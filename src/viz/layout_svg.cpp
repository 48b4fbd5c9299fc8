#include "viz/layout_svg.hpp"

#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <numeric>
#include <sstream>

#include "io/write_mesh.hpp"
#include "viz/render.hpp"

namespace isoquad {

namespace {

cairo_status_t append_to_string(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

struct Placement {
  double x = 0, y = 0;  // top-left of the panel in points
};

}  // namespace

void write_layout_svg(const std::filesystem::path& path, const TriMesh& mesh,
                      const FaceData<uint32_t>& labels, const Layout& layout, const ParamMap& map,
                      const std::vector<uint32_t>& bad_faces) {
  const uint32_t np = uint32_t(layout.charts.size());
  // One lattice unit in points: the whole picture about 1200 points wide.
  int64_t area = 0, widest = 1;
  for (const Chart& c : layout.charts) {
    area += (c.width + 2) * (c.height + 2);
    widest = std::max(widest, c.width + 2);
  }
  const double row_units = std::max(double(widest), std::sqrt(double(area)) * 1.3);
  const double unit = std::clamp(1200.0 / row_units, 1.0, 40.0);
  const double margin = 14;
  // Shelf packing, tallest first.
  std::vector<uint32_t> order(np);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return layout.charts[a].height > layout.charts[b].height;
  });
  std::vector<Placement> place(np);
  const double page_w = row_units * unit + 2 * margin;
  double x = margin, y = margin, shelf = 0;
  for (const uint32_t p : order) {
    const double w = double(layout.charts[p].width) * unit,
                 h = double(layout.charts[p].height) * unit;
    if (x + w + margin > page_w && x > margin) {
      x = margin;
      y += shelf + margin;
      shelf = 0;
    }
    place[p] = {x, y};
    x += w + margin;
    shelf = std::max(shelf, h);
  }
  const double page_h = y + shelf + margin;

  std::string bytes;
  const bool png = path.extension() == ".png";
  cairo_surface_t* surface =
      png ? cairo_image_surface_create(CAIRO_FORMAT_RGB24, int(std::ceil(page_w)),
                                       int(std::ceil(page_h)))
          : cairo_svg_surface_create_for_stream(append_to_string, &bytes, page_w, page_h);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  // Chart (u, v) to the page: v grows upwards.
  auto to_page = [&](uint32_t p, const UV& uv) {
    const Chart& c = layout.charts[p];
    return std::array<double, 2>{place[p].x + uv[0] * unit,
                                 place[p].y + (double(c.height) - uv[1]) * unit};
  };
  for (uint32_t p = 0; p < np; ++p) {
    const Chart& c = layout.charts[p];
    const Rgb col = distinct_color(p);
    cairo_set_source_rgb(cr, 0.75 + 0.25 * col.r, 0.75 + 0.25 * col.g, 0.75 + 0.25 * col.b);
    cairo_rectangle(cr, place[p].x, place[p].y, double(c.width) * unit, double(c.height) * unit);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.55, 0.55, 0.55);
    cairo_set_line_width(cr, 0.4);
    for (int64_t i = 1; i < c.width; ++i) {
      const auto a = to_page(p, {double(i), 0}), b = to_page(p, {double(i), double(c.height)});
      cairo_move_to(cr, a[0], a[1]);
      cairo_line_to(cr, b[0], b[1]);
    }
    for (int64_t j = 1; j < c.height; ++j) {
      const auto a = to_page(p, {0, double(j)}), b = to_page(p, {double(c.width), double(j)});
      cairo_move_to(cr, a[0], a[1]);
      cairo_line_to(cr, b[0], b[1]);
    }
    cairo_stroke(cr);
  }
  cairo_set_line_width(cr, std::min(0.3, 0.05 * unit));
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const auto q = to_page(labels[f], map.uv[f][c]);
      c == 0 ? cairo_move_to(cr, q[0], q[1]) : cairo_line_to(cr, q[0], q[1]);
    }
    cairo_close_path(cr);
  }
  cairo_stroke(cr);
  cairo_set_source_rgb(cr, 0.9, 0.05, 0.05);
  for (const uint32_t f : bad_faces) {
    for (int c = 0; c < 3; ++c) {
      const auto q = to_page(labels[f], map.uv[f][c]);
      c == 0 ? cairo_move_to(cr, q[0], q[1]) : cairo_line_to(cr, q[0], q[1]);
    }
    cairo_close_path(cr);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 1.2);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 10);
  for (uint32_t p = 0; p < np; ++p) {
    const Chart& c = layout.charts[p];
    cairo_rectangle(cr, place[p].x, place[p].y, double(c.width) * unit, double(c.height) * unit);
    cairo_stroke(cr);
    cairo_move_to(cr, place[p].x, place[p].y - 2);
    cairo_show_text(cr, fmt::format("{} ({}x{})", p, c.width, c.height).c_str());
  }
  cairo_destroy(cr);
  if (png) cairo_surface_write_to_png_stream(surface, append_to_string, &bytes);
  cairo_surface_finish(surface);
  cairo_surface_destroy(surface);
  write_file_atomically(
      path, [&](std::ostream& out) { out << bytes; }, true);
}

}  // namespace isoquad
