// estimate_spacing: the median nearest-neighbour distance of a frame's points, found in a hash
// grid whose cells hold a couple of points each.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

#include "tear/exec/parallel.h"
#include "tear/surface/mesher.h"

namespace tear {

namespace {

struct CellKey {
  int64_t i, j, k;
  bool operator==(const CellKey& o) const { return i == o.i && j == o.j && k == o.k; }
  bool operator<(const CellKey& o) const {
    return i != o.i ? i < o.i : j != o.j ? j < o.j : k < o.k;
  }
};

uint64_t hash_of(const CellKey& c) {
  uint64_t h = uint64_t(c.i) * 0x9E3779B97F4A7C15ull;
  h ^= uint64_t(c.j) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
  h ^= uint64_t(c.k) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
  return h ^ (h >> 29);
}

// Points sorted by cell, and an open-addressing table from a cell to its run of points.
class HashGrid {
 public:
  HashGrid(const std::vector<Eigen::Vector3d>& points, double cell) : points_(points), cell_(cell) {
    std::vector<CellKey> keys(points.size());
    for (size_t p = 0; p < points.size(); ++p) keys[p] = key_of(points[p]);
    order_.resize(points.size());
    std::iota(order_.begin(), order_.end(), uint32_t(0));
    std::sort(order_.begin(), order_.end(), [&](uint32_t a, uint32_t b) {
      return keys[a] < keys[b] || (keys[a] == keys[b] && a < b);
    });
    size_t cells = 0;
    for (size_t n = 0; n < order_.size(); ++n)
      cells += n == 0 || !(keys[order_[n]] == keys[order_[n - 1]]);
    size_t capacity = 16;
    while (capacity < 2 * cells) capacity *= 2;
    slots_.assign(capacity, Slot{});
    for (size_t n = 0; n < order_.size();) {
      size_t end = n + 1;
      while (end < order_.size() && keys[order_[end]] == keys[order_[n]]) ++end;
      const CellKey key = keys[order_[n]];
      size_t s = hash_of(key) & (slots_.size() - 1);
      while (slots_[s].end != 0) s = (s + 1) & (slots_.size() - 1);
      slots_[s] = Slot{key, uint32_t(n), uint32_t(end)};
      occupancy_ += double(end - n) * double(end - n);
      n = end;
    }
    occupancy_ /= double(std::max<size_t>(1, points.size()));
  }

  // Points in the cell of a random point, on average.
  double occupancy() const { return occupancy_; }

  // Distance from point p to its nearest other point within `max_ring` rings of cells
  // (infinity when none is that close).
  double nearest(uint32_t p, int max_ring) const {
    const CellKey c = key_of(points_[p]);
    double best2 = std::numeric_limits<double>::infinity();
    for (int r = 0; r <= max_ring; ++r) {
      // Points in ring r are at least (r - 1) cells away.
      if (r > 0 && double(r - 1) * cell_ * double(r - 1) * cell_ >= best2) break;
      for (int64_t i = c.i - r; i <= c.i + r; ++i)
        for (int64_t j = c.j - r; j <= c.j + r; ++j)
          for (int64_t k = c.k - r; k <= c.k + r; ++k) {
            if (std::max({std::abs(i - c.i), std::abs(j - c.j), std::abs(k - c.k)}) != r)
              continue;  // inside: an earlier ring
            const Slot* s = find({i, j, k});
            if (!s) continue;
            for (uint32_t n = s->begin; n < s->end; ++n) {
              const uint32_t q = order_[n];
              if (q == p) continue;
              best2 = std::min(best2, (points_[q] - points_[p]).squaredNorm());
            }
          }
    }
    return std::sqrt(best2);
  }

 private:
  struct Slot {
    CellKey key{0, 0, 0};
    uint32_t begin = 0, end = 0;  // end == 0: empty slot
  };

  CellKey key_of(const Eigen::Vector3d& p) const {
    return {int64_t(std::floor(p.x() / cell_)), int64_t(std::floor(p.y() / cell_)),
            int64_t(std::floor(p.z() / cell_))};
  }
  const Slot* find(const CellKey& key) const {
    for (size_t s = hash_of(key) & (slots_.size() - 1);; s = (s + 1) & (slots_.size() - 1)) {
      if (slots_[s].end == 0) return nullptr;
      if (slots_[s].key == key) return &slots_[s];
    }
  }

  const std::vector<Eigen::Vector3d>& points_;
  double cell_;
  std::vector<uint32_t> order_;
  std::vector<Slot> slots_;
  double occupancy_ = 0;
};

}  // namespace

double estimate_spacing(const PointTable& frame) {
  std::vector<Eigen::Vector3d> points = positions(frame);
  points.erase(std::remove_if(points.begin(), points.end(),
                              [](const Eigen::Vector3d& p) { return !p.allFinite(); }),
               points.end());
  if (points.size() < 2 || points.size() > std::numeric_limits<uint32_t>::max() / 2) return 0;
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const Eigen::Vector3d& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  // First cell size: each point's share of the bounding box (of its area when flat), shrunk
  // while the cells hold many points (clustered points in a large box).
  const Eigen::Vector3d extent = hi - lo;
  int dim = 0;
  double measure = 1;
  for (int a = 0; a < 3; ++a)
    if (extent[a] > 0) ++dim, measure *= extent[a];
  if (dim == 0) return 0;  // every point at one place
  double cell = std::pow(measure / double(points.size()), 1.0 / dim);
  constexpr int kMaxRing = 3;
  for (int attempt = 0; attempt < 40; ++attempt) {
    const HashGrid grid(points, cell);
    if (grid.occupancy() > 8 && attempt < 20) {
      cell *= std::pow(2 / grid.occupancy(), 1.0 / dim);
      continue;
    }
    std::vector<double> nearest(points.size());
    parallel_for(points.size(), [&](size_t p) { nearest[p] = grid.nearest(uint32_t(p), kMaxRing); });
    // Coincident points say nothing about the spacing.
    nearest.erase(std::remove(nearest.begin(), nearest.end(), 0.0), nearest.end());
    if (nearest.empty()) return 0;
    const auto median = nearest.begin() + long(nearest.size() / 2);
    std::nth_element(nearest.begin(), median, nearest.end());
    if (std::isfinite(*median)) return *median;
    cell *= 4;  // most points are further apart than the rings searched
  }
  return 0;
}

}  // namespace tear
