#include "viz/render.hpp"

#include <cairo.h>
#include <algorithm>
#include <cmath>

#include "io/write_mesh.hpp"
#include "isoquad/error.hpp"

namespace isoquad {

struct Canvas::Surface {
  cairo_surface_t* surface = nullptr;
  cairo_t* cr = nullptr;
  ~Surface() {
    if (cr) cairo_destroy(cr);
    if (surface) cairo_surface_destroy(surface);
  }
};

Rgb distinct_color(uint32_t i) {
  const double hue = std::fmod(0.13 + i * 0.6180339887498949, 1.0) * 6.0;
  const double s = i % 3 == 0 ? 0.55 : (i % 3 == 1 ? 0.40 : 0.65), v = 0.95;
  const int sector = int(hue);
  const double f = hue - sector, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (sector % 6) {
    case 0:
      return {v, t, p};
    case 1:
      return {q, v, p};
    case 2:
      return {p, v, t};
    case 3:
      return {p, q, v};
    case 4:
      return {t, p, v};
    default:
      return {v, p, q};
  }
}

namespace {

// An orthographic view: picture axes and the scale that fits `box` (5% margin), or, when
// points are given, their projection (tighter: the box's corners overstate most shapes).
struct ViewBasis {
  Vec3 right, up, forward, center;
  double scale = 1;
  ViewBasis(int width, int height, const Box3& box, const Camera& camera,
            const std::vector<Vec3>* points = nullptr) {
    forward = normalized(camera.direction);
    right = normalized(cross(forward, camera.up));
    if (squared_norm(right) == 0) right = normalized(cross(forward, Vec3{1, 0, 0}));
    up = cross(right, forward);
    center = box.center();
    double lo_x = INFINITY, hi_x = -INFINITY, lo_y = INFINITY, hi_y = -INFINITY;
    auto take = [&](const Vec3& p) {
      const double x = dot(p - center, right), y = dot(p - center, up);
      lo_x = std::min(lo_x, x), hi_x = std::max(hi_x, x);
      lo_y = std::min(lo_y, y), hi_y = std::max(hi_y, y);
    };
    if (points && !points->empty()) {
      for (const Vec3& p : *points) take(p);
    } else {
      for (int i = 0; i < 8; ++i)
        take({i & 1 ? box.hi.x : box.lo.x, i & 2 ? box.hi.y : box.lo.y,
              i & 4 ? box.hi.z : box.lo.z});
    }
    center = center + (0.5 * (lo_x + hi_x)) * right + (0.5 * (lo_y + hi_y)) * up;
    const double ext_x = std::max(0.5 * (hi_x - lo_x), 1e-300),
                 ext_y = std::max(0.5 * (hi_y - lo_y), 1e-300);
    scale = 0.95 * std::min(width / (2 * ext_x), height / (2 * ext_y));
  }
};

// Depth-tests the pixels whose centres lie in the screen triangle p (x, y in pixels, z depth)
// of a W x H buffer: write(i) runs where the triangle is nearer than depth[i], after the update.
template <class Write>
void raster(const Vec3 (&p)[3], int W, int H, std::vector<float>& depth, Write&& write) {
  const double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
  if (area == 0) return;
  const int x0 = std::max(0, int(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
  const int x1 = std::min(W - 1, int(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
  const int y0 = std::max(0, int(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
  const int y1 = std::min(H - 1, int(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double w0 = ((p[1].x - px) * (p[2].y - py) - (p[1].y - py) * (p[2].x - px)) / area;
      const double w1 = ((p[2].x - px) * (p[0].y - py) - (p[2].y - py) * (p[0].x - px)) / area;
      const double w2 = 1 - w0 - w1;
      if (w0 < 0 || w1 < 0 || w2 < 0) continue;
      const float z = float(w0 * p[0].z + w1 * p[1].z + w2 * p[2].z);
      const std::size_t i = std::size_t(y) * W + x;
      if (z < depth[i]) {
        depth[i] = z;
        write(i);
      }
    }
}

}  // namespace

double visible_area_fraction(const std::vector<std::array<Vec3, 3>>& triangles,
                             const Camera& camera) {
  Box3 box;
  for (const auto& t : triangles)
    for (const Vec3& p : t) box.add(p);
  constexpr int kRes = 192;
  const ViewBasis b(kRes, kRes, box, camera);
  std::vector<float> depth(kRes * kRes, INFINITY);
  std::vector<uint32_t> id(kRes * kRes, kInvalid);
  std::vector<double> areas(triangles.size());
  double total = 0;
  for (uint32_t f = 0; f < triangles.size(); ++f) {
    const auto& t = triangles[f];
    Vec3 p[3];
    for (int i = 0; i < 3; ++i) {
      const Vec3 d = t[i] - b.center;
      p[i] = {0.5 * kRes + b.scale * dot(d, b.right), 0.5 * kRes - b.scale * dot(d, b.up),
              dot(d, b.forward)};
    }
    areas[f] = 0.5 * norm(cross(t[1] - t[0], t[2] - t[0]));
    total += areas[f];
    raster(p, kRes, kRes, depth, [&](std::size_t i) { id[i] = f; });
  }
  std::sort(id.begin(), id.end());
  id.erase(std::unique(id.begin(), id.end()), id.end());
  double seen = 0;
  for (const uint32_t i : id)
    if (i != kInvalid) seen += areas[i];
  return total > 0 ? seen / total : 0;
}

Camera best_view(const std::vector<std::array<Vec3, 3>>& triangles) {
  Camera best;
  double best_score = -1;
  for (const double elevation : {-30.0, 30.0})
    for (int k = 0; k < 8; ++k) {
      const double az = (22.5 + 45.0 * k) * M_PI / 180, el = elevation * M_PI / 180;
      Camera c;
      c.direction = {-std::cos(el) * std::sin(az), std::sin(el), -std::cos(el) * std::cos(az)};
      const double score = visible_area_fraction(triangles, c);
      if (score > best_score + 1e-3) {
        best_score = score;
        best = c;
      }
    }
  return best;
}

Camera best_view(const std::vector<const TriMesh*>& meshes) {
  std::vector<std::array<Vec3, 3>> triangles;
  for (const TriMesh* m : meshes)
    for (uint32_t f = 0; f < m->num_faces(); ++f) {
      const Tri& t = m->face(f);
      triangles.push_back({m->position(t[0]), m->position(t[1]), m->position(t[2])});
    }
  return best_view(triangles);
}

Canvas::Canvas(int width, int height, const Box3& box, const Camera& camera,
               const std::vector<Vec3>* fit)
    : w_(width), h_(height), surface_(std::make_unique<Surface>()) {
  const ViewBasis b(width, height, box, camera, fit);
  forward_ = b.forward;
  right_ = b.right;
  up_ = b.up;
  center_ = b.center;
  scale_ = b.scale;
  bias_ = 2e-3 * box.diagonal();
  depth_.assign(std::size_t(w_ * ss_) * h_ * ss_, INFINITY);
  pixels_.assign(depth_.size(), {255, 255, 255});
  surface_->surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w_, h_);
  surface_->cr = cairo_create(surface_->surface);
}

Canvas::~Canvas() = default;

Canvas::Projected Canvas::project(Vec3 p) const {
  const Vec3 d = p - center_;
  return {0.5 * w_ + scale_ * dot(d, right_), 0.5 * h_ - scale_ * dot(d, up_), dot(d, forward_)};
}

void Canvas::raster_triangle(const Vec3& a, const Vec3& b, const Vec3& c, Rgb color) {
  const Vec3 n = cross(b - a, c - a);
  if (squared_norm(n) == 0) return;
  // Lambert with a headlight slightly above-left; back faces are shaded darker.
  const Vec3 light = normalized(-1.0 * forward_ + 0.35 * up_ - 0.25 * right_);
  const double cosine = dot(normalized(n), light);
  const double shade = cosine >= 0 ? 0.25 + 0.75 * cosine : 0.15 + 0.3 * -cosine;
  const std::array<uint8_t, 3> rgb = {uint8_t(std::clamp(color.r * shade, 0.0, 1.0) * 255),
                                      uint8_t(std::clamp(color.g * shade, 0.0, 1.0) * 255),
                                      uint8_t(std::clamp(color.b * shade, 0.0, 1.0) * 255)};
  Vec3 p[3];
  for (int k = 0; k < 3; ++k) {
    const Projected q = project(k == 0 ? a : (k == 1 ? b : c));
    p[k] = {q.x * ss_, q.y * ss_, q.z};
  }
  raster(p, w_ * ss_, h_ * ss_, depth_, [&](std::size_t i) { pixels_[i] = rgb; });
}

void Canvas::fill(const TriMesh& mesh, const std::function<Rgb(uint32_t)>& color) {
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const Tri& t = mesh.face(f);
    raster_triangle(mesh.position(t[0]), mesh.position(t[1]), mesh.position(t[2]), color(f));
  }
}

void Canvas::fill_polygons(const std::vector<Vec3>& positions,
                           const std::vector<std::vector<uint32_t>>& polygons,
                           const std::function<Rgb(uint32_t)>& color) {
  for (uint32_t f = 0; f < polygons.size(); ++f)
    for (std::size_t i = 1; i + 1 < polygons[f].size(); ++i)
      raster_triangle(positions[polygons[f][0]], positions[polygons[f][i]],
                      positions[polygons[f][i + 1]], color(f));
}

void Canvas::resolve() {
  if (resolved_) return;
  resolved_ = true;
  cairo_surface_flush(surface_->surface);
  unsigned char* data = cairo_image_surface_get_data(surface_->surface);
  const int stride = cairo_image_surface_get_stride(surface_->surface);
  const int W = w_ * ss_;
  for (int y = 0; y < h_; ++y)
    for (int x = 0; x < w_; ++x) {
      int sum[3] = {0, 0, 0};
      for (int dy = 0; dy < ss_; ++dy)
        for (int dx = 0; dx < ss_; ++dx) {
          const auto& px = pixels_[std::size_t(y * ss_ + dy) * W + x * ss_ + dx];
          for (int k = 0; k < 3; ++k) sum[k] += px[k];
        }
      uint32_t* out = reinterpret_cast<uint32_t*>(data + y * stride) + x;
      const int n = ss_ * ss_;
      *out = (uint32_t(sum[0] / n) << 16) | (uint32_t(sum[1] / n) << 8) | uint32_t(sum[2] / n);
    }
  cairo_surface_mark_dirty(surface_->surface);
}

bool Canvas::visible(double x, double y, double z) const {
  const int W = w_ * ss_, H = h_ * ss_;
  const int cx = int(x * ss_), cy = int(y * ss_);
  // Visible if any nearby supersample is not clearly in front of the point.
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int sx = cx + dx, sy = cy + dy;
      if (sx < 0 || sy < 0 || sx >= W || sy >= H) continue;
      if (z <= depth_[std::size_t(sy) * W + sx] + bias_) return true;
    }
  return false;
}

void Canvas::line(Vec3 a, Vec3 b, Rgb color, double width) {
  resolve();
  const Projected pa = project(a), pb = project(b);
  const int steps = std::max(2, int(std::hypot(pb.x - pa.x, pb.y - pa.y)) + 1);
  cairo_t* cr = surface_->cr;
  cairo_set_source_rgb(cr, color.r, color.g, color.b);
  cairo_set_line_width(cr, width);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  bool drawing = false;
  for (int i = 0; i <= steps; ++i) {
    const double t = double(i) / steps;
    const double x = pa.x + t * (pb.x - pa.x), y = pa.y + t * (pb.y - pa.y),
                 z = pa.z + t * (pb.z - pa.z);
    const bool vis = visible(x, y, z);
    if (vis && !drawing) cairo_move_to(cr, x, y);
    if (vis) cairo_line_to(cr, x, y);
    drawing = vis;
  }
  cairo_stroke(cr);
}

void Canvas::point(Vec3 p, Rgb color, double radius) {
  resolve();
  const Projected q = project(p);
  if (!visible(q.x, q.y, q.z)) return;
  cairo_t* cr = surface_->cr;
  cairo_arc(cr, q.x, q.y, radius, 0, 2 * M_PI);
  cairo_set_source_rgb(cr, color.r, color.g, color.b);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_set_line_width(cr, 0.8);
  cairo_stroke(cr);
}

namespace {
cairo_status_t write_to_stream(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::ostream*>(closure)->write(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}
}  // namespace

void Canvas::caption(const std::string& text, double size) {
  resolve();
  cairo_t* cr = surface_->cr;
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_move_to(cr, 0.6 * size, 1.4 * size);
  cairo_show_text(cr, text.c_str());
}

void Canvas::save_png_row(const std::filesystem::path& path, const std::vector<Canvas*>& canvases) {
  int width = 0, height = 0;
  for (Canvas* c : canvases) {
    c->resolve();
    cairo_surface_flush(c->surface_->surface);
    width += c->w_;
    height = std::max(height, c->h_);
  }
  cairo_surface_t* row = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  cairo_t* cr = cairo_create(row);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  int x = 0;
  for (Canvas* c : canvases) {
    cairo_set_source_surface(cr, c->surface_->surface, x, 0);
    cairo_paint(cr);
    x += c->w_;
  }
  cairo_destroy(cr);
  cairo_surface_flush(row);
  try {
    write_file_atomically(
        path,
        [&](std::ostream& out) {
          if (cairo_surface_write_to_png_stream(row, write_to_stream, &out) != CAIRO_STATUS_SUCCESS)
            throw Error(ErrorKind::internal, "E700", "PNG encoding failed");
        },
        true);
  } catch (...) {
    cairo_surface_destroy(row);
    throw;
  }
  cairo_surface_destroy(row);
}

void Canvas::save_png(const std::filesystem::path& path) {
  resolve();
  cairo_surface_flush(surface_->surface);
  write_file_atomically(
      path,
      [&](std::ostream& out) {
        if (cairo_surface_write_to_png_stream(surface_->surface, write_to_stream, &out) !=
            CAIRO_STATUS_SUCCESS)
          throw Error(ErrorKind::internal, "E700", "PNG encoding failed");
      },
      true);
}

}  // namespace isoquad
