// Loading, defaults, the resolved document, and --set overrides.
#include "scene_test_util.h"

#include <algorithm>
#include <vector>

namespace tear {
namespace {

using nlohmann::json;

// A 3D scene touching every section, with defaults left out where possible.
json rich_scene_3d() {
  return json::parse(R"({
    "dim": 3, "seed": 7,
    "grid": { "dx": 0.02, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1], "walls": "slip" },
    "time": { "frame_dt": 0.02, "frames": 10, "max_dt": 5e-4 },
    "gravity": [0, -981, 0],
    "transfer": "flip", "flip_ratio": 0.9,
    "damage": { "solver": "none", "zeta": 2 },
    "materials": {
      "meat": { "model": "qr_aniso", "E": 100, "nu": 0.25, "rho": 2, "fiber_scale": [50, 5],
                "damage": { "sigma_c": 0.35, "eta": 0.1, "alpha": -1 } },
      "bone": { "model": "fixed_corotated", "E": 1e5, "nu": 0.3, "rho": 3 }
    },
    "objects": [
      { "shape": { "type": "tube", "center": [0.5, 0.5, 0.5], "axis": [0, 0, 1], "radius": 0.2,
                   "inner_radius": 0.1, "height": 0.4,
                   "transform": { "rotate": { "axis": [1, 0, 0], "angle_deg": 30 } } },
        "material": "meat", "fibers": { "type": "circumferential" },
        "angular_velocity": [0, 0, 1] },
      { "shape": { "type": "sphere", "center": [0.5, 0.8, 0.5], "radius": 0.05 },
        "material": "bone", "ppc": 27, "sampling": "grid", "velocity": [0, -1, 0] }
    ],
    "boundaries": [
      { "type": "separate", "shape": { "type": "half_space", "point": [0, 0.1, 0], "normal": [0, 1, 0] },
        "friction": 0.3 },
      { "type": "sticky", "shape": { "type": "box", "min": [0.4, 0.9, 0.4], "max": [0.6, 1, 0.6] },
        "velocity": [0, 0.1, 0], "end": 0.5 }
    ],
    "output": { "every": 2, "checkpoint_every": 0 }
  })");
}

TEST(SceneLoad, MinimalSceneGetsEveryDefault) {
  Scene s = parse_scene(test::minimal_scene_2d(), "scenes/mini.json");
  EXPECT_EQ(s.name, "mini");
  EXPECT_EQ(s.seed, 1u);
  EXPECT_EQ(s.walls, ContactType::Separate);
  EXPECT_DOUBLE_EQ(s.cfl, 0.4);
  EXPECT_DOUBLE_EQ(s.max_dt, 1e-3);
  EXPECT_EQ(s.transfer, Transfer::Apic);
  EXPECT_EQ(s.damage.solver, DamageSolver::None);
  EXPECT_DOUBLE_EQ(s.damage.l0, 0.5 * s.dx);
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].ppc, 4);
  EXPECT_FALSE(s.objects[0].grid_sampling);
  EXPECT_EQ(s.objects[0].fibers.type, FiberField::Constant);
  EXPECT_EQ(s.output_every, 1);
  EXPECT_EQ(s.checkpoint_every, 10);
  EXPECT_EQ(s.formats, std::vector<std::string>{"ply"});
  const json& r = s.resolved;
  EXPECT_EQ(r["time"]["cfl"], 0.4);
  EXPECT_EQ(r["gravity"], json({0.0, 0.0}));
  EXPECT_EQ(r["integrator"], "explicit");
  EXPECT_EQ(r["damage"]["solver"], "none");
  EXPECT_EQ(r["materials"]["jelly"]["fiber_scale"], json({0.0}));
  EXPECT_TRUE(r["materials"]["jelly"]["damage"].is_null());
  EXPECT_EQ(r["objects"][0]["shape"]["transform"]["scale"], 1.0);
  EXPECT_NEAR(r["objects"][0]["fibers"]["center"][0].get<double>(), 0.4, 1e-15);
  EXPECT_EQ(r["objects"][0]["fibers"]["center"].size(), 2u);
  EXPECT_EQ(r["boundaries"], json::array());
  EXPECT_EQ(r["output"]["formats"], json({"ply"}));
  EXPECT_TRUE(s.output_fields.empty());
  EXPECT_EQ(r["output"]["fields"], json::array());
}

TEST(SceneLoad, RichSceneIsParsed) {
  Scene s = parse_scene(rich_scene_3d(), "rich.json");
  EXPECT_EQ(s.dim, 3);
  EXPECT_EQ(s.seed, 7u);
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].name, "bone");  // materials are indexed in name order
  EXPECT_EQ(s.materials[1].name, "meat");
  EXPECT_EQ(s.objects[0].material, 1);
  EXPECT_EQ(s.objects[1].material, 0);
  EXPECT_TRUE(s.materials[1].damage.enabled);
  EXPECT_DOUBLE_EQ(s.materials[1].damage.alpha[0], -1);
  EXPECT_DOUBLE_EQ(s.materials[1].damage.alpha[1], 0);
  EXPECT_FALSE(s.materials[0].damage.enabled);
  EXPECT_EQ(s.objects[1].ppc, 27);
  EXPECT_TRUE(s.objects[1].grid_sampling);
  EXPECT_EQ(s.objects[0].shape.type, Shape::Type::Tube);
  // Fiber axis defaults to the tube's world axis: z rotated 30 degrees about x.
  EXPECT_NEAR(s.objects[0].fibers.axis.dot(Vec3d(0, -0.5, std::sqrt(3.0) / 2)), 1, 1e-12);
  EXPECT_EQ(s.boundaries[0].shape.type, Shape::Type::HalfSpace);
  EXPECT_DOUBLE_EQ(s.boundaries[0].friction, 0.3);
  EXPECT_DOUBLE_EQ(s.boundaries[1].end, 0.5);
  EXPECT_DOUBLE_EQ(s.boundaries[0].end, 1e30);
  EXPECT_EQ(s.damage.solver, DamageSolver::None);
  EXPECT_DOUBLE_EQ(s.flip_ratio, 0.9);
}

// Without damage.solver, a scene whose materials can be damaged gets the explicit solver (so a
// damage block is never silently ignored); one without damageable materials gets none.
TEST(SceneLoad, DamageSolverDefaultFollowsTheMaterials) {
  json doc = rich_scene_3d();
  doc["damage"].erase("solver");
  Scene s = parse_scene(doc, "rich.json");
  EXPECT_EQ(s.damage.solver, DamageSolver::Explicit);
  EXPECT_EQ(s.resolved["damage"]["solver"], "explicit");
  doc["materials"]["meat"].erase("damage");
  EXPECT_EQ(parse_scene(doc, "rich.json").damage.solver, DamageSolver::None);
  doc["materials"]["meat"]["damage"] = nullptr;
  EXPECT_EQ(parse_scene(doc, "rich.json").damage.solver, DamageSolver::None);
}

// qr_aniso's energy lambda: lambda_Lame + mu by default; lambda_Lame itself with "paper".
TEST(SceneLoad, LambdaConventionPaperTakesTheLameLambdaAsItIs) {
  json doc = rich_scene_3d();
  const auto meat = [](const Scene& s) {
    return std::find_if(s.materials.begin(), s.materials.end(),
                        [](const MaterialSpec& m) { return m.name == "meat"; })
        ->params;
  };
  const double mu = 100 / (2 * 1.25), lame = 100 * 0.25 / (1.25 * 0.5);
  const Scene tear_default = parse_scene(doc, "rich.json");
  EXPECT_NEAR(meat(tear_default).lambda, lame + mu, 1e-12);
  EXPECT_EQ(tear_default.resolved["materials"]["meat"]["lambda_convention"], "small_strain");
  doc["materials"]["meat"]["lambda_convention"] = "paper";
  const Scene paper = parse_scene(doc, "rich.json");
  EXPECT_NEAR(meat(paper).lambda, lame, 1e-12);
  EXPECT_NEAR(meat(paper).mu, mu, 1e-12);
  EXPECT_NEAR(meat(paper).kx, 50 * mu, 1e-12);
  EXPECT_EQ(paper.resolved["materials"]["meat"]["lambda_convention"], "paper");
  doc["materials"]["bone"]["lambda_convention"] = "paper";
  EXPECT_EQ(test::scene_error(doc), "broken.json: materials.bone.lambda_convention: \"paper\" is "
                                    "only for qr_aniso (the other models use the Lame lambda of "
                                    "E, nu either way)");
  doc["materials"]["bone"].erase("lambda_convention");
  doc["materials"]["meat"]["lambda_convention"] = "lame";
  EXPECT_NE(test::scene_error(doc).find("materials.meat.lambda_convention: unknown value \"lame\""),
            std::string::npos);
}

// output.formats accepts every point format io/ can write, in the order given.
TEST(SceneLoad, EveryPointFormatIsAccepted) {
  json doc = rich_scene_3d();
  doc["output"]["formats"] = {"vtu", "ply", "bgeo"};
  Scene s = parse_scene(doc, "rich.json");
  EXPECT_EQ(s.formats, (std::vector<std::string>{"vtu", "ply", "bgeo"}));
  EXPECT_EQ(s.resolved["output"]["formats"], json({"vtu", "ply", "bgeo"}));
}

// output.fields: the optional frame columns, in the order given.
TEST(SceneLoad, OptionalFrameColumnsAreListed) {
  json doc = rich_scene_3d();
  doc["output"]["fields"] = {"damage_laplacian", "driving_force"};
  Scene s = parse_scene(doc, "rich.json");
  EXPECT_EQ(s.output_fields, (std::vector<std::string>{"damage_laplacian", "driving_force"}));
  EXPECT_EQ(s.resolved["output"]["fields"], json({"damage_laplacian", "driving_force"}));
}

// The example of SCENE_FORMAT.md and of docs/scene_reference.md load as written, except
// SCENE_FORMAT.md's "damage.transfer", which tear no longer has (docs/materials.md "Damage
// solvers"; the scene error tests check its message).
TEST(SceneLoad, DocumentedExamplesLoad) {
  Scene a = parse_scene(json::parse(R"({
  "name": "diagonal_block_tear",
  "dim": 2,
  "seed": 1,
  "grid":   { "dx": 0.01, "domain_min": [0, 0], "domain_max": [1, 1], "walls": "separate" },
  "time":   { "frame_dt": 0.02, "frames": 100, "cfl": 0.4, "max_dt": 5e-4 },
  "gravity": [0, -981],
  "transfer": "apic",
  "integrator": "explicit",
  "damage": { "solver": "explicit", "l0": null, "zeta": 1.0 },
  "materials": {
    "fibrous": {
      "model": "qr_aniso", "E": 100, "nu": 0.25, "rho": 2,
      "fiber_scale": [50, 0],
      "damage": { "sigma_c": 0.35, "eta": 0.1, "residual": 0.001, "alpha": [-1, 0] },
      "plasticity": null,
      "inextensible": false
    }
  },
  "objects": [
    { "shape": { "type": "box", "min": [0.3, 0.3], "max": [0.7, 0.7] },
      "material": "fibrous", "ppc": 4,
      "fibers": { "type": "constant", "a1": [1, 1] },
      "velocity": [0, 0] }
  ],
  "boundaries": [
    { "type": "sticky", "shape": { "type": "box", "min": [0.25, 0.68], "max": [0.75, 0.75] },
      "velocity": [0, 0.1], "start": 0, "end": 1e30 },
    { "type": "sticky", "shape": { "type": "box", "min": [0.25, 0.25], "max": [0.75, 0.32] },
      "velocity": [0, -0.1] }
  ],
  "output": { "every": 1, "formats": ["ply"], "checkpoint_every": 10 }
})"), "scene_format.json");
  EXPECT_EQ(a.name, "diagonal_block_tear");
  EXPECT_EQ(a.damage.solver, DamageSolver::Explicit);
  EXPECT_DOUBLE_EQ(a.damage.l0, 0.005);
  EXPECT_DOUBLE_EQ(a.materials[0].damage.alpha[0], -1);
  // The crack surface is the paper's isotropic one unless asked for.
  EXPECT_FALSE(a.materials[0].damage.anisotropic_surface());
  EXPECT_EQ(a.resolved["materials"]["fibrous"]["damage"]["surface_anisotropy"], json({0.0, 0.0}));
  EXPECT_EQ(a.boundaries.size(), 2u);
  EXPECT_EQ(a.resolved["materials"]["fibrous"]["fiber_scale"], json({50.0}));  // [50, 0] in 2D
  Scene b = parse_scene(json::parse(R"({
  "dim": 2,
  "grid": { "dx": 0.01, "domain_min": [0, 0], "domain_max": [1, 1] },
  "time": { "frame_dt": 0.02, "frames": 50 },
  "gravity": [0, -981],
  "materials": {
    "meat": { "model": "qr_aniso", "E": 100, "nu": 0.25, "rho": 2, "fiber_scale": [50] }
  },
  "objects": [
    { "shape": { "type": "box", "min": [0.3, 0.3], "max": [0.7, 0.7],
                 "transform": { "rotate": 45 } },
      "material": "meat", "fibers": { "type": "constant", "a1": [1, 0] } }
  ],
  "boundaries": [
    { "type": "sticky", "shape": { "type": "half_space", "point": [0, 0.1], "normal": [0, 1] } }
  ]
})"), "docs_example.json");
  EXPECT_EQ(b.name, "docs_example");
}

TEST(SceneLoad, ResolvedSceneReloadsToItself) {
  for (const json& doc : {test::minimal_scene_2d(), rich_scene_3d()}) {
    Scene a = parse_scene(doc, "a.json");
    // Through text, as `tear run` writes DIR/scene.json.
    std::string file = test::write_temp("resolved_" + std::to_string(a.dim) + ".json",
                                        a.resolved.dump(2));
    Scene b = load_scene(file);
    EXPECT_EQ(a.resolved, b.resolved);
    EXPECT_EQ(b.resolved["name"], "a");  // the name is kept, not re-derived from the file
    Scene c = parse_scene(b.resolved, "c.json");
    EXPECT_EQ(c.resolved.dump(), b.resolved.dump());
  }
}

TEST(SceneLoad, MissingFileAndBadJsonAreSceneErrors) {
  try {
    load_scene("/nonexistent/dir/x.json");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(),
                 "/nonexistent/dir/x.json: (file): cannot open file: No such file or directory");
  }
  std::string file = test::write_temp("syntax.json", "{ \"dim\": 2,\n  \"grid\": { ] }");
  try {
    load_scene(file);
    FAIL();
  } catch (const SceneError& e) {
    std::string msg = e.what();
    EXPECT_EQ(msg.rfind(file + ": (file): invalid JSON: parse error at line 2", 0), 0u) << msg;
  }
}

TEST(SceneOverrides, SetValuesAndArrayElements) {
  std::string file = test::write_temp("over.json", test::minimal_scene_2d().dump());
  Scene s = load_scene(file, {"materials.jelly.E=5000", "grid.domain_max.1=2",
                              "objects.0.ppc=9", "transfer=flip", "time.frames=7",
                              "objects.0.shape.min=[0.1, 0.1]"});
  EXPECT_EQ(s.materials[0].params.E, Real(5000));
  EXPECT_DOUBLE_EQ(s.domain_max.y(), 2);
  EXPECT_EQ(s.objects[0].ppc, 9);
  EXPECT_EQ(s.transfer, Transfer::Flip);  // "flip" is not JSON, so taken as a string
  EXPECT_EQ(s.frames, 7);
  EXPECT_DOUBLE_EQ(s.objects[0].shape.min.x(), 0.1);
  EXPECT_EQ(s.resolved["materials"]["jelly"]["E"], 5000.0);
  // A new key under an existing object is set, then validated like any other key.
  s = load_scene(file, {"time.cfl=0.5"});
  EXPECT_DOUBLE_EQ(s.cfl, 0.5);
  // Sections the scene may leave out can be named although the file has none of them.
  ASSERT_FALSE(test::minimal_scene_2d().contains("output"));
  s = load_scene(file, {"output.every=3", "render.color=velocity", "damage.zeta=2"});
  EXPECT_EQ(s.output_every, 3);
  EXPECT_EQ(s.render.color, "velocity");
  EXPECT_DOUBLE_EQ(s.damage.zeta, 2);
  // FLIP's blend as a relaxation time: unset (null) by default, stored when given.
  EXPECT_EQ(s.flip_relaxation_time, 0);
  EXPECT_TRUE(s.resolved["flip_relaxation_time"].is_null());
  s = load_scene(file, {"transfer=flip", "flip_relaxation_time=0.01"});
  EXPECT_DOUBLE_EQ(s.flip_relaxation_time, 0.01);
  EXPECT_EQ(s.resolved["flip_relaxation_time"], 0.01);
}

// tear run --resolution K: dx and the cap on dt divided by K, l0 following dx unless the scene
// sets it, every length in scene units unchanged; K = 1 changes nothing.
TEST(SceneLoad, ResolutionRefinesTheGridAndTheTimeStepCap) {
  nlohmann::json doc = test::minimal_scene_2d();
  doc["materials"]["jelly"]["model"] = "qr_aniso";
  doc["materials"]["jelly"]["damage"] = {{"sigma_c", 10}, {"eta", 0.1}};
  const std::string file = test::write_temp("resolution.json", doc.dump());
  const Scene one = load_scene(file), same = load_scene(file, {}, 1);
  EXPECT_EQ(same.resolved, one.resolved);
  const Scene two = load_scene(file, {"time.max_dt=4e-4"}, 2.5);
  EXPECT_DOUBLE_EQ(two.dx, one.dx / 2.5);
  EXPECT_DOUBLE_EQ(two.max_dt, 4e-4 / 2.5);  // after the overrides
  EXPECT_DOUBLE_EQ(two.damage.l0, one.damage.l0 / 2.5);
  EXPECT_DOUBLE_EQ(two.objects[0].shape.max.x(), one.objects[0].shape.max.x());
  EXPECT_DOUBLE_EQ(load_scene(file, {}, 2).max_dt, one.max_dt / 2);  // the default cap too
  // An l0 the scene sets is a length in scene units: kept.
  EXPECT_DOUBLE_EQ(load_scene(file, {"damage.l0=0.03"}, 3).damage.l0, 0.03);
  // Coarser.
  EXPECT_DOUBLE_EQ(load_scene(file, {}, 0.5).dx, one.dx * 2);
  try {
    load_scene(file, {}, -1);
    ADD_FAILURE() << "a negative resolution was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("(resolution): must be a positive number"),
              std::string::npos)
        << e.what();
  }
}

// `description`: a string, or lines as an array of strings; kept in the resolved scene.
TEST(SceneLoad, DescriptionIsAStringOrLines) {
  nlohmann::json doc = test::minimal_scene_2d();
  EXPECT_EQ(parse_scene(doc, "d.json").description, "");
  EXPECT_FALSE(parse_scene(doc, "d.json").resolved.contains("description"));
  doc["description"] = "one line";
  EXPECT_EQ(parse_scene(doc, "d.json").description, "one line");
  doc["description"] = {"first", "second"};
  const Scene s = parse_scene(doc, "d.json");
  EXPECT_EQ(s.description, "first\nsecond");
  EXPECT_EQ(parse_scene(s.resolved, "r.json").resolved, s.resolved);
  doc["description"] = {"first", 2};
  try {
    parse_scene(doc, "d.json");
    ADD_FAILURE() << "a number in the description was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("d.json: description[1]: must be a string"),
              std::string::npos)
        << e.what();
  }
}

std::string override_error(const std::vector<std::string>& ov) {
  std::string file = test::write_temp("over_bad.json", test::minimal_scene_2d().dump());
  try {
    load_scene(file, ov);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneOverrides, BadOverridesFailClearly) {
  EXPECT_NE(override_error({"materials.steel.E=1"})
                .find("materials.steel.E: override \"materials.steel.E=1\": \"materials.steel\" "
                      "does not exist"),
            std::string::npos);
  EXPECT_NE(
      override_error({"objects.3.ppc=1"}).find("\"objects.3\" does not exist (array of 1 entry)"),
      std::string::npos);
  EXPECT_NE(override_error({"objects.x.ppc=1"}).find("\"objects.x\" does not exist"),
            std::string::npos);
  EXPECT_NE(override_error({"flip_relaxation_time=0.01"})
                .find("flip_relaxation_time: is FLIP's blend: set \"transfer\": \"flip\" (it is "
                      "\"apic\")"),
            std::string::npos);
  EXPECT_NE(override_error({"transfer=flip", "flip_relaxation_time=0"})
                .find("flip_relaxation_time: must be > 0, got 0"),
            std::string::npos);
  // Only the optional sections are made up; any other missing object is an error.
  EXPECT_NE(override_error({"outptu.every=3"}).find("\"outptu\" does not exist"),
            std::string::npos);
  EXPECT_NE(override_error({"render.camera.fov_deg=30"}).find("\"render.camera\" does not exist"),
            std::string::npos);
  EXPECT_NE(override_error({"dim.x=1"}).find("\"dim\" is an integer (2), not an object or array"),
            std::string::npos);
  EXPECT_NE(override_error({"grid.dx"})
                .find("(override): override \"grid.dx\" must look like a.b.c=VALUE"),
            std::string::npos);
  // Values set by overrides are validated with the normal path.
  EXPECT_NE(override_error({"materials.jelly.nu=0.7"})
                .find("materials.jelly.nu: must be in (-1, 0.5), got 0.7"),
            std::string::npos);
  EXPECT_NE(override_error({"time.fps=30"}).find("time.fps: unknown key"), std::string::npos);
}

// Every shipped example loads, and its resolved scene reloads to itself (as DIR/scene.json
// of a run must).
TEST(SceneLoad, EveryExampleLoadsAndRoundTrips) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  // examples/ and its folders (examples/paper/).
  for (const auto& e :
       fs::recursive_directory_iterator(fs::path(TEAR_SOURCE_DIR) / "examples"))
    if (e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 1u);
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    Scene a;
    try {
      a = load_scene(f.string());
    } catch (const SceneError& e) {
      ADD_FAILURE() << e.what();
      continue;
    }
    EXPECT_EQ(a.file, f.string());
    EXPECT_FALSE(a.objects.empty());
    EXPECT_EQ(a.resolved["dim"], a.dim);
    Scene b = parse_scene(a.resolved, "resolved.json");
    EXPECT_EQ(b.resolved, a.resolved);
    EXPECT_EQ(b.resolved.dump(), a.resolved.dump());
    // Through text too, as `tear run` writes it.
    Scene c = load_scene(test::write_temp("example_" + f.filename().string(), a.resolved.dump(2)));
    EXPECT_EQ(c.resolved.dump(), a.resolved.dump());
  }
}

}  // namespace
}  // namespace tear
