// A plain MLS-MPM loop (Hu et al. 2018, as in the 88-line mls-mpm88, in 3D and double): dense
// grid, particles as an array of structs, scalar inner loops, OpenMP with each thread scattering
// into its own copy of the grid (summed after), neo-Hookean, separating walls, a binary PLY frame
// every 20 steps with the columns tear writes. The reference that `tear run` of
// bench/scenes/neo_block_3d.json is timed against (docs/cli.md "tear bench"); not part of tear.
//   plain_mls_mpm [steps=200] [out_dir=/tmp/plain_mls_mpm]
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

constexpr int kN = 64;  // cells per axis over [0, 1]^3
constexpr double kDx = 1.0 / kN, kInvDx = kN;
constexpr int kNodes = kN + 1;
constexpr double kDt = 1e-3, kE = 1e4, kNu = 0.3, kRho = 1000;
constexpr double kMu = kE / (2 * (1 + kNu)), kLambda = kE * kNu / ((1 + kNu) * (1 - 2 * kNu));
constexpr int kBound = 3;  // wall nodes

struct Particle {
  double x[3], v[3], C[9], F[9];
};

// Quadratic B-spline weights of one particle: base node and w[node][axis].
void weights(const double x[3], int base[3], double fx[3], double w[3][3]) {
  for (int d = 0; d < 3; ++d) {
    const double xg = x[d] * kInvDx;
    base[d] = int(xg - 0.5);
    fx[d] = xg - base[d];
    w[0][d] = 0.5 * (1.5 - fx[d]) * (1.5 - fx[d]);
    w[1][d] = 0.75 - (fx[d] - 1) * (fx[d] - 1);
    w[2][d] = 0.5 * (fx[d] - 0.5) * (fx[d] - 0.5);
  }
}

size_t node(int i, int j, int k) { return (size_t(k) * kNodes + j) * kNodes + i; }

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
    for (int d = 0; d < 3; ++d)
      f[d] = float(p[size_t(i)].x[d]), f[3 + d] = float(p[size_t(i)].v[d]);
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
  if (std::system(("mkdir -p " + dir).c_str()) != 0) return 1;
  const auto t0 = std::chrono::steady_clock::now();
  // The block of bench/scenes/neo_block_3d.json: 39^3 cells at 8 lattice particles per cell.
  std::vector<Particle> p;
  const double lo = 0.1953125, h = kDx / 2;
  const int per_axis = 78;
  p.reserve(size_t(per_axis) * per_axis * per_axis);
  for (int k = 0; k < per_axis; ++k)
    for (int j = 0; j < per_axis; ++j)
      for (int i = 0; i < per_axis; ++i) {
        Particle q{};
        q.x[0] = lo + (i + 0.5) * h, q.x[1] = lo + (j + 0.5) * h, q.x[2] = lo + (k + 0.5) * h;
        q.F[0] = q.F[4] = q.F[8] = 1;
        p.push_back(q);
      }
  const double vol = h * h * h, mass = kRho * vol;
  const size_t nodes = size_t(kNodes) * kNodes * kNodes;
  // Per thread: mass and momentum of every node, interleaved; then the sum: mass, velocity.
  std::vector<std::vector<double>> local(size_t(omp_get_max_threads()),
                                         std::vector<double>(nodes * 4));
  std::vector<double> grid(nodes * 4);
  write_ply(dir + "/00000.ply", p);
  for (int step = 1; step <= steps; ++step) {
#pragma omp parallel
    {
      double* g = local[size_t(omp_get_thread_num())].data();
      std::memset(g, 0, nodes * 4 * sizeof(double));
#pragma omp for
      for (long n = 0; n < long(p.size()); ++n) {
        const Particle& q = p[size_t(n)];
        int base[3];
        double fx[3], w[3][3];
        weights(q.x, base, fx, w);
        // Neo-Hookean: P F^T = mu (F F^T - I) + lambda log(J) I.
        const double* F = q.F;
        const double J = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
                         F[2] * (F[3] * F[7] - F[4] * F[6]);
        const double lj = kLambda * std::log(J), s = -kDt * vol * 4 * kInvDx * kInvDx;
        double A[9];
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            double ff = 0;
            for (int c = 0; c < 3; ++c) ff += F[a * 3 + c] * F[b * 3 + c];
            A[a * 3 + b] = s * (kMu * (ff - (a == b)) + (a == b) * lj) + mass * q.C[a * 3 + b];
          }
        const double mv[3] = {mass * q.v[0], mass * q.v[1], mass * q.v[2]};
        for (int k = 0; k < 3; ++k)
          for (int j = 0; j < 3; ++j) {
            const double wjk = w[j][1] * w[k][2], ry = (j - fx[1]) * kDx, rz = (k - fx[2]) * kDx;
            double* row = g + 4 * node(base[0], base[1] + j, base[2] + k);
            for (int i = 0; i < 3; ++i) {
              const double wt = w[i][0] * wjk, rx = (i - fx[0]) * kDx;
              double* nd = row + 4 * i;
              nd[0] += wt * mass;
              for (int a = 0; a < 3; ++a)
                nd[1 + a] += wt * (mv[a] + A[a * 3] * rx + A[a * 3 + 1] * ry + A[a * 3 + 2] * rz);
            }
          }
      }
#pragma omp for
      for (long id = 0; id < long(nodes); ++id) {
        double s4[4] = {0, 0, 0, 0};
        for (const auto& l : local)
          for (int c = 0; c < 4; ++c) s4[c] += l[size_t(id) * 4 + c];
        double* gn = &grid[size_t(id) * 4];
        gn[0] = s4[0];
        if (s4[0] <= 0) {
          gn[1] = gn[2] = gn[3] = 0;
          continue;
        }
        for (int c = 0; c < 3; ++c) gn[1 + c] = s4[1 + c] / s4[0];
        gn[2] -= kDt * 9.8;
        const int cc[3] = {int(id % kNodes), int(id / kNodes % kNodes), int(id / kNodes / kNodes)};
        for (int d = 0; d < 3; ++d) {
          if (cc[d] < kBound && gn[1 + d] < 0) gn[1 + d] = 0;
          if (cc[d] > kN - kBound && gn[1 + d] > 0) gn[1 + d] = 0;
        }
      }
#pragma omp for
      for (long n = 0; n < long(p.size()); ++n) {
        Particle& q = p[size_t(n)];
        int base[3];
        double fx[3], w[3][3];
        weights(q.x, base, fx, w);
        double v[3] = {0, 0, 0}, B[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        for (int k = 0; k < 3; ++k)
          for (int j = 0; j < 3; ++j) {
            const double wjk = w[j][1] * w[k][2], ry = j - fx[1], rz = k - fx[2];
            const double* row = grid.data() + 4 * node(base[0], base[1] + j, base[2] + k);
            for (int i = 0; i < 3; ++i) {
              const double wt = w[i][0] * wjk, rx = i - fx[0];
              const double* nd = row + 4 * i;
              for (int a = 0; a < 3; ++a) {
                const double wv = wt * nd[1 + a];
                v[a] += wv;
                B[a * 3] += wv * rx, B[a * 3 + 1] += wv * ry, B[a * 3 + 2] += wv * rz;
              }
            }
          }
        double Fn[9];
        for (int a = 0; a < 9; ++a) q.C[a] = 4 * kInvDx * B[a];
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            double f = q.F[a * 3 + b];
            for (int c = 0; c < 3; ++c) f += kDt * q.C[a * 3 + c] * q.F[c * 3 + b];
            Fn[a * 3 + b] = f;
          }
        std::memcpy(q.F, Fn, sizeof(Fn));
        for (int a = 0; a < 3; ++a) q.v[a] = v[a], q.x[a] += kDt * v[a];
      }
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
