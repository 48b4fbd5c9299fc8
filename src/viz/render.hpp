// Headless pictures (DESIGN.md §9.3): a small z-buffer rasterizer with flat Lambert shading,
// supersampled 2x, then antialiased lines and dots drawn with Cairo, each tested against the
// depth buffer so that hidden seams stay hidden. Deterministic; no OpenGL.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/tri_mesh.hpp"

namespace isoquad {

struct Rgb {
  double r = 0, g = 0, b = 0;
};

// The i-th colour of a sequence whose hues step by the golden ratio: neighbours differ clearly.
Rgb distinct_color(uint32_t i);

struct Camera {
  Vec3 direction{-0.55, -0.45, -0.70};  // viewing direction (towards the model)
  Vec3 up{0, 1, 0};
};

// The fraction of the surface's area a viewer sees along `camera` (triangles that show at least
// one pixel of a small depth buffer count whole).
double visible_area_fraction(const std::vector<std::array<Vec3, 3>>& triangles,
                             const Camera& camera);

// The three-quarter view (eight azimuths around `up`, seen from 30 degrees above or below) that
// shows the most surface; ties go to the first candidate, so the choice is deterministic.
Camera best_view(const std::vector<std::array<Vec3, 3>>& triangles);
Camera best_view(const std::vector<const TriMesh*>& meshes);

class Canvas {
 public:
  // Fits `box` into a width x height picture seen along `camera`; or, given `fit`, fits those
  // points' projection (a tighter frame).
  Canvas(int width, int height, const Box3& box, const Camera& camera,
         const std::vector<Vec3>* fit = nullptr);
  ~Canvas();
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  // Flat-shaded triangles; color(f) gives each face's base colour.
  void fill(const TriMesh& mesh, const std::function<Rgb(uint32_t)>& color);
  // Polygons (e.g. quads), fanned into triangles, with one colour.
  void fill_polygons(const std::vector<Vec3>& positions,
                     const std::vector<std::vector<uint32_t>>& polygons,
                     const std::function<Rgb(uint32_t)>& color);
  // Lines and dots, drawn only where they are not behind the filled surface.
  void line(Vec3 a, Vec3 b, Rgb color, double width);
  void point(Vec3 p, Rgb color, double radius);
  // A caption in the top-left corner.
  void caption(const std::string& text, double size = 22);
  // Writes the PNG atomically.
  void save_png(const std::filesystem::path& path);
  // Several canvases side by side in one PNG (atomically).
  static void save_png_row(const std::filesystem::path& path, const std::vector<Canvas*>& canvases);

 private:
  struct Projected {
    double x, y, z;
  };
  Projected project(Vec3 p) const;  // picture coordinates and depth (smaller is nearer)
  bool visible(double x, double y, double z) const;
  void resolve();  // downsamples the raster into the Cairo surface (once, before lines)
  void raster_triangle(const Vec3& a, const Vec3& b, const Vec3& c, Rgb color);

  int w_, h_, ss_ = 2;
  Vec3 right_, up_, forward_, center_;
  double scale_, bias_;
  std::vector<float> depth_;                    // supersampled
  std::vector<std::array<uint8_t, 3>> pixels_;  // supersampled
  bool resolved_ = false;
  struct Surface;
  std::unique_ptr<Surface> surface_;
};

}  // namespace isoquad
