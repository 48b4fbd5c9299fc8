#include "seg/vsa.hpp"

#include "core/face_regions.hpp"
#include "core/z_order.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <queue>
#include <random>

namespace isoquad {

namespace {

// Running sums of a region. With unit face normals the L2,1 error of a region under its best
// plane is exactly 2 (A - |sum A n|), and the compactness term is sum A|c|^2 - |sum A c|^2 / A,
// so errors of regions and of candidate merges cost O(1).
struct RegionSums {
  double area = 0, c2 = 0;
  Vec3 n, c;
  uint32_t faces = 0;
  void add(double a, Vec3 normal, Vec3 centroid) {
    area += a;
    n += a * normal;
    c += a * centroid;
    c2 += a * dot(centroid, centroid);
    ++faces;
  }
  RegionSums merged(const RegionSums& o) const {
    RegionSums r = *this;
    r.area += o.area, r.c2 += o.c2, r.n += o.n, r.c += o.c, r.faces += o.faces;
    return r;
  }
  double error(double compact_weight) const {
    if (area <= 0) return 0;
    return std::max(0.0, 2 * (area - norm(n))) +
           compact_weight * std::max(0.0, c2 - squared_norm(c) / area);
  }
};

// A flood queue entry as one 128-bit key, compared as an integer: the error's bits (a
// non-negative double orders as its bit pattern), then the face (in the flood's numbering), then
// the proxy. Smaller keys pop first; ties are broken by ids, so the flood is deterministic.
__extension__ typedef unsigned __int128 QueueKey;

QueueKey queue_key(double error, uint32_t face, uint32_t proxy) {
  return QueueKey(std::bit_cast<uint64_t>(error)) << 64 | uint64_t(face) << 32 | proxy;
}

// A 4-ary min-heap of keys: the flood's hot loop, with branch-light integer comparisons. Half as
// deep as a binary heap, its four children next to each other; the pop order is the same.
class KeyHeap {
 public:
  void clear() { a_.clear(); }
  bool empty() const { return a_.empty(); }
  void push(QueueKey k) {
    std::size_t i = a_.size();
    a_.push_back(k);
    while (i > 0) {
      const std::size_t p = (i - 1) / 4;
      if (!(k < a_[p])) break;
      a_[i] = a_[p];
      i = p;
    }
    a_[i] = k;
  }
  QueueKey pop() {
    const QueueKey top = a_[0], last = a_.back();
    a_.pop_back();
    const std::size_t n = a_.size();
    if (n == 0) return top;
    std::size_t i = 0;
    while (true) {
      const std::size_t first = 4 * i + 1;
      if (first >= n) break;
      std::size_t c = first;
      const std::size_t end = std::min(first + 4, n);
      for (std::size_t k = first + 1; k < end; ++k)
        if (a_[k] < a_[c]) c = k;
      if (!(a_[c] < last)) break;
      a_[i] = a_[c];
      i = c;
    }
    a_[i] = last;
    return top;
  }

 private:
  std::vector<QueueKey> a_;
};

class Vsa {
 public:
  Vsa(const TriMesh& mesh, const EdgeData<char>& barrier, const VsaOptions& o)
      : m_(mesh), barrier_(barrier), o_(o), rng_(o.seed) {
    const uint32_t nf = m_.num_faces();
    a_.resize(nf);
    c_.resize(nf);
    for (uint32_t f = 0; f < nf; ++f) {
      a_[f] = m_.face_area(f);
      const Tri& t = m_.face(f);
      c_[f] = (m_.position(t[0]) + m_.position(t[1]) + m_.position(t[2])) / 3.0;
      area_ += a_[f];
    }
    drop_noise_barriers();
    smooth_normals();
    label_.assign(nf, kInvalid);
  }

  Segmentation run();
  FaceData<uint32_t> split(const FaceData<uint32_t>& labels, const std::vector<uint32_t>& regions);

 private:
  bool crossable(uint32_t h) const { return m_.twin(h) != kInvalid && !barrier_[m_.edge(h)]; }
  void drop_noise_barriers();
  double weight() const {
    return o_.compactness / (area_ / double(std::max<std::size_t>(proxies_.size(), 1)));
  }
  double face_error(uint32_t f, const Proxy& p) const {
    return a_[f] * (squared_norm(n_[f] - p.normal) + weight() * squared_norm(c_[f] - p.centroid));
  }
  Proxy proxy_at(uint32_t f) const {
    Proxy p;
    p.normal = n_[f];
    p.centroid = c_[f];
    p.seed_face = f;
    return p;
  }
  void smooth_normals();
  void partition();
  void flood();
  void fit();
  double total_error() const;
  void relax(uint32_t iterations);
  void converge();
  void add_proxies(uint32_t count);
  uint32_t farthest_in_region(const std::vector<uint32_t>& seeds, uint32_t region);
  bool teleport();
  void merge_small(double min_area);
  void compact();
  std::vector<RegionSums> sums() const;

  const TriMesh& m_;
  EdgeData<char> barrier_;
  VsaOptions o_;
  std::mt19937_64 rng_;
  std::vector<Vec3> n_, c_;
  std::vector<double> a_;
  double area_ = 0;
  std::vector<uint32_t> label_;
  std::vector<double> best_queued_;
  std::vector<uint32_t> best_proxy_;
  // For flood, in its own face numbering (built on the first flood): order_ lists the faces,
  // rank_ is its inverse; per face its normal, centroid and area together, and its crossable
  // neighbours (kInvalid where the edge is a barrier or the boundary).
  struct PackedFace {
    Vec3 normal, centroid;
    double area;
  };
  void build_flood_order();
  std::vector<uint32_t> order_, rank_;
  std::vector<PackedFace> packed_;
  std::vector<uint32_t> near_, flood_label_;
  KeyHeap heap_;
  std::vector<Proxy> proxies_;
  std::vector<double> log_;
  std::vector<uint32_t> dist_, queue_;  // farthest_in_region's
};

// Feature edges that enclose fewer than 10 faces are noise (common on scans at 60 degrees), not
// features: they stop being barriers, so that they neither count as patches nor block flooding.
void Vsa::drop_noise_barriers() {
  std::vector<uint32_t> region;
  const uint32_t count = face_regions(
      m_, [&](uint32_t h) { return crossable(h); }, region);
  if (count < 2) return;
  std::vector<uint32_t> size(count, 0);
  for (uint32_t r : region) ++size[r];
  for (uint32_t f = 0; f < m_.num_faces(); ++f)
    if (size[region[f]] < 10)
      for (uint32_t i = 0; i < 3; ++i) barrier_[m_.edge(3 * f + i)] = 0;
}

// Scan noise makes face normals jitter; the metric uses normals averaged twice with those
// neighbours that turn less than 30 degrees (bilateral: sharp edges stay sharp even where no
// feature is marked) and not across barriers. The geometry is untouched.
void Vsa::smooth_normals() {
  const uint32_t nf = m_.num_faces();
  n_.resize(nf);
  for (uint32_t f = 0; f < nf; ++f) n_[f] = m_.face_normal(f);
  const std::vector<Vec3> raw = n_;
  std::vector<Vec3> next(nf);
  const double cos_limit = std::cos(30.0 * 3.14159265358979323846 / 180.0);
  for (int it = 0; it < 2; ++it) {
    for (uint32_t f = 0; f < nf; ++f) {
      Vec3 s = a_[f] * n_[f];
      for (uint32_t i = 0; i < 3; ++i)
        if (crossable(3 * f + i)) {
          const uint32_t g = TriMesh::face_of(m_.twin(3 * f + i));
          if (dot(raw[f], raw[g]) >= cos_limit) s += a_[g] * n_[g];
        }
      next[f] = squared_norm(s) > 0 ? normalized(s) : n_[f];
    }
    n_.swap(next);
  }
}

// Distortion-minimizing flooding from the proxies' seed faces. The hot loop of the segmentation
// (tens of floods over every face), bound by memory reads: it runs on its own numbering of the
// faces, in Morton (Z-curve) order of their centroids, with per face its normal, centroid, area
// and crossable neighbours packed together. Input files often list faces in no spatial order
// (on bunny00 adjacent faces are a median of 12,909 apart). The errors are computed as
// face_error does; exact ties go by the flood's numbering (looking up the input ids instead cost
// 13% of the flood and changed no corpus segmentation). The queue is a binary heap of integer
// keys: 30% faster than std::push_heap on structs (bunny00 in 30 patches: 1.04 -> 0.73 s, then
// 0.64 s without the lookup).
void Vsa::flood() {
  const uint32_t nf = m_.num_faces();
  if (order_.empty() && nf > 0) build_flood_order();
  // Only an entry that beats the best one already queued for a face can decide its label.
  std::vector<double>& best = best_queued_;
  best.assign(nf, INFINITY);
  std::vector<uint32_t>& best_proxy = best_proxy_;
  best_proxy.assign(nf, kInvalid);
  std::vector<uint32_t>& label = flood_label_;
  label.assign(nf, kInvalid);
  const double w = weight();
  KeyHeap& heap = heap_;
  heap.clear();
  auto push_neighbours = [&](uint32_t f, uint32_t p) {
    const Proxy& proxy = proxies_[p];
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t g = near_[3 * f + i];
      if (g == kInvalid || label[g] != kInvalid) continue;
      const PackedFace& d = packed_[g];
      const double e = d.area * (squared_norm(d.normal - proxy.normal) +
                                 w * squared_norm(d.centroid - proxy.centroid));
      // The error depends on the face and the proxy only: the same pair reached again from
      // another neighbour would be a duplicate key, so only a strictly better key is queued.
      if (e < best[g] || (e == best[g] && p < best_proxy[g])) {
        best[g] = e;
        best_proxy[g] = p;
        heap.push(queue_key(e, g, p));
      }
    }
  };
  for (uint32_t p = 0; p < proxies_.size(); ++p) label[rank_[proxies_[p].seed_face]] = p;
  for (uint32_t p = 0; p < proxies_.size(); ++p) push_neighbours(rank_[proxies_[p].seed_face], p);
  while (!heap.empty()) {
    const QueueKey k = heap.pop();
    const uint32_t face = uint32_t(k >> 32), proxy = uint32_t(k);
    if (label[face] != kInvalid) continue;
    label[face] = proxy;
    push_neighbours(face, proxy);
  }
  for (uint32_t i = 0; i < nf; ++i) label_[order_[i]] = label[i];
}

void Vsa::build_flood_order() {
  const uint32_t nf = m_.num_faces();
  order_ = z_order(c_);
  rank_.resize(nf);
  for (uint32_t i = 0; i < nf; ++i) rank_[order_[i]] = i;
  near_.resize(3 * std::size_t(nf));
  packed_.resize(nf);
  for (uint32_t i = 0; i < nf; ++i) {
    const uint32_t f = order_[i];
    for (uint32_t k = 0; k < 3; ++k)
      near_[3 * i + k] =
          crossable(3 * f + k) ? rank_[TriMesh::face_of(m_.twin(3 * f + k))] : kInvalid;
    packed_[i] = {n_[f], c_[f], a_[f]};
  }
}

// Floods; regions that no seed can reach (enclosed by barriers) get a proxy of their own, seeded
// at their largest face.
void Vsa::partition() {
  flood();
  std::vector<uint32_t> region;
  const uint32_t unreached = face_regions(
      m_, [&](uint32_t h) { return crossable(h); },
      [&](uint32_t f) { return label_[f] == kInvalid; }, region);
  if (unreached == 0) return;
  std::vector<uint32_t> best(unreached, kInvalid);
  for (uint32_t f = 0; f < m_.num_faces(); ++f) {
    const uint32_t r = region[f];
    if (r != kInvalid && (best[r] == kInvalid || a_[f] > a_[best[r]])) best[r] = f;
  }
  for (uint32_t f : best) proxies_.push_back(proxy_at(f));
  flood();
}

std::vector<RegionSums> Vsa::sums() const {
  std::vector<RegionSums> s(proxies_.size());
  for (uint32_t f = 0; f < m_.num_faces(); ++f) s[label_[f]].add(a_[f], n_[f], c_[f]);
  return s;
}

// Refits every proxy to its region; the new seed is the region's best-fitting face.
void Vsa::fit() {
  const auto s = sums();
  for (uint32_t p = 0; p < proxies_.size(); ++p) {
    Proxy& q = proxies_[p];
    q.area = s[p].area;
    // A closed region (a sphere in one patch) has a near-zero normal sum: keep the old normal.
    if (norm(s[p].n) > 1e-12 * std::max(s[p].area, 1e-300)) q.normal = normalized(s[p].n);
    if (s[p].area > 0) q.centroid = s[p].c / s[p].area;
    q.error = 0;
    q.seed_face = kInvalid;
  }
  std::vector<double> best(proxies_.size(), INFINITY);
  for (uint32_t f = 0; f < m_.num_faces(); ++f) {
    Proxy& q = proxies_[label_[f]];
    const double e = face_error(f, q);
    q.error += e;
    if (e < best[label_[f]]) {
      best[label_[f]] = e;
      q.seed_face = f;
    }
  }
}

double Vsa::total_error() const {
  double e = 0;
  for (const Proxy& p : proxies_) e += p.error;
  return e;
}

void Vsa::relax(uint32_t iterations) {
  for (uint32_t i = 0; i < iterations; ++i) {
    partition();
    fit();
    log_.push_back(total_error());
  }
}

// Lloyd iterations until the error, averaged over 3 iterations, changes by less than 0.1%
// (it may fluctuate); keeps the best labelling seen.
void Vsa::converge() {
  auto best_labels = label_;
  auto best_proxies = proxies_;
  double best = total_error();
  std::vector<double> hist{best};
  for (uint32_t it = 0; it < o_.max_iterations; ++it) {
    relax(1);
    const double e = total_error();
    hist.push_back(e);
    if (e < best) {
      best = e, best_labels = label_, best_proxies = proxies_;
    }
    if (hist.size() > 3) {
      const double avg_change = std::fabs(hist[hist.size() - 4] - e) / 3.0;
      if (avg_change <= 1e-3 * e || e == 0) break;
    }
  }
  label_ = std::move(best_labels);
  proxies_ = std::move(best_proxies);
}

// Error diffusion: each region receives new seeds in proportion to its error (carrying the
// rounding residual over); within a region, new seeds go to the faces farthest from its seeds.
void Vsa::add_proxies(uint32_t count) {
  if (count == 0) return;
  const uint32_t k = uint32_t(proxies_.size());
  const double total = total_error();
  std::vector<uint32_t> per(k, 0);
  uint32_t placed = 0;
  if (total > 0) {
    double residual = 0;
    for (uint32_t p = 0; p < k && placed < count; ++p) {
      const double want = proxies_[p].error / total * count + residual;
      const uint32_t n = std::min(uint32_t(std::floor(want)), count - placed);
      residual = want - n;
      per[p] = n;
      placed += n;
    }
  }
  // What rounding left over (or everything, on a zero-error surface) goes to the largest regions.
  std::vector<uint32_t> order(k);
  for (uint32_t p = 0; p < k; ++p) order[p] = p;
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return proxies_[a].error + proxies_[a].area > proxies_[b].error + proxies_[b].area;
  });
  for (uint32_t i = 0; placed < count; i = (i + 1) % k, ++placed) ++per[order[i]];

  std::vector<uint32_t> seeds;
  for (uint32_t p = 0; p < k; ++p) {
    for (uint32_t n = 0; n < per[p]; ++n) {
      // Farthest within region p from its seed and the seeds added to it so far.
      seeds.clear();
      for (uint32_t q = 0; q < proxies_.size(); ++q)
        if ((q == p || q >= k) && label_[proxies_[q].seed_face] == p)
          seeds.push_back(proxies_[q].seed_face);
      const uint32_t far = farthest_in_region(seeds, p);
      if (far == kInvalid) break;  // a one-face region cannot take another seed
      proxies_.push_back(proxy_at(far));
    }
  }
}

// The face of region `region` farthest in hops (through crossable edges, inside the region) from
// `seeds` (faces of the region), ties to the smaller id; kInvalid if every face is a seed.
uint32_t Vsa::farthest_in_region(const std::vector<uint32_t>& seeds, uint32_t region) {
  dist_.assign(m_.num_faces(), kInvalid);
  queue_.clear();
  for (const uint32_t f : seeds) {
    dist_[f] = 0;
    queue_.push_back(f);
  }
  uint32_t far = queue_.front();
  for (std::size_t qi = 0; qi < queue_.size(); ++qi) {
    const uint32_t f = queue_[qi];
    if (dist_[f] > dist_[far] || (dist_[f] == dist_[far] && f < far)) far = f;
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i;
      if (!crossable(h)) continue;
      const uint32_t g = TriMesh::face_of(m_.twin(h));
      if (label_[g] == region && dist_[g] == kInvalid) {
        dist_[g] = dist_[f] + 1;
        queue_.push_back(g);
      }
    }
  }
  return dist_[far] == 0 ? kInvalid : far;
}

// CGAL-style teleportation: merge the adjacent pair that costs least and re-seed the freed
// proxy in the worst region; kept only if the error drops.
bool Vsa::teleport() {
  const auto s = sums();
  const double w = weight();
  const uint32_t k = uint32_t(proxies_.size());
  uint32_t worst = 0;
  for (uint32_t p = 1; p < k; ++p)
    if (s[p].error(w) > s[worst].error(w)) worst = p;
  if (s[worst].faces < 2) return false;
  double best_cost = INFINITY;
  uint32_t bi = kInvalid, bj = kInvalid;
  for (uint32_t h = 0; h < m_.num_halfedges(); ++h) {
    if (!crossable(h)) continue;
    const uint32_t i = label_[TriMesh::face_of(h)], j = label_[TriMesh::face_of(m_.twin(h))];
    if (i >= j || i == worst || j == worst) continue;
    const double cost = s[i].merged(s[j]).error(w) - s[i].error(w) - s[j].error(w);
    if (cost < best_cost || (cost == best_cost && std::pair(i, j) < std::pair(bi, bj))) {
      best_cost = cost, bi = i, bj = j;
    }
  }
  if (bi == kInvalid || best_cost >= 0.5 * s[worst].error(w)) return false;
  const auto saved_labels = label_;
  const auto saved_proxies = proxies_;
  const double before = total_error();
  for (uint32_t& l : label_)
    if (l == bj) l = bi;
  uint32_t far = kInvalid;
  double far_err = -1;
  for (uint32_t f = 0; f < m_.num_faces(); ++f)
    if (label_[f] == worst && f != proxies_[worst].seed_face) {
      const double e = face_error(f, proxies_[worst]);
      if (e > far_err) far_err = e, far = f;
    }
  proxies_[bj] = proxy_at(far);
  relax(3);
  if (total_error() < before) return true;
  label_ = saved_labels;
  proxies_ = saved_proxies;
  return false;
}

// Regions below the size floor are merged into the neighbour they fit best (not across a
// barrier: a region enclosed by features stays).
void Vsa::merge_small(double min_area) {
  while (true) {
    const auto s = sums();
    const double w = weight();
    // A region below 10 faces may merge across a barrier too: features that enclose a few
    // faces (noise on scans) do not deserve a patch.
    auto joins = [&](uint32_t h, const RegionSums& r) {
      return m_.twin(h) != kInvalid && (crossable(h) || r.faces < 10);
    };
    std::vector<char> has_neighbour(proxies_.size(), 0);
    for (uint32_t h = 0; h < m_.num_halfedges(); ++h) {
      const uint32_t p = label_[TriMesh::face_of(h)];
      if (joins(h, s[p]) && p != label_[TriMesh::face_of(m_.twin(h))]) has_neighbour[p] = 1;
    }
    uint32_t victim = kInvalid;
    for (uint32_t p = 0; p < proxies_.size(); ++p) {
      if (s[p].faces >= 10 && s[p].area >= min_area) continue;
      if (has_neighbour[p] && (victim == kInvalid || s[p].area < s[victim].area)) victim = p;
    }
    if (victim == kInvalid || proxies_.size() <= 1) return;
    uint32_t into = kInvalid;
    double best = INFINITY;
    for (uint32_t h = 0; h < m_.num_halfedges(); ++h) {
      if (label_[TriMesh::face_of(h)] != victim || !joins(h, s[victim])) continue;
      const uint32_t q = label_[TriMesh::face_of(m_.twin(h))];
      if (q == victim) continue;
      const double cost = s[q].merged(s[victim]).error(w) - s[q].error(w);
      if (cost < best || (cost == best && q < into)) best = cost, into = q;
    }
    for (uint32_t& l : label_)
      if (l == victim) l = into;
    proxies_.erase(proxies_.begin() + victim);
    for (uint32_t& l : label_)
      if (l > victim) --l;
  }
}

// Patch ids in order of each patch's first face, so ids do not depend on seeding history.
void Vsa::compact() {
  std::vector<uint32_t> remap(proxies_.size(), kInvalid);
  std::vector<Proxy> ordered;
  for (uint32_t& l : label_) {
    if (remap[l] == kInvalid) {
      remap[l] = uint32_t(ordered.size());
      ordered.push_back(proxies_[l]);
    }
    l = remap[l];
  }
  proxies_ = std::move(ordered);
}

Segmentation Vsa::run() {
  const uint32_t nf = m_.num_faces();
  proxies_.push_back(proxy_at(uint32_t(rng_() % nf)));
  relax(1);
  const uint32_t k0 = uint32_t(proxies_.size());  // one per barrier-enclosed region
  const double e1 = total_error();
  const double h = o_.target_edge_length;
  const uint32_t k_max =
      h > 0 ? std::max<uint32_t>(k0, uint32_t(area_ / (16 * h * h))) : std::max(k0, 400u);
  const uint32_t k_min = std::max<uint32_t>(k0, m_.boundary_loops().empty() ? 6 : 1);
  const uint32_t target = o_.patches > 0 ? std::max(o_.patches, k0) : k_max;
  // Hierarchical seeding: double the proxy count by error diffusion, relaxing after each step.
  while (proxies_.size() < target) {
    if (o_.patches == 0 && proxies_.size() >= k_min && total_error() <= o_.error_drop * e1) break;
    const uint32_t k = uint32_t(proxies_.size());
    add_proxies(std::min(k, target - k));
    if (proxies_.size() == k) break;  // nowhere left to seed
    relax(3);
  }
  converge();
  for (uint32_t r = 0; r < o_.teleport_rounds; ++r)
    if (!teleport()) break;
  merge_small(h > 0 ? 2 * h * h : 0.0);
  compact();
  fit();
  log_.push_back(total_error());

  Segmentation seg;
  seg.face_patch = FaceData<uint32_t>(label_);
  seg.proxies = proxies_;
  seg.energy_log = log_;
  return seg;
}

// Each listed region in two: a second proxy at the face farthest (in hops inside the region)
// from the region's best-fitting face, then Lloyd iterations that flood only the listed regions,
// each proxy inside its own region. The other regions keep their faces.
FaceData<uint32_t> Vsa::split(const FaceData<uint32_t>& labels,
                              const std::vector<uint32_t>& regions) {
  const uint32_t nf = m_.num_faces();
  label_.assign(labels.begin(), labels.end());
  uint32_t k = 0;
  for (uint32_t l : label_) k = std::max(k, l + 1);
  proxies_.assign(k, Proxy{});
  fit();
  std::vector<uint32_t> parent(k);
  for (uint32_t p = 0; p < k; ++p) parent[p] = p;
  std::vector<char> split_region(k, 0);
  for (uint32_t r : regions)
    if (r < k) split_region[r] = 1;
  for (uint32_t r = 0; r < k; ++r) {
    if (!split_region[r] || proxies_[r].seed_face == kInvalid) continue;
    const uint32_t far = farthest_in_region({proxies_[r].seed_face}, r);
    if (far == kInvalid) continue;
    proxies_.push_back(proxy_at(far));
    parent.push_back(r);
  }
  using Entry = std::pair<double, std::pair<uint32_t, uint32_t>>;  // error, (face, proxy)
  for (int it = 0; it < 6; ++it) {
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    for (uint32_t f = 0; f < nf; ++f)
      if (split_region[labels[f]]) label_[f] = kInvalid;
    auto push = [&](uint32_t f, uint32_t p) {
      for (uint32_t i = 0; i < 3; ++i) {
        const uint32_t h = 3 * f + i;
        if (!crossable(h)) continue;
        const uint32_t g = TriMesh::face_of(m_.twin(h));
        if (label_[g] == kInvalid && labels[g] == parent[p])
          heap.push({face_error(g, proxies_[p]), {g, p}});
      }
    };
    for (uint32_t p = 0; p < proxies_.size(); ++p)
      if (split_region[parent[p]]) label_[proxies_[p].seed_face] = p;
    for (uint32_t p = 0; p < proxies_.size(); ++p)
      if (split_region[parent[p]]) push(proxies_[p].seed_face, p);
    while (!heap.empty()) {
      const auto [e, fp] = heap.top();
      heap.pop();
      if (label_[fp.first] != kInvalid) continue;
      label_[fp.first] = fp.second;
      push(fp.first, fp.second);
    }
    for (uint32_t f = 0; f < nf; ++f)
      if (label_[f] == kInvalid) label_[f] = labels[f];  // not reached (cut off by barriers)
    fit();
  }
  return FaceData<uint32_t>(label_);
}

}  // namespace

FaceData<uint32_t> split_vsa_regions(const TriMesh& mesh, const EdgeData<char>& barrier,
                                     const FaceData<uint32_t>& labels,
                                     const std::vector<uint32_t>& regions,
                                     const VsaOptions& options) {
  return Vsa(mesh, barrier, options).split(labels, regions);
}

Segmentation segment_vsa(const TriMesh& mesh, const EdgeData<char>& barrier,
                         const VsaOptions& options) {
  return Vsa(mesh, barrier, options).run();
}

double vsa_energy(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t num_patches,
                  double compactness) {
  std::vector<RegionSums> s(num_patches);
  double area = 0;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const Tri& t = mesh.face(f);
    const Vec3 c = (mesh.position(t[0]) + mesh.position(t[1]) + mesh.position(t[2])) / 3.0;
    s[labels[f]].add(mesh.face_area(f), mesh.face_normal(f), c);
    area += mesh.face_area(f);
  }
  double e = 0;
  for (const auto& r : s) e += r.error(compactness / (area / std::max(num_patches, 1u)));
  return e;
}

}  // namespace isoquad
