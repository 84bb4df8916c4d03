#include "tear/damage/crack_metrics.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace tear {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Points bucketed by a uniform grid of 2D cells (coordinates given by `key`).
class CellIndex {
 public:
  CellIndex(double cell, size_t n) : inv_(1 / cell) { cells_.reserve(n); }
  void add(double a, double b, size_t i) { cells_[key(a, b)].push_back(i); }
  // Calls fn(i) for the points in the 3 x 3 cells around (a, b).
  template <class Fn>
  void near(double a, double b, Fn&& fn) const {
    const int64_t ia = int64_t(std::floor(a * inv_)), ib = int64_t(std::floor(b * inv_));
    for (int64_t x = ia - 1; x <= ia + 1; ++x)
      for (int64_t y = ib - 1; y <= ib + 1; ++y) {
        const auto it = cells_.find(pack(x, y));
        if (it == cells_.end()) continue;
        for (size_t i : it->second) fn(i);
      }
  }

 private:
  static uint64_t pack(int64_t x, int64_t y) {
    return (uint64_t(x) << 32) ^ (uint64_t(y) & 0xffffffffu);
  }
  uint64_t key(double a, double b) const {
    return pack(int64_t(std::floor(a * inv_)), int64_t(std::floor(b * inv_)));
  }
  double inv_;
  std::unordered_map<uint64_t, std::vector<size_t>> cells_;
};

// Two unit vectors orthogonal to n and to each other (in 2D: the crack line and z).
void basis(int dim, const Vec3d& n, Vec3d* e1, Vec3d* e2) {
  const Vec3d helper =
      dim == 2 ? Vec3d::UnitZ() : (std::abs(n[0]) < 0.9 ? Vec3d::UnitX() : Vec3d::UnitY());
  *e1 = n.cross(helper).normalized();
  *e2 = n.cross(*e1);
}

// How purely cracked the stripes along n are: the projections x . n of all points and of the
// cracked ones binned at a quarter spacing and smoothed with a triangle one spacing wide each
// side (so that where the bins fall does not matter); then the mean over the cracked points
// of the cracked share of their bin, sum_b c_b (c_b / a_b) / sum_b c_b.
double purity(const std::vector<Vec3d>& all, const std::vector<char>& cracked, const Vec3d& n,
              double spacing) {
  constexpr int kSub = 4;  // bins per spacing
  const double bin = spacing / kSub;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Vec3d& p : all) {
    const double s = p.dot(n);
    lo = std::min(lo, s), hi = std::max(hi, s);
  }
  const size_t bins = size_t((hi - lo) / bin) + 1 + 2 * kSub;
  std::vector<double> a(bins, 0), c(bins, 0);
  for (size_t i = 0; i < all.size(); ++i) {
    const size_t b = kSub + std::min(bins - 1, size_t((all[i].dot(n) - lo) / bin));
    a[b] += 1;
    if (cracked[i]) c[b] += 1;
  }
  auto smooth = [&](const std::vector<double>& h) {
    std::vector<double> out(bins, 0);
    for (size_t b = 0; b < bins; ++b) {
      if (h[b] == 0) continue;
      for (int k = -kSub + 1; k < kSub; ++k) {
        const long t = long(b) + k;
        if (t >= 0 && t < long(bins)) out[size_t(t)] += h[b] * (kSub - std::abs(k));
      }
    }
    return out;
  };
  const std::vector<double> sa = smooth(a), sc = smooth(c);
  double num = 0, den = 0;
  for (size_t b = 0; b < bins; ++b)
    if (sc[b] > 0) num += c[b] * sc[b] / sa[b], den += c[b];
  return den > 0 ? num / den : 0;
}

Vec3d from_angle(double degrees) {  // the normal of a 2D crack line at `degrees`
  const double t = degrees * kPi / 180;
  return Vec3d(-std::sin(t), std::cos(t), 0);
}

}  // namespace

Vec3d crack_normal(int dim, const std::vector<Vec3d>& points, const std::vector<char>& cracked,
                   double spacing) {
  if (std::count(cracked.begin(), cracked.end(), 1) < 3) return Vec3d::Zero();
  Vec3d best = Vec3d::Zero();
  double best_score = -1;
  auto consider = [&](const Vec3d& n) {
    const double c = purity(points, cracked, n, spacing);
    if (c > best_score) best_score = c, best = n;
  };
  if (dim == 2) {
    for (int k = 0; k < 720; ++k) consider(from_angle(-90 + 0.25 * (k + 1)));
    return best;
  }
  // Fibonacci points on the upper half sphere (n and -n are the same crack), about 5.8
  // degrees apart; then polar grids around the best: 1 degree steps out to 8 degrees, 0.25
  // degree steps out to 1.5 degrees.
  constexpr int kDirections = 1200;
  const double golden = kPi * (3 - std::sqrt(5.0));
  for (int k = 0; k < kDirections; ++k) {
    const double z = 1 - (k + 0.5) / kDirections, r = std::sqrt(1 - z * z);
    consider(Vec3d(r * std::cos(golden * k), r * std::sin(golden * k), z));
  }
  for (const double step : {1.0, 0.25}) {
    const Vec3d centre = best;
    Vec3d e1, e2;
    basis(3, centre, &e1, &e2);
    for (int i = 1; i <= (step == 1.0 ? 8 : 6); ++i)
      for (int j = 0; j < 6 * i; ++j) {
        const double tilt = i * step * kPi / 180, phi = 2 * kPi * j / (6 * i);
        consider((std::cos(tilt) * centre +
                  std::sin(tilt) * (std::cos(phi) * e1 + std::sin(phi) * e2))
                     .normalized());
      }
  }
  return best;
}

double band_width(int dim, const std::vector<Vec3d>& points, const Vec3d& normal,
                  double spacing) {
  if (points.empty()) return 0;
  Vec3d e1, e2;
  basis(dim, normal, &e1, &e2);
  // Tube coordinates: 2D uses e1 only (e2 = z is 0 for every point).
  CellIndex index(spacing, points.size());
  for (size_t i = 0; i < points.size(); ++i)
    index.add(points[i].dot(e1), dim == 3 ? points[i].dot(e2) : 0.0, i);
  const double tube_area = dim == 2 ? 2 * spacing : kPi * spacing * spacing;
  const double volume = std::pow(spacing, dim);
  std::vector<double> widths(points.size()), along;
  for (size_t i = 0; i < points.size(); ++i) {
    const double a = points[i].dot(e1), b = dim == 3 ? points[i].dot(e2) : 0.0;
    along.clear();
    index.near(a, b, [&](size_t j) {
      const double da = points[j].dot(e1) - a, db = dim == 3 ? points[j].dot(e2) - b : 0.0;
      if (da * da + db * db < spacing * spacing) along.push_back(points[j].dot(normal));
    });
    std::sort(along.begin(), along.end());
    const double s = points[i].dot(normal);
    size_t lo = size_t(std::lower_bound(along.begin(), along.end(), s) - along.begin());
    size_t hi = lo;
    while (lo > 0 && along[lo] - along[lo - 1] <= 2 * spacing) --lo;
    while (hi + 1 < along.size() && along[hi + 1] - along[hi] <= 2 * spacing) ++hi;
    widths[i] = double(hi - lo + 1) * volume / tube_area;
  }
  std::nth_element(widths.begin(), widths.begin() + long(widths.size() / 2), widths.end());
  return widths[widths.size() / 2];
}

double mean_nearest_distance(const std::vector<Vec3d>& a, const std::vector<Vec3d>& b) {
  if (a.empty() && b.empty()) return 0;
  if (a.empty() || b.empty()) return std::numeric_limits<double>::infinity();
  // Brute force over a bucketed copy would need a cell size; the sets in tests are small
  // (thousands), so search the sorted x-coordinates outwards.
  auto one_way = [](const std::vector<Vec3d>& from, const std::vector<Vec3d>& to) {
    std::vector<size_t> order(to.size());
    for (size_t i = 0; i < to.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t i, size_t j) { return to[i][0] < to[j][0]; });
    std::vector<double> xs(to.size());
    for (size_t i = 0; i < to.size(); ++i) xs[i] = to[order[i]][0];
    double sum = 0;
    for (const Vec3d& p : from) {
      const size_t start = size_t(std::lower_bound(xs.begin(), xs.end(), p[0]) - xs.begin());
      double best = std::numeric_limits<double>::infinity();
      for (size_t k = start; k < xs.size() && xs[k] - p[0] < best; ++k)
        best = std::min(best, (to[order[k]] - p).norm());
      for (size_t k = start; k-- > 0 && p[0] - xs[k] < best;)
        best = std::min(best, (to[order[k]] - p).norm());
      sum += best;
    }
    return sum;
  };
  return (one_way(a, b) + one_way(b, a)) / double(a.size() + b.size());
}

CrackFigures measure_cracks(int dim, const std::vector<Vec3d>& rest,
                            const std::vector<double>& damage, double spacing,
                            double threshold) {
  CrackFigures f;
  std::vector<Vec3d> cracked;
  std::vector<char> flags(rest.size(), 0);
  for (size_t i = 0; i < rest.size(); ++i)
    if (damage[i] > threshold) cracked.push_back(rest[i]), flags[i] = 1;
  f.cracked = cracked.size();
  f.fraction = rest.empty() ? 0 : double(cracked.size()) / double(rest.size());
  if (cracked.size() < 3) return f;
  f.normal = crack_normal(dim, rest, flags, spacing);
  if (dim == 2) {
    // The line direction t = (n_y, -n_x), folded into (-90, 90].
    double a = std::atan2(-f.normal[0], f.normal[1]) * 180 / kPi;
    while (a <= -90) a += 180;
    while (a > 90) a -= 180;
    f.angle_degrees = a;
  }
  f.width = band_width(dim, cracked, f.normal, spacing);
  f.width_spacings = f.width / spacing;
  return f;
}

}  // namespace tear
