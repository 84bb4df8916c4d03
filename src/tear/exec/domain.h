// exec/: the Domain seam, the steps a multi-process (MPI) run adds to an MPM step. Each rank
// owns a region of the grid and the particles in it; the Domain sums and copies the grid nodes
// that ranks share (halos), hands particles to the rank whose region they enter, and reduces
// figures over all ranks. One process: LocalDomain, where every call does nothing (the data it
// is given is already whole). Where the step calls each: docs/architecture.md "Domain".
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tear {

// A grid node field as plain storage: `count` nodes of `components` doubles or floats each
// (`bytes_per_component` 8 or 4). Halo exchange moves whole nodes.
struct NodeFieldView {
  void* data = nullptr;
  size_t count = 0;
  int components = 1;
  int bytes_per_component = 8;
};

inline NodeFieldView node_field(double* data, size_t count, int components) {
  return {data, count, components, 8};
}
inline NodeFieldView node_field(float* data, size_t count, int components) {
  return {data, count, components, 4};
}

// Particles seen as records of bytes, so the Domain can move them without knowing their
// fields (particles/ implements it from the field registry).
class ParticleRecords {
 public:
  virtual ~ParticleRecords() = default;
  virtual size_t size() const = 0;
  // Position of particle i (z = 0 in 2D): which rank owns it.
  virtual void position(size_t i, double out[3]) const = 0;
  // The records of particles `which` (ascending), appended to `out`.
  virtual void pack(const std::vector<uint32_t>& which, std::string* out) const = 0;
  // Remove particles `which` (ascending), keeping the others in order.
  virtual void erase(const std::vector<uint32_t>& which) = 0;
  // Append the particles of records made by pack().
  virtual void append(const std::string& records) = 0;
};

class Domain {
 public:
  virtual ~Domain() = default;
  virtual int rank() const = 0;
  virtual int ranks() const = 0;
  // After a scatter to the grid (P2G of momentum and mass, the damage transfer): add into
  // every node this rank owns what other ranks scattered into their ghost copies of it.
  virtual void sum_halos(const std::vector<NodeFieldView>& fields) = 0;
  // Before a gather from the grid (G2P, the damage Laplacian): copy every owned node's value
  // into the other ranks' ghost copies.
  virtual void copy_halos(const std::vector<NodeFieldView>& fields) = 0;
  // After a scatter that keeps, per node, the largest of a key with the values that came with
  // it (crack fields: the steepest damage gradient and its direction): every node this rank
  // owns takes, among its own copy and the other ranks' ghost copies of it, the one with the
  // largest `key` (a tie goes to the lowest rank: deterministic) and that copy's `carried`
  // values, and the element-wise largest of each `maxed` field over all copies.
  virtual void max_halos(NodeFieldView key, const std::vector<NodeFieldView>& carried,
                         const std::vector<NodeFieldView>& maxed) = 0;
  // After G2P: send the particles that left this rank's region to their owners, receive the
  // ones that entered it.
  virtual void migrate(ParticleRecords* particles) = 0;
  // Reductions over all ranks (the time step, statistics, dot products of solvers). `values`:
  // `n` numbers reduced element by element, in a fixed rank order (deterministic).
  virtual void sum(double* values, size_t n) const = 0;
  virtual double min(double x) const = 0;
  virtual double max(double x) const = 0;
  double sum(double x) const {
    sum(&x, 1);
    return x;
  }
};

// One process owns everything: no halos, no migration, reductions are the values themselves.
class LocalDomain final : public Domain {
 public:
  int rank() const override { return 0; }
  int ranks() const override { return 1; }
  void sum_halos(const std::vector<NodeFieldView>&) override {}
  void copy_halos(const std::vector<NodeFieldView>&) override {}
  void max_halos(NodeFieldView, const std::vector<NodeFieldView>&,
                 const std::vector<NodeFieldView>&) override {}
  void migrate(ParticleRecords*) override {}
  void sum(double*, size_t) const override {}
  double min(double x) const override { return x; }
  double max(double x) const override { return x; }
  using Domain::sum;
};

}  // namespace tear
