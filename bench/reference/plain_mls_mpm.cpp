// A plain MLS-MPM loop (Hu et al. 2018, as in the 88-line mls-mpm88, in 3D and double): dense
// grid, OpenMP, each thread scattering into its own copy of the grid (summed after; atomics on
// doubles are 3-4 times slower here), neo-Hookean, separating walls, a binary PLY frame every 20
// steps with the columns tear writes. The reference that `tear run` of bench/scenes/neo_block_3d.json
// is timed against (docs/architecture.md "Speed of a whole run"); not part of tear.
//   plain_mls_mpm [steps=200] [out_dir=/tmp/plain_mls_mpm]
#include <Eigen/Dense>
#include <omp.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using Vec = Eigen::Vector3d;
using Mat = Eigen::Matrix3d;

namespace {

constexpr int kN = 64;  // cells per axis over [0, 1]^3
constexpr double kDx = 1.0 / kN, kInvDx = kN;
constexpr int kNodes = kN + 1;
constexpr double kDt = 1e-3, kE = 1e4, kNu = 0.3, kRho = 1000;
constexpr double kMu = kE / (2 * (1 + kNu)), kLambda = kE * kNu / ((1 + kNu) * (1 - 2 * kNu));
constexpr int kBound = 3;  // wall nodes

struct Particle {
  Vec x, v;
  Mat C, F;
};

void write_ply(const std::string& path, const std::vector<Particle>& p) {
  const size_t n = p.size();
  std::string out = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) +
                    "\nproperty int id\nproperty float x\nproperty float y\nproperty float z\n"
                    "property float vx\nproperty float vy\nproperty float vz\n"
                    "property float damage\nproperty uchar material\nproperty float fx\n"
                    "property float fy\nproperty float fz\nend_header\n";
  const size_t header = out.size(), row = 45;
  out.resize(header + n * row);
#pragma omp parallel for
  for (long i = 0; i < long(n); ++i) {
    char* q = &out[header + size_t(i) * row];
    const int32_t id = int32_t(i);
    std::memcpy(q, &id, 4);
    float f[6];
    for (int d = 0; d < 3; ++d) f[d] = float(p[i].x[d]), f[3 + d] = float(p[i].v[d]);
    std::memcpy(q + 4, f, 24);
    const float zero = 0, one = 1;
    std::memcpy(q + 28, &zero, 4);
    q[32] = 0;
    std::memcpy(q + 33, &one, 4);
    std::memcpy(q + 37, &zero, 4);
    std::memcpy(q + 41, &zero, 4);
  }
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file || std::fwrite(out.data(), 1, out.size(), file) != out.size()) std::exit(1);
  std::fclose(file);
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 200;
  const std::string dir = argc > 2 ? argv[2] : "/tmp/plain_mls_mpm";
  std::system(("mkdir -p " + dir).c_str());
  const auto t0 = std::chrono::steady_clock::now();
  // The block of bench/scenes/neo_block_3d.json: 39^3 cells at 8 lattice particles per cell.
  std::vector<Particle> p;
  const double lo = 0.1953125, h = kDx / 2;
  const int per_axis = 78;
  p.reserve(size_t(per_axis) * per_axis * per_axis);
  for (int k = 0; k < per_axis; ++k)
    for (int j = 0; j < per_axis; ++j)
      for (int i = 0; i < per_axis; ++i)
        p.push_back({Vec(lo + (i + 0.5) * h, lo + (j + 0.5) * h, lo + (k + 0.5) * h), Vec::Zero(),
                     Mat::Zero(), Mat::Identity()});
  const double vol = h * h * h, mass = kRho * vol;
  const size_t nodes = size_t(kNodes) * kNodes * kNodes;
  std::vector<double> grid_m(nodes);
  std::vector<Vec> grid_v(nodes);
  int threads = 1;
#pragma omp parallel
#pragma omp single
  threads = omp_get_num_threads();
  // Per thread: mass and momentum, interleaved.
  std::vector<std::vector<Eigen::Vector4d>> local{size_t(threads)};
  for (auto& g : local) g.resize(nodes);
  auto node = [](int i, int j, int k) { return (size_t(k) * kNodes + j) * kNodes + i; };
  write_ply(dir + "/00000.ply", p);
  for (int step = 1; step <= steps; ++step) {
#pragma omp parallel
    {
    std::vector<Eigen::Vector4d>& g = local[size_t(omp_get_thread_num())];
    std::fill(g.begin(), g.end(), Eigen::Vector4d::Zero());
#pragma omp for
    for (long n = 0; n < long(p.size()); ++n) {
      const Particle& q = p[size_t(n)];
      const Vec xg = q.x * kInvDx;
      const Eigen::Vector3i base = (xg.array() - 0.5).floor().cast<int>();
      const Vec fx = xg - base.cast<double>();
      std::array<Vec, 3> w = {Vec(0.5 * (1.5 - fx.array()).square()),
                              Vec(0.75 - (fx.array() - 1).square()),
                              Vec(0.5 * (fx.array() - 0.5).square())};
      // Neo-Hookean: P F^T = mu (F F^T - I) + lambda log(J) I.
      const double J = q.F.determinant();
      const Mat PFt = kMu * (q.F * q.F.transpose() - Mat::Identity()) +
                      kLambda * std::log(J) * Mat::Identity();
      const Mat affine = -kDt * vol * 4 * kInvDx * kInvDx * PFt + mass * q.C;
      const Vec mv0 = mass * q.v;
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i) {
            const Vec dpos = (Vec(i, j, k) - fx) * kDx;
            const double wt = w[i][0] * w[j][1] * w[k][2];
            const Vec mv = wt * (mv0 + affine * dpos);
            g[node(base[0] + i, base[1] + j, base[2] + k)] +=
                Eigen::Vector4d(wt * mass, mv[0], mv[1], mv[2]);
          }
    }
    }
#pragma omp parallel for
    for (long id = 0; id < long(nodes); ++id) {
      Eigen::Vector4d sum = Eigen::Vector4d::Zero();
      for (const auto& g : local) sum += g[size_t(id)];
      grid_m[size_t(id)] = sum[0];
      grid_v[size_t(id)] = sum.tail<3>();
      if (grid_m[size_t(id)] <= 0) continue;
      Vec& v = grid_v[size_t(id)];
      v /= grid_m[size_t(id)];
      v[1] -= kDt * 9.8;
      const int c[3] = {int(id % kNodes), int(id / kNodes % kNodes), int(id / kNodes / kNodes)};
      for (int d = 0; d < 3; ++d) {
        if (c[d] < kBound && v[d] < 0) v[d] = 0;
        if (c[d] > kN - kBound && v[d] > 0) v[d] = 0;
      }
    }
#pragma omp parallel for
    for (long n = 0; n < long(p.size()); ++n) {
      Particle& q = p[size_t(n)];
      const Vec xg = q.x * kInvDx;
      const Eigen::Vector3i base = (xg.array() - 0.5).floor().cast<int>();
      const Vec fx = xg - base.cast<double>();
      std::array<Vec, 3> w = {Vec(0.5 * (1.5 - fx.array()).square()),
                              Vec(0.75 - (fx.array() - 1).square()),
                              Vec(0.5 * (fx.array() - 0.5).square())};
      Vec v = Vec::Zero();
      Mat B = Mat::Zero();
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i) {
            const Vec dpos = (Vec(i, j, k) - fx);
            const double wt = w[i][0] * w[j][1] * w[k][2];
            const Vec gv = grid_v[node(base[0] + i, base[1] + j, base[2] + k)];
            v += wt * gv;
            B += 4 * kInvDx * wt * gv * dpos.transpose();
          }
      q.v = v;
      q.C = B;
      q.x += kDt * v;
      q.F = (Mat::Identity() + kDt * B) * q.F;
    }
    if (step % 20 == 0) {
      char name[32];
      std::snprintf(name, sizeof(name), "/%05d.ply", step / 20);
      write_ply(dir + name, p);
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%zu particles, %d steps in %.2f s (%.1f ms a step)\n", p.size(), steps, wall,
              1000 * wall / steps);
  return 0;
}
