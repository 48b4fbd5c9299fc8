#include "stress_shapes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "marching_tets.hpp"
#include "metrics/quality.hpp"
#include "shapes.hpp"
#include "stress_parametric.hpp"

namespace isoquad::test {

namespace {

constexpr double kPi = std::numbers::pi;

// splitmix64: the same numbers on every platform (std's distributions are not).
struct Rng {
  uint64_t state;
  double next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }
  double in(double lo, double hi) { return lo + (hi - lo) * next(); }
  Vec3 direction() {
    const double z = in(-1, 1), a = in(0, 2 * kPi), s = std::sqrt(1 - z * z);
    return {s * std::cos(a), s * std::sin(a), z};
  }
};

// A smooth noise: a sum of plane waves of one frequency in random directions, of amplitude
// `amp` in all (the sum over sqrt(n)).
struct Waves {
  std::vector<std::array<double, 4>> waves;  // direction times frequency, phase
  double amp = 0;
  Waves(uint64_t seed, int n, double frequency, double amplitude) : amp(amplitude / std::sqrt(n)) {
    Rng rng{seed};
    for (int k = 0; k < n; ++k) {
      const Vec3 d = frequency * rng.direction();
      waves.push_back({d.x, d.y, d.z, rng.in(0, 2 * kPi)});
    }
  }
  double operator()(const Vec3& p) const {
    double s = 0;
    for (const auto& w : waves) s += std::sin(w[0] * p.x + w[1] * p.y + w[2] * p.z + w[3]);
    return amp * s;
  }
};

// Polynomial smooth minimum of blend width k (Quilez): the fillet of a union.
double smin(double a, double b, double k) {
  const double h = std::max(k - std::fabs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k / 4;
}
double torus_sdf(Vec3 p, Vec3 c, double R, double r) {
  const Vec3 q = p - c;
  return std::hypot(std::hypot(q.x, q.y) - R, q.z) - r;
}
double capsule_sdf(Vec3 p, Vec3 a, Vec3 b, double r) {
  const Vec3 ab = b - a;
  const double t = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0);
  return norm(p - a - t * ab) - r;
}
// A box of half sizes `half` with its edges and corners rounded to radius r.
double round_box_sdf(Vec3 p, Vec3 c, Vec3 half, double r) {
  const Vec3 q{std::fabs(p.x - c.x) - half.x + r, std::fabs(p.y - c.y) - half.y + r,
               std::fabs(p.z - c.z) - half.z + r};
  const Vec3 out{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
  return norm(out) + std::min(std::max({q.x, q.y, q.z}), 0.0) - r;
}

// A case whose mesh is the zero set of f in the box [lo, hi] widened by 2 h.
StressCase implicit_case(std::string family, std::string params, int64_t euler, Implicit f, Vec3 lo,
                         Vec3 hi, double h, int smoothing = 3) {
  const Vec3 pad{2 * h, 2 * h, 2 * h};
  return {std::move(family), "", std::move(params), euler, 0, [=] {
            return marching_tets(f, lo - pad, hi + pad, h, smoothing);
          }};
}

void tori(std::vector<StressCase>& out) {
  // genus, minor radius, spacing of the centres (of 2 major radii), bend, cell size
  constexpr std::array<double, 5> kTori[] = {
      {1, 0.35, 0, 0, 0.09},     {1, 0.15, 0, 0, 0.06},       {2, 0.35, 0.9, 0, 0.12},
      {2, 0.25, 1.0, 0, 0.09},   {3, 0.3, 0.85, 0, 0.12},     {3, 0.4, 0.95, 0.3, 0.16},
      {4, 0.3, 0.9, 0, 0.12},    {4, 0.35, 0.85, 0.25, 0.14}, {5, 0.3, 0.9, 0, 0.12},
      {5, 0.4, 0.8, 0.2, 0.16},  {1, 0.5, 0, 0, 0.13},        {3, 0.2, 1.0, 0, 0.08},
      {5, 0.3, 0.95, 0.15, 0.13}};
  for (const auto& [gd, r, spacing, bend, h] : kTori) {
    const int g = int(gd);
    std::vector<Vec3> centres;
    for (int i = 0; i < g; ++i) {
      const double x = 2 * spacing * (i - 0.5 * (g - 1));
      centres.push_back({x, bend * x * x / 2, 0});
    }
    Vec3 lo{INFINITY, INFINITY, -r}, hi{-INFINITY, -INFINITY, r};
    for (const Vec3& c : centres) {
      lo = {std::min(lo.x, c.x - 1 - r), std::min(lo.y, c.y - 1 - r), -r};
      hi = {std::max(hi.x, c.x + 1 + r), std::max(hi.y, c.y + 1 + r), r};
    }
    const double blend = 0.5 * r;
    out.push_back(implicit_case(
        "tori",
        fmt::format("genus {}, minor radius {}, spacing {}, bend {}, cell {}", g, r, spacing, bend,
                    h),
        2 - 2 * g,
        [=](const Vec3& p) {
          double f = INFINITY;
          for (const Vec3& c : centres) f = smin(f, torus_sdf(p, c, 1, r), blend);
          return f;
        },
        lo, hi, h));
  }
}

// The (p, q) torus knot on the torus of radii 1 and rt.
Vec3 torus_knot(double t, int p, int q, double rt) {
  const double s = 2 * kPi * t;
  return {(1 + rt * std::cos(q * s)) * std::cos(p * s),
          (1 + rt * std::cos(q * s)) * std::sin(p * s), rt * std::sin(q * s)};
}

void tubes(std::vector<StressCase>& out) {
  struct Tube {
    const char* curve;
    bool closed;
    double radius;
    int around;
    double aspect;
    Vec3 (*at)(double);
  };
  const Tube kTubes[] = {
      {"straight", false, 0.02, 8, 1,
       [](double t) {
         return Vec3{2 * t - 1, 0, 0};
       }},
      {"helix 3 turns", false, 0.03, 10, 1.5,
       [](double t) {
         return Vec3{0.4 * std::cos(6 * kPi * t), 0.4 * std::sin(6 * kPi * t), 1.5 * t};
       }},
      {"tight helix 6 turns", false, 0.03, 8, 2,
       [](double t) {
         return Vec3{0.3 * std::cos(12 * kPi * t), 0.3 * std::sin(12 * kPi * t), 1.2 * t};
       }},
      {"sine wave", false, 0.04, 12, 1,
       [](double t) {
         return Vec3{2 * t, 0.15 * std::sin(4 * kPi * t), 0};
       }},
      {"wavy helix", false, 0.03, 10, 1.5,
       [](double t) {
         return Vec3{0.5 * std::cos(4 * kPi * t), 0.5 * std::sin(4 * kPi * t),
                     t + 0.1 * std::sin(12 * kPi * t)};
       }},
      {"circle", true, 0.02, 8, 2,
       [](double t) {
         return Vec3{std::cos(2 * kPi * t), std::sin(2 * kPi * t), 0};
       }},
      {"trefoil knot", true, 0.08, 16, 1, [](double t) { return torus_knot(t, 2, 3, 0.45); }},
      {"(2,5) torus knot", true, 0.05, 12, 1.5, [](double t) { return torus_knot(t, 2, 5, 0.45); }},
      {"(3,4) torus knot", true, 0.04, 10, 2, [](double t) { return torus_knot(t, 3, 4, 0.4); }},
      {"spiral 4 turns", false, 0.015, 8, 2,
       [](double t) {
         const double a = 8 * kPi * t, rho = 0.15 + 0.08 * a / (2 * kPi);
         return Vec3{rho * std::cos(a), rho * std::sin(a), 0};
       }},
      {"S-curve", false, 0.01, 8, 2,
       [](double t) {
         return Vec3{2 * t - 1, 0.3 * std::sin(2 * kPi * t), 0.2 * t};
       }},
      {"coil ring", true, 0.04, 12, 1, [](double t) { return torus_knot(t, 1, 8, 0.25); }},
      {"thin trefoil knot", true, 0.03, 8, 2, [](double t) { return torus_knot(t, 2, 3, 0.35); }},
  };
  for (const Tube& t : kTubes)
    out.push_back(
        {"tubes", "",
         fmt::format("{}, radius {}, {} around, aspect {}", t.curve, t.radius, t.around, t.aspect),
         t.closed ? 0 : 2, 0,
         [t] { return swept_tube(t.at, t.closed, t.radius, t.around, t.aspect); }});
}

void spheres(std::vector<StressCase>& out) {
  // subdivisions, axes, per-vertex noise (of the edge length), smooth noise amplitude and
  // frequency
  constexpr std::array<double, 7> kSpheres[] = {
      {4, 1, 1, 1, 0.1, 0, 1},         {4, 1, 1, 1, 0.3, 0, 1},
      {5, 1, 1, 1, 0.2, 0, 1},         {4, 1, 1, 1, 0.1, 0.05, 3},
      {4, 1, 1, 1, 0.2, 0.1, 5},       {5, 1, 1, 1, 0.25, 0.03, 8},
      {4, 1.6, 1, 0.7, 0.15, 0.05, 4}, {5, 2, 0.8, 0.8, 0.1, 0.02, 6},
      {4, 1, 1, 0.4, 0.2, 0.03, 4},    {5, 1.3, 1.1, 0.9, 0.3, 0.08, 3},
      {4, 1, 1, 1, 0.4, 0.15, 2},      {5, 1, 1, 1, 0.35, 0.05, 10},
      {4, 2.5, 0.6, 0.6, 0.2, 0.04, 5}};
  uint64_t seed = 100;
  for (const auto& [sub, ax, ay, az, jitter, amp, freq] : kSpheres) {
    const uint64_t s = seed++;
    out.push_back(
        {"spheres", "",
         fmt::format("{} subdivisions, axes {} {} {}, vertex noise {}, smooth noise {} at {}", sub,
                     ax, ay, az, jitter, amp, freq),
         2, 0, [=] {
           PolyMesh m = icosphere(int(sub));
           const double edge = 1.05 / std::pow(2.0, sub);
           const Waves smooth(s, 6, freq, amp);
           Rng rng{s * 7919};
           for (Vec3& p : m.positions) {
             const Vec3 n = normalized(Vec3{p.x / ax, p.y / ay, p.z / az});
             const Vec3 q{ax * p.x, ay * p.y, az * p.z};
             p = q + (smooth(q) + jitter * edge * rng.in(-1, 1)) * n;
           }
           return m;
         }});
  }
}

void plates(std::vector<StressCase>& out) {
  // open plates: sides, holes, hole radius (of the half cell), bend (dome 1, wave 2), cell size
  constexpr std::array<double, 7> kOpen[] = {
      {1, 1, 1, 0.5, 0, 0, 0.02},     {1, 1, 2, 0.5, 0.1, 1, 0.02},  {2, 1, 3, 0.6, 0, 0, 0.025},
      {2, 1, 4, 0.4, 0.15, 2, 0.025}, {1, 1, 5, 0.5, 0.1, 1, 0.015}, {3, 1, 6, 0.5, 0, 0, 0.025},
      {1.5, 1, 2, 0.7, 0.2, 2, 0.02}, {1, 1, 4, 0.3, 0.05, 1, 0.012}};
  uint64_t seed = 200;
  for (const auto& [a, b, kd, rf, bend, mode, h] : kOpen) {
    const int k = int(kd);
    const int cols = int(std::ceil(std::sqrt(k * a / b))), rows = (k + cols - 1) / cols;
    const double cw = a / cols, ch = b / rows;
    Rng rng{seed++};
    std::vector<std::array<double, 3>> holes;
    for (int i = 0; i < k; ++i)
      holes.push_back({cw * (i % cols + 0.5 + rng.in(-0.1, 0.1)),
                       ch * (i / cols + 0.5 + rng.in(-0.1, 0.1)), rf * std::min(cw, ch) / 2});
    out.push_back(
        {"plates", "",
         fmt::format("open {}x{}, {} holes of {}, bend {} ({}), cell {}", a, b, k, rf, bend,
                     mode == 1   ? "dome"
                     : mode == 2 ? "wave"
                                 : "flat",
                     h),
         1 - k, uint32_t(k + 1), [=] {
           PolyMesh m = plate_with_holes(a, b, holes, h);
           for (Vec3& p : m.positions)
             p.z = mode == 1   ? bend * std::sin(kPi * p.x / a) * std::sin(kPi * p.y / b)
                   : mode == 2 ? bend * std::sin(2 * kPi * p.x / a)
                               : 0;
           return m;
         }});
  }
  // thick plates: sides, thickness, holes (in a row, or 2 x 2 for 4), cell size
  constexpr std::array<double, 5> kThick[] = {{2, 1, 0.2, 1, 0.045},
                                              {2, 1, 0.25, 2, 0.055},
                                              {2, 2, 0.3, 4, 0.06},
                                              {3, 1, 0.2, 3, 0.055},
                                              {1.5, 1.5, 0.4, 2, 0.07}};
  for (const auto& [a, b, t, kd, h] : kThick) {
    const int k = int(kd), cols = k == 4 ? 2 : k, rows = k == 4 ? 2 : 1;
    const double r = 0.25 * std::min(a / cols, b / rows);
    out.push_back(implicit_case(
        "plates", fmt::format("thick {}x{}x{}, {} holes, cell {}", a, b, t, k, h), 2 - 2 * k,
        [=](const Vec3& p) {
          double hole = INFINITY;
          for (int i = 0; i < k; ++i) {
            const double cx = a * ((i % cols + 0.5) / cols - 0.5);
            const double cy = b * ((i / cols + 0.5) / rows - 0.5);
            hole = std::min(hole, std::hypot(p.x - cx, p.y - cy) - r);
          }
          return -smin(-round_box_sdf(p, {}, {a / 2, b / 2, t / 2}, 0.3 * t), hole, 0.3 * t);
        },
        {-a / 2, -b / 2, -t / 2}, {a / 2, b / 2, t / 2}, h));
  }
}

void boxes(std::vector<StressCase>& out) {
  // rounded boxes: half sizes, fillet radius, cell size
  constexpr std::array<double, 5> kBoxes[] = {
      {0.5, 0.5, 0.5, 0.1, 0.06},    {1, 0.5, 0.3, 0.05, 0.05},   {1, 0.25, 0.25, 0.1, 0.055},
      {0.8, 0.6, 0.15, 0.05, 0.045}, {0.5, 0.5, 0.5, 0.25, 0.08}, {1.5, 0.4, 0.4, 0.15, 0.07}};
  for (const auto& [hx, hy, hz, r, h] : kBoxes)
    out.push_back(implicit_case(
        "boxes", fmt::format("box {}x{}x{}, fillet {}, cell {}", 2 * hx, 2 * hy, 2 * hz, r, h), 2,
        [=](const Vec3& p) {
          return round_box_sdf(p, {}, {hx, hy, hz}, r);
        },
        {-hx, -hy, -hz}, {hx, hy, hz}, h));
  // unions of rounded boxes (centre, half sizes), their inner fillets by the blend; a round
  // hole through the first along z
  struct Union {
    const char* what;
    double fillet, blend, hole, h;
    std::vector<std::array<Vec3, 2>> parts;
  };
  const Union kUnions[] = {
      {"L",
       0.05,
       0.15,
       0,
       0.055,
       {{Vec3{0, 0, 0}, {1, 0.3, 0.3}}, {Vec3{0.7, 0.6, 0}, {0.3, 0.9, 0.3}}}},
      {"L upright",
       0.08,
       0.2,
       0,
       0.06,
       {{Vec3{0, 0, 0}, {0.8, 0.2, 0.5}}, {Vec3{-0.6, 0, 0.6}, {0.2, 0.6, 0.2}}}},
      {"T",
       0.05,
       0.1,
       0,
       0.05,
       {{Vec3{0, 0, 0}, {1, 0.2, 0.2}}, {Vec3{0, 0.6, 0}, {0.2, 0.6, 0.2}}}},
      {"3D cross",
       0.05,
       0.15,
       0,
       0.055,
       {{Vec3{0, 0, 0}, {1, 0.2, 0.2}},
        {Vec3{0, 0, 0}, {0.2, 1, 0.2}},
        {Vec3{0, 0, 0}, {0.2, 0.2, 1}}}},
      {"slab with a hole", 0.08, 0.1, 0.3, 0.06, {{Vec3{0, 0, 0}, {1, 0.6, 0.3}}}},
      {"cube with a hole", 0.1, 0.1, 0.2, 0.065, {{Vec3{0, 0, 0}, {0.5, 0.5, 0.5}}}},
      {"steps",
       0.04,
       0.08,
       0,
       0.065,
       {{Vec3{0, 0, -0.3}, {1, 1, 0.2}},
        {Vec3{0, 0, 0}, {0.7, 0.7, 0.2}},
        {Vec3{0, 0, 0.3}, {0.4, 0.4, 0.2}}}}};
  for (const Union& u : kUnions) {
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi = -lo;
    for (const auto& [c, half] : u.parts) {
      lo = {std::min(lo.x, c.x - half.x), std::min(lo.y, c.y - half.y),
            std::min(lo.z, c.z - half.z)};
      hi = {std::max(hi.x, c.x + half.x), std::max(hi.y, c.y + half.y),
            std::max(hi.z, c.z + half.z)};
    }
    out.push_back(implicit_case(
        "boxes",
        fmt::format("{}, {} boxes, fillet {}, blend {}, hole {}, cell {}", u.what, u.parts.size(),
                    u.fillet, u.blend, u.hole, u.h),
        u.hole > 0 ? 0 : 2,
        [u](const Vec3& p) {
          double f = INFINITY;
          for (const auto& [c, half] : u.parts)
            f = smin(f, round_box_sdf(p, c, half, u.fillet), u.blend);
          if (u.hole > 0) f = -smin(-f, std::hypot(p.x, p.y) - u.hole, u.blend);
          return f;
        },
        lo, hi, u.h));
  }
}

void pipes(std::vector<StressCase>& out) {
  struct Pipe {
    const char* what;
    double radius;
    int genus;
    double h;
    std::vector<std::array<Vec3, 2>> segments;
  };
  std::vector<Pipe> kPipes = {
      {"T", 0.15, 0, 0.05, {{Vec3{-1, 0, 0}, {1, 0, 0}}, {Vec3{0, 0, 0}, {0, 1, 0}}}},
      {"Y",
       0.12,
       0,
       0.042,
       {{Vec3{}, {0, 1, 0}}, {Vec3{}, {-0.866, -0.5, 0}}, {Vec3{}, {0.866, -0.5, 0}}}},
      {"cross", 0.1, 0, 0.04, {{Vec3{-1, 0, 0}, {1, 0, 0}}, {Vec3{0, -1, 0}, {0, 1, 0}}}},
      {"6-arm star",
       0.12,
       0,
       0.05,
       {{Vec3{-1, 0, 0}, {1, 0, 0}}, {Vec3{0, -1, 0}, {0, 1, 0}}, {Vec3{0, 0, -1}, {0, 0, 1}}}},
      {"tree",
       0.1,
       0,
       0.038,
       {{Vec3{0, 0, -1}, {0, 0, 0.2}},
        {Vec3{0, 0, 0}, {0.6, 0, 0.6}},
        {Vec3{0, 0, -0.3}, {-0.5, 0.4, 0.3}},
        {Vec3{0, 0, 0.2}, {0, -0.2, 1}}}},
      {"5-arm star", 0.08, 0, 0.032, {}},
      {"comb",
       0.08,
       0,
       0.034,
       {{Vec3{-1, 0, 0}, {1, 0, 0}},
        {Vec3{-0.9, 0, 0}, {-0.9, 0.8, 0}},
        {Vec3{-0.3, 0, 0}, {-0.3, 0.8, 0}},
        {Vec3{0.3, 0, 0}, {0.3, 0.8, 0}},
        {Vec3{0.9, 0, 0}, {0.9, 0.8, 0}}}},
      {"H",
       0.12,
       0,
       0.048,
       {{Vec3{-0.6, -1, 0}, {-0.6, 1, 0}},
        {Vec3{0.6, -1, 0}, {0.6, 1, 0}},
        {Vec3{-0.6, 0, 0}, {0.6, 0, 0}}}},
      {"square frame", 0.1, 1, 0.045, {}},
      {"frame with a diagonal", 0.1, 2, 0.042, {{Vec3{-0.8, -0.8, 0}, {0.8, 0.8, 0}}}},
      {"ladder",
       0.08,
       2,
       0.034,
       {{Vec3{-0.4, -1, 0}, {-0.4, 1, 0}},
        {Vec3{0.4, -1, 0}, {0.4, 1, 0}},
        {Vec3{-0.4, -0.8, 0}, {0.4, -0.8, 0}},
        {Vec3{-0.4, 0, 0}, {0.4, 0, 0}},
        {Vec3{-0.4, 0.8, 0}, {0.4, 0.8, 0}}}},
      {"two-level tree",
       0.05,
       0,
       0.021,
       {{Vec3{0, 0, 0}, {0, 0, 1}},
        {Vec3{0, 0, 1}, {0.5, 0, 1.5}},
        {Vec3{0, 0, 1}, {-0.25, 0.43, 1.5}},
        {Vec3{0, 0, 1}, {-0.25, -0.43, 1.5}},
        {Vec3{0.5, 0, 1.5}, {0.8, 0.2, 1.9}},
        {Vec3{0.5, 0, 1.5}, {0.7, -0.3, 1.9}}}},
      {"bend with a branch", 0.1, 0, 0.038, {{Vec3{0.707, 0.707, 0}, {1.2, 1.2, 0}}}}};
  // The generated ones: the 5-arm star (spiral points on the sphere), the frames' sides, the bend
  // (an arc of 8 segments).
  for (int i = 0; i < 5; ++i) {
    const double z = 1 - (2 * i + 1) / 5.0, a = 2.39996 * i, s = std::sqrt(1 - z * z);
    kPipes[5].segments.push_back({Vec3{}, {s * std::cos(a), s * std::sin(a), z}});
  }
  for (Pipe* p : {&kPipes[8], &kPipes[9]})
    for (int i = 0; i < 4; ++i) {
      const double a0 = kPi / 2 * i + kPi / 4, a1 = a0 + kPi / 2, r = 0.8 * std::sqrt(2.0);
      p->segments.push_back({Vec3{r * std::cos(a0), r * std::sin(a0), 0},
                             Vec3{r * std::cos(a1), r * std::sin(a1), 0}});
    }
  for (int i = 0; i < 8; ++i) {
    const double a0 = kPi / 2 * i / 8, a1 = kPi / 2 * (i + 1) / 8;
    kPipes[12].segments.push_back(
        {Vec3{std::cos(a0), std::sin(a0), 0}, Vec3{std::cos(a1), std::sin(a1), 0}});
  }
  for (const Pipe& p : kPipes) {
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi = -lo;
    for (const auto& s : p.segments)
      for (const Vec3& q : s) {
        lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
        hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
      }
    const Vec3 r{p.radius, p.radius, p.radius};
    out.push_back(implicit_case(
        "pipes",
        fmt::format("{}, {} segments, radius {}, cell {}", p.what, p.segments.size(), p.radius,
                    p.h),
        2 - 2 * p.genus,
        [segments = p.segments, radius = p.radius](const Vec3& q) {
          double f = INFINITY;
          for (const auto& s : segments)
            f = smin(f, capsule_sdf(q, s[0], s[1], radius), radius / 2);
          return f;
        },
        lo - r, hi + r, p.h));
  }
}

void strips(std::vector<StressCase>& out) {
  // centre line (0 straight of this length, 1 arc of radius and angle, 2 closed circle of radius
  // with a wave of this height in z), width, turns, grid step
  constexpr std::array<double, 6> kStrips[] = {
      {0, 2, 0, 0.3, 0.5, 0.02},  {0, 2, 0, 0.4, 1, 0.02},     {0, 3, 0, 0.3, 2, 0.015},
      {0, 3, 0, 0.5, 3, 0.025},   {1, 1, kPi, 0.3, 1, 0.02},   {1, 0.8, 1.5 * kPi, 0.25, 2, 0.015},
      {0, 1, 0, 0.6, 0.25, 0.01}, {2, 1, 0, 0.3, 1, 0.02},     {2, 1, 0, 0.4, 2, 0.025},
      {2, 1, 0, 0.2, 3, 0.015},   {2, 1, 0.15, 0.5, 1, 0.025}, {0, 4, 0, 0.2, 4, 0.02},
      {2, 1.2, 0.2, 0.3, 2, 0.02}};
  for (const auto& [kind, size, extra, w, turns, step] : kStrips) {
    const bool closed = kind == 2;
    const double along = kind == 0 ? size : kind == 1 ? size * extra : 2 * kPi * size;
    const int nu = int(std::lround(along / step)), nv = std::max(3, int(std::lround(w / step)));
    out.push_back({"strips", "",
                   fmt::format("{} {}{}, width {}, {} turns, step {}",
                               kind == 0   ? "straight"
                               : kind == 1 ? "arc"
                                           : "closed band",
                               size,
                               kind == 1   ? fmt::format(" over {:.2f} rad", extra)
                               : kind == 2 ? fmt::format(", wave {}", extra)
                                           : "",
                               w, turns, step),
                   closed ? 0 : 1, closed ? 2u : 1u, [=] {
                     return grid_surface(nu, nv, closed, [=](double u, double v) {
                       const double t = 2 * kPi * turns * u, s = w * (v - 0.5);
                       Vec3 c, radial;
                       if (kind == 0) {
                         c = {size * u, 0, 0};
                         radial = {0, 1, 0};
                       } else if (kind == 1) {
                         const double a = extra * u;
                         c = {size * std::sin(a), size * (1 - std::cos(a)), 0};
                         radial = {std::sin(a), -std::cos(a), 0};
                       } else {
                         const double a = 2 * kPi * u;
                         c = {size * std::cos(a), size * std::sin(a), extra * std::sin(2 * a)};
                         radial = {std::cos(a), std::sin(a), 0};
                       }
                       return c + s * (std::cos(t) * radial + std::sin(t) * Vec3{0, 0, 1});
                     });
                   }});
  }
}

void blobs(std::vector<StressCase>& out) {
  // satellites, noise amplitude and frequency, cell size
  constexpr std::array<double, 4> kBlobs[] = {
      {3, 0.02, 6, 0.064},   {4, 0.03, 8, 0.057}, {5, 0.02, 10, 0.054}, {6, 0.03, 6, 0.079},
      {8, 0.02, 12, 0.059},  {3, 0.04, 5, 0.09},  {5, 0.03, 9, 0.054},  {7, 0.025, 7, 0.07},
      {4, 0.015, 14, 0.057}, {6, 0.04, 6, 0.083}, {2, 0.03, 8, 0.058},  {5, 0.05, 4, 0.082},
      {8, 0.03, 10, 0.066}};
  uint64_t seed = 300;
  for (const auto& [nd, amp, freq, h] : kBlobs) {
    const int n = int(nd);
    const uint64_t s = seed++;
    Rng rng{s};
    std::vector<std::array<double, 4>> balls = {{0, 0, 0, 0.65}};
    for (int i = 0; i < n; ++i) {
      // spiral points on the sphere, jittered: the satellites spread around the body
      const double z = 1 - (2 * i + 1.0) / n, a = 2.39996 * i + rng.in(0, 0.5);
      const Vec3 d = normalized(
          Vec3{std::sqrt(1 - z * z) * std::cos(a), std::sqrt(1 - z * z) * std::sin(a), z} +
          0.2 * rng.direction());
      const Vec3 c = rng.in(0.55, 0.8) * d;
      balls.push_back({c.x, c.y, c.z, rng.in(0.25, 0.45)});
    }
    const Waves noise(s, 6, freq, amp);
    const Implicit f = [=](const Vec3& p) {
      double d = INFINITY;
      for (const auto& b : balls) d = smin(d, norm(p - Vec3{b[0], b[1], b[2]}) - b[3], 0.25);
      return d + noise(p);
    };
    out.push_back(
        {"blobs", "", fmt::format("{} satellites, noise {} at {}, cell {}", n, amp, freq, h), 2, 0,
         [=] {
           // One relaxation round and a scanner's jitter: uneven triangles, as scans have.
           PolyMesh m = marching_tets(f, Vec3{-1.5, -1.5, -1.5}, Vec3{1.5, 1.5, 1.5}, h, 1);
           Rng jitter{s * 31};
           for (Vec3& p : m.positions) p += 0.05 * h * jitter.direction();
           return m;
         }});
  }
}

}  // namespace

const std::vector<StressCase>& stress_cases() {
  static const std::vector<StressCase> cases = [] {
    std::vector<StressCase> all;
    for (auto family : {tori, tubes, spheres, plates, boxes, pipes, strips, blobs}) {
      const std::size_t first = all.size();
      family(all);
      for (std::size_t i = first; i < all.size(); ++i)
        all[i].name = fmt::format("{}_{:02}", all[i].family, i - first + 1);
    }
    return all;
  }();
  return cases;
}

std::vector<const StressCase*> stress_ci_cases() {
  // genus 2 and 5; a helix and a knot; a round and an elongated noisy sphere; an open plate and a
  // thick one; a box and a box with a hole; a T and a frame of genus 2; an open and a closed
  // strip; two blobs
  constexpr const char* kNames[] = {"tori_03",    "tori_09",    "tubes_02",  "tubes_07",
                                    "spheres_02", "spheres_13", "plates_04", "plates_11",
                                    "boxes_01",   "boxes_11",   "pipes_01",  "pipes_10",
                                    "strips_03",  "strips_09",  "blobs_02",  "blobs_07"};
  std::vector<const StressCase*> out;
  for (const char* name : kNames)
    for (const StressCase& c : stress_cases())
      if (c.name == name) out.push_back(&c);
  return out;
}

PolyMesh build_stress_mesh(const StressCase& c) {
  const PolyMesh m = c.build();
  bool edge_manifold = false, vertex_manifold = false, oriented = false;
  const Topology t = topology_of(m, &edge_manifold, &vertex_manifold, &oriented, nullptr, nullptr);
  Box3 box;
  for (const Vec3& p : m.positions) box.add(p);
  std::size_t degenerate = 0;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const auto v = m.face(f);
    const Vec3 n =
        cross(m.positions[v[1]] - m.positions[v[0]], m.positions[v[2]] - m.positions[v[0]]);
    degenerate += norm(n) <= 1e-12 * box.diagonal() * box.diagonal();
  }
  if (!m.all_faces_have(3) || !edge_manifold || !vertex_manifold || !oriented ||
      t.components != 1 || t.euler != c.euler || t.boundary_loops != c.boundary_loops ||
      degenerate > 0)
    throw std::logic_error(fmt::format(
        "{}: chi {} (intended {}), {} boundary loops (intended {}), {} components, manifold {}/{}, "
        "oriented {}, {} degenerate triangles",
        c.name, t.euler, c.euler, t.boundary_loops, c.boundary_loops, t.components, edge_manifold,
        vertex_manifold, oriented, degenerate));
  return m;
}

PolyMesh scaled_to_diagonal(PolyMesh m, double diagonal) {
  Box3 box;
  for (const Vec3& p : m.positions) box.add(p);
  const Vec3 centre = 0.5 * (box.lo + box.hi);
  const double s = diagonal / box.diagonal();
  for (Vec3& p : m.positions) p = s * (p - centre);
  return m;
}

}  // namespace isoquad::test
