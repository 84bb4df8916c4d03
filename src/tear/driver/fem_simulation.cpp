// The FEM simulation behind the driver (docs/fem.md): each "simulation": "fem" object meshed by
// netgen (fem/mesh.h), its elements given their materials and fibers, stepped by fem/; frames of
// the nodes and of the bodies' surfaces, checkpoints of the nodes from the field registry.
#include "tear/driver/simulation.h"
#include "tear/exec/phase_timer.h"
#include "tear/fem/fem.h"
#include "tear/io/field_io.h"
#include "tear/scene/sampling.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

namespace tear {

namespace {

// Checkpoint format: this magic (its digit is the format's version), the header below, the
// nodes' state fields (io/field_io.h), a byte saying whether the elements' plastic state
// follows (every element's rest_inverse and plastic strain and volume, when a material is
// plastic), a 64-bit checksum of everything before it.
const std::string kFemCheckpointMagic = "TEARFEM2";

uint64_t mix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

template <int Dim>
class FemSimulation final : public Simulation {
 public:
  explicit FemSimulation(const Scene& scene)
      : settings_(mpm_settings(scene)),
        frame_dt_(scene.frame_dt),
        start_(std::chrono::steady_clock::now()) {
    for (const MaterialSpec& m : scene.materials) material_names_.push_back(m.name);
    for (size_t k = 0; k < scene.objects.size(); ++k) {
      const ObjectSpec& o = scene.objects[k];
      const std::string name = scene.file + ": objects[" + std::to_string(k) + "]";
      FemMesh mesh;
      if (o.fem_mesh) {
        mesh = *o.fem_mesh;  // a volume mesh file's, checked by the scene
      } else {
        try {
          mesh = mesh_shape(o.shape, Dim, o.mesh_size);
        } catch (const std::exception& e) {
          throw std::runtime_error(name + ": meshing the shape at mesh_size " +
                                   std::to_string(o.mesh_size) + ": " + e.what());
        }
        check_fem_mesh(mesh, name + " (its mesh)");
      }
      const uint64_t key = mix(scene.seed ^ mix(k + 1));
      const auto setup = [&](const Vec3d& c, size_t e) {
        ElementSetup<Dim> made;
        made.material = uint16_t(o.material);
        const FiberSpec* fibers = &o.fibers;
        for (const RegionSpec& region : o.regions)
          if (region.shape.inside(c)) {
            made.material = uint16_t(region.material), fibers = &region.fibers;
            break;
          }
        made.fiber = fiber_frame_at<Dim>(*fibers, c, mix(key ^ mix(e)));
        const MaterialSpec& m = scene.materials[made.material];
        made.mass_damping = Real(m.rayleigh_alpha);
        made.stiffness_damping = Real(m.rayleigh_beta);
        made.consistent_mass = o.consistent_mass;
        return made;
      };
      append_fem_body<Dim>(mesh, settings_.materials, setup, o.velocity, o.angular_velocity,
                           o.shape.world_center(), &state_);
      start_nodes(o, key, state_.bodies.back());
    }
    const long bad = find_fem_fault(settings_, state_);
    if (bad >= 0)
      throw std::runtime_error(describe(size_t(bad), true) +
                               ": FEM bodies must lie inside grid.domain_min/max");
    refuse_undefined_starts(scene);
  }

  int dim() const override { return Dim; }
  size_t num_particles() const override { return state_.num_nodes(); }
  int frame() const override { return frame_; }
  double time() const override { return state_.time; }
  long total_steps() const override { return state_.steps; }
  double estimate_dt() const override { return dt_limits().dt(); }
  DtLimits dt_limits() const override { return fem_dt_limits(settings_, state_); }

  double step(double dt_cap) override {
    const double dt = std::min(dt_cap, estimate_dt());
    {
      PhaseTimer timer(&step_seconds_);
      fem_step(settings_, &state_, dt, &solve_);
    }
    step_figures_.add(dt);
    const long bad = find_fem_fault(settings_, state_);
    if (bad >= 0) {
      const Particles<Dim>& p = state_.nodes;
      const bool left = p.x[size_t(bad)].allFinite() && p.v[size_t(bad)].allFinite();
      char step[96];
      std::snprintf(step, sizeof(step), "frame %d, step %ld (dt %.3g s): ", frame_ + 1,
                    state_.steps, dt);
      throw UnstableRun(
          (left ? "the run stopped in " : "the simulation became unstable in ") +
          std::string(step) + describe(size_t(bad)) +
          (left ? "; enlarge grid.domain_min/domain_max, or keep it in with grid.walls or a "
                  "collider"
                : "; lower time.cfl or time.max_dt, or check the material's parameters"));
    }
    return dt;
  }

  bool advance_frame(const std::atomic<bool>* stop) override {
    if (!advance_to(*this, double(frame_ + 1) * frame_dt_, stop, &state_.time)) return false;
    ++frame_;
    return true;
  }

  FrameStats collect_stats() override {
    const FemFigures f = measure_fem(settings_, state_);
    FrameStats s;
    s.frame = frame_;
    s.time = state_.time;
    step_figures_.take(&s);
    s.particles = state_.num_nodes();
    s.mass = f.mass;
    s.momentum = f.momentum;
    s.angular_momentum = f.angular_momentum;
    s.kinetic_energy = f.kinetic_energy;
    s.elastic_energy = f.elastic_energy;
    s.implicit_figures = settings_.integrator == Integrator::Implicit;
    s.newton_iterations = solve_.newton_iterations;
    s.newton_iterations_max = solve_.newton_iterations_max;
    s.cg_iterations = solve_.cg_iterations;
    s.newton_residual = solve_.residual_max;
    s.newton_unconverged = solve_.unconverged;
    solve_ = FemSolveStats();
    s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    return s;
  }

  PointRows frame_rows() const override {
    rows_.resize(state_.num_nodes());
    for (size_t k = 0; k < rows_.size(); ++k) rows_[k] = uint32_t(k);  // never reordered
    return tear::frame_rows(state_.nodes, rows_);
  }

  const PointTable& frame_table() const override {
    fill_table(frame_rows(), &table_);
    return table_;
  }

  // The element figures as columns: id, material, energy (density), von_mises, J, fx fy fz, and
  // plastic_strain where a material is plastic.
  void add_element_columns(PointTable* t) const {
    const FemElements<Dim>& el = state_.elements;
    const FemElementFigures f = fem_element_figures(settings_, state_);
    std::vector<double> id(el.size()), material(el.size()), fiber[3];
    for (auto& c : fiber) c.resize(el.size());
    for (size_t e = 0; e < el.size(); ++e) {
      id[e] = double(e), material[e] = double(el.material[e]);
      for (int d = 0; d < 3; ++d) fiber[d][e] = f.fiber[e][d];
    }
    t->count = el.size();
    t->add("id", ColumnType::Int32, id);
    t->add("material", ColumnType::UInt8, material);
    t->add("energy", ColumnType::Float32, f.energy);
    t->add("von_mises", ColumnType::Float32, f.von_mises);
    t->add("J", ColumnType::Float32, f.J);
    t->add("fx", ColumnType::Float32, fiber[0]);
    t->add("fy", ColumnType::Float32, fiber[1]);
    t->add("fz", ColumnType::Float32, fiber[2]);
    if (fem_plastic(settings_)) t->add("plastic_strain", ColumnType::Float32, f.plastic_strain);
  }

  // "fem": the bodies' boundary triangles in 3D, their element triangles in 2D (the filled body,
  // with the element columns), over all nodes (vertex k is node k); 3D also "volume": the
  // tetrahedra with the element columns (VTU).
  std::vector<MeshPart> frame_meshes() const override {
    MeshPart part;
    part.name = "fem";
    part.corners = 3;
    const PointTable all = frame_table();
    part.vertices.count = state_.num_nodes();
    for (const char* name : {"id", "x", "y", "z", "vx", "vy", "vz", "material"})
      part.vertices.add(name, all.types[index_of(all, name)], all.column(name));
    std::vector<double> id, material;
    if (Dim == 3) {
      for (size_t b = 0; b < state_.bodies.size(); ++b)
        for (size_t f = state_.bodies[b].face_begin; f < state_.bodies[b].face_end; ++f) {
          const std::array<int, 3>& t = state_.faces[f];
          part.elements.push_back({uint32_t(t[0]), uint32_t(t[1]), uint32_t(t[2]), 0});
          id.push_back(double(f));
          material.push_back(double(state_.nodes.material[size_t(t[0])]));
        }
    } else {
      const FemElements<Dim>& el = state_.elements;
      for (size_t e = 0; e < el.size(); ++e)
        part.elements.push_back({el.corners[e][0], el.corners[e][1], el.corners[e][2], 0});
      add_element_columns(&part.element_columns);
      return {part};
    }
    part.element_columns.count = part.elements.size();
    part.element_columns.add("id", ColumnType::Int32, id);
    part.element_columns.add("material", ColumnType::UInt8, material);
    MeshPart volume;
    volume.name = "volume";
    volume.corners = 4;
    volume.vertices = part.vertices;
    const FemElements<Dim>& el = state_.elements;
    for (size_t e = 0; e < el.size(); ++e) {
      std::array<uint32_t, 4> c{};
      for (int a = 0; a <= Dim; ++a) c[size_t(a)] = el.corners[e][size_t(a)];
      volume.elements.push_back(c);
    }
    add_element_columns(&volume.element_columns);
    return {part, volume};
  }

  std::vector<MeshFigures> body_meshes() const override {
    std::vector<MeshFigures> out;
    for (const FemBody& b : state_.bodies) out.push_back(b.figures);
    return out;
  }

  std::vector<std::pair<std::string, double>> phase_seconds() const override {
    return {{"fem step", step_seconds_}};
  }

  size_t memory_bytes() const override { return fem_memory_bytes(state_); }

  ByteWriter checkpoint() const override { return encode(true); }
  size_t checkpoint_bytes_max() const override { return encode(false).size(); }

  void decode_checkpoint(const std::string& bytes) override {
    ByteReader r = open_checkpoint(bytes, kFemCheckpointMagic,
                                   std::string(1, kFemCheckpointMagic.back()), Dim,
                                   "a checkpoint of an MPM run (this scene is FEM)");
    const uint64_t nodes = r.get<uint64_t>(), elements = r.get<uint64_t>();
    if (nodes != state_.num_nodes() || elements != state_.elements.size())
      throw std::runtime_error("checkpoint has " + std::to_string(nodes) + " nodes and " +
                               std::to_string(elements) + " elements, the scene's meshes " +
                               std::to_string(state_.num_nodes()) + " and " +
                               std::to_string(state_.elements.size()));
    const double time = r.get<double>();
    const long steps = long(r.get<int64_t>());
    const int frame = r.get<int32_t>();
    StepFigures step_figures;
    step_figures.read(&r);
    FemSolveStats is;
    is.solves = long(r.get<int64_t>());
    is.newton_iterations = long(r.get<int64_t>());
    is.newton_iterations_max = r.get<int32_t>();
    is.cg_iterations = long(r.get<int64_t>());
    is.residual_max = r.get<double>();
    is.unconverged = long(r.get<int64_t>());
    Particles<Dim> store(GroupKind::MeshVertices);
    store.enable_like(state_.nodes);
    get_fields(&r, size_t(nodes), &store);
    const bool plastic = r.get<uint8_t>() != 0;
    if (plastic != fem_plastic(settings_))
      throw std::runtime_error(plastic ? "checkpoint holds plastic elements; the scene's materials "
                                         "are elastic"
                                       : "checkpoint holds no plastic state; the scene has a "
                                         "plastic material");
    std::vector<Mat<Dim>> rest;
    std::vector<PlasticState> flow;
    if (plastic) {
      rest.resize(size_t(elements));
      flow.resize(size_t(elements));
      for (size_t e = 0; e < rest.size(); ++e) {
        for (int k = 0; k < Dim * Dim; ++k) rest[e].data()[k] = r.get<Real>();
        flow[e].strain = r.get<Real>();
        flow[e].volume = r.get<Real>();
        if (!rest[e].allFinite() || !std::isfinite(flow[e].strain) ||
            !std::isfinite(flow[e].volume))
          throw std::runtime_error("corrupt checkpoint (element " + std::to_string(e) +
                                   "'s plastic state is not finite)");
      }
    }
    if (!r.at_end()) throw std::runtime_error("corrupt checkpoint (trailing bytes)");
    for (size_t i = 0; i < store.size(); ++i)
      if (store.id[i] != i)
        throw std::runtime_error("corrupt checkpoint (node " + std::to_string(i) + " has id " +
                                 std::to_string(store.id[i]) + ")");
    std::swap(state_.nodes, store);
    if (const long bad = find_fem_fault(settings_, state_); bad >= 0) {
      const std::string why = "corrupt checkpoint (" + describe(size_t(bad), true) + ")";
      std::swap(state_.nodes, store);
      throw std::runtime_error(why);
    }
    if (plastic) {
      state_.elements.rest_inverse = std::move(rest);
      state_.elements.plastic = std::move(flow);
    }
    state_.time = time;
    state_.steps = steps;
    frame_ = frame;
    step_figures_ = step_figures;
    solve_ = is;
  }

 private:
  // neo_hookean and stvk_hencky take log J (log of the singular values): undefined where an
  // element is inverted or flat. A start with such an element in such a material is refused (a
  // run would end in NaN); qr_aniso and fixed_corotated are defined for every F (docs/fem.md).
  void refuse_undefined_starts(const Scene& scene) const {
    const FemElements<Dim>& el = state_.elements;
    for (size_t b = 0; b < state_.bodies.size(); ++b)
      for (size_t e = state_.bodies[b].element_begin; e < state_.bodies[b].element_end; ++e) {
        const Model m = settings_.materials[el.material[e]].model;
        if (m != Model::NeoHookean && m != Model::StvkHencky) continue;
        if (fem_deformation(state_, state_.nodes.x, e).determinant() > 0) continue;
        throw std::runtime_error(
            scene.file + ": objects[" + std::to_string(b) + "]: element " +
            std::to_string(e - state_.bodies[b].element_begin) +
            " starts inverted or flat (initial_nodes \"" +
            scene.resolved.at("objects").at(b).value("initial_nodes", "rest") + "\"), where " +
            model_name(m) + " is undefined: use qr_aniso or fixed_corotated");
      }
  }

  // AnisoMPM Fig. 19's starts: the body's nodes scattered at random over its bounding box, or
  // all within a thousandth of mesh_size of the shape's centre (its rest shape stays the
  // mesh's). Not exactly at the centre: F = 0 in every element is a stationary point of every
  // model (docs/fem.md, "Inverted starts"), which no integrator leaves.
  void start_nodes(const ObjectSpec& o, uint64_t key, const FemBody& body) {
    if (o.node_start == ObjectSpec::NodeStart::Rest) return;
    Particles<Dim>& p = state_.nodes;
    Vec<Dim> lo = p.x[body.node_begin], hi = lo;
    for (size_t i = body.node_begin; i < body.node_end; ++i)
      lo = lo.cwiseMin(p.x[i]), hi = hi.cwiseMax(p.x[i]);
    if (o.node_start == ObjectSpec::NodeStart::Point) {
      const Vec<Dim> centre = o.shape.world_center().head<Dim>().template cast<Real>();
      const Vec<Dim> half = Vec<Dim>::Constant(Real(0.5e-3 * o.mesh_size));
      lo = centre - half, hi = centre + half;
    }
    for (size_t i = body.node_begin; i < body.node_end; ++i)
      for (int d = 0; d < Dim; ++d) {
        const double u = double(mix(key ^ mix(i * Dim + size_t(d) + 0x51A7)) >> 11) * 0x1.0p-53;
        p.x[i][d] = lo[d] + Real(u) * (hi[d] - lo[d]);
      }
  }

  ByteWriter encode(bool compact) const {
    ByteWriter w;
    w.put_bytes(kFemCheckpointMagic);
    w.put<int32_t>(Dim);
    w.put<int32_t>(sizeof(Real));
    w.put<uint64_t>(state_.num_nodes());
    w.put<uint64_t>(state_.elements.size());
    w.put<double>(state_.time);
    w.put<int64_t>(state_.steps);
    w.put<int32_t>(frame_);
    step_figures_.write(&w);
    w.put<int64_t>(solve_.solves);
    w.put<int64_t>(solve_.newton_iterations);
    w.put<int32_t>(solve_.newton_iterations_max);
    w.put<int64_t>(solve_.cg_iterations);
    w.put<double>(solve_.residual_max);
    w.put<int64_t>(solve_.unconverged);
    put_fields(state_.nodes, &w, compact);
    const bool plastic = fem_plastic(settings_);
    w.put<uint8_t>(plastic ? 1 : 0);
    if (plastic)
      for (size_t e = 0; e < state_.elements.size(); ++e) {
        const Mat<Dim>& B = state_.elements.rest_inverse[e];
        for (int k = 0; k < Dim * Dim; ++k) w.put<Real>(B.data()[k]);
        w.put<Real>(state_.elements.plastic[e].strain);
        w.put<Real>(state_.elements.plastic[e].volume);
      }
    put_checksum(&w);
    return w;
  }

  static size_t index_of(const PointTable& t, const std::string& name) {
    return size_t(std::find(t.names.begin(), t.names.end(), name) - t.names.begin());
  }

  // "node 12 (material jelly) left the domain at x (..), v (..)" and the like.
  std::string describe(size_t i, bool start = false) const {
    const Particles<Dim>& p = state_.nodes;
    Vec3d x = Vec3d::Zero(), v = Vec3d::Zero();
    x.head<Dim>() = p.x[i].template cast<double>();
    v.head<Dim>() = p.v[i].template cast<double>();
    const bool finite = x.allFinite() && v.allFinite();
    char where[256];
    std::snprintf(where, sizeof(where), "x (%.6g, %.6g, %.6g), v (%.6g, %.6g, %.6g)", x[0], x[1],
                  x[2], v[0], v[1], v[2]);
    const uint16_t m = p.material[i];
    return "node " + std::to_string(i) + " (material " +
           (m < material_names_.size() ? material_names_[m] : "?") + ") " +
           (finite ? (start ? "starts outside the domain at " : "left the domain at ")
                   : (start ? "is not finite: " : "is no longer finite: ")) +
           where;
  }

  MpmSettings settings_;
  std::vector<std::string> material_names_;
  double frame_dt_;
  FemState<Dim> state_;
  FemSolveStats solve_;
  double step_seconds_ = 0;
  std::chrono::steady_clock::time_point start_;
  mutable std::vector<uint32_t> rows_;
  mutable PointTable table_;
  int frame_ = 0;
  StepFigures step_figures_;
};

}  // namespace

std::unique_ptr<Simulation> make_fem_simulation(const Scene& scene) {
  if (scene.dim == 2) return std::make_unique<FemSimulation<2>>(scene);
  return std::make_unique<FemSimulation<3>>(scene);
}

}  // namespace tear
