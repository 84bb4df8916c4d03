// Bad input: every broken scene is rejected with "FILE: JSON.PATH: reason".
// The table goes through load_scene() (a real file, optional --set overrides), so missing
// files, JSON syntax errors and bad overrides are checked the same way as bad values.
#include "scene_test_util.h"

#include <optional>
#include <set>
#include <vector>

namespace tear {
namespace {

using nlohmann::json;

struct BrokenScene {
  std::string name;                    // test name
  std::string patch;                   // JSON merge patch (RFC 7386) on minimal_scene_2d()
  std::vector<std::string> overrides;  // `tear run --set` strings
  std::optional<std::string> raw;      // file text instead of the patched scene
  bool missing = false;                // no file at all
  std::string expected;                // substring of what() right after "FILE: "
};

BrokenScene patched(const std::string& name, const std::string& patch,
                    const std::string& expected) {
  return {name, patch, {}, std::nullopt, false, expected};
}
BrokenScene overridden(const std::string& name, std::vector<std::string> ov,
                       const std::string& expected) {
  return {name, "{}", std::move(ov), std::nullopt, false, expected};
}
BrokenScene raw_file(const std::string& name, const std::string& text,
                     const std::string& expected) {
  return {name, "{}", {}, text, false, expected};
}

// A qr_aniso material with a damage block; `damage` is the inner JSON of "damage".
std::string with_damage(const std::string& damage) {
  return R"({"materials": {"jelly": {"model": "qr_aniso", "damage": )" + damage + "}}}";
}

// A sphere object whose extra keys (", ..." JSON members) are appended.
std::string sphere_object(const std::string& extra) {
  return R"({"objects": [{"shape": {"type": "sphere", "center": [0.5, 0.5], "radius": 0.1},
                          "material": "jelly")" +
         extra + "}]}";
}

// An object with the given shape JSON.
std::string shape_object(const std::string& shape) {
  return R"({"objects": [{"material": "jelly", "shape": )" + shape + "}]}";
}

// A boundary: `extra` are ", ..." members after type and shape.
std::string boundary(const std::string& type, const std::string& extra) {
  return R"({"boundaries": [{"type": ")" + type +
         R"(", "shape": {"type": "box", "min": [0, 0], "max": [1, 0.1]})" + extra + "}]}";
}

std::vector<BrokenScene> broken_scenes() {
  std::vector<BrokenScene> t = {
      // --- the file itself
      {"MissingFile",
       "{}",
       {},
       std::nullopt,
       true,
       "(file): cannot open file: No such file or directory"},
      raw_file("JsonSyntaxError", "{ \"dim\": 2,\n  \"grid\": { ] }",
               "(file): invalid JSON: parse error at line 2, column 13: syntax error while parsing "
               "object key - unexpected ']'"),
      raw_file("JsonTrailingComma", "{\n  \"dim\": 2,\n}",
               "(file): invalid JSON: parse error at line 3, column 1"),
      raw_file("EmptyFile", "", "(file): invalid JSON: parse error at line 1, column 1"),
      raw_file("RootIsArray", "[1, 2]", "(root): must be an object, got an array"),
      // --- unknown keys (typos never pass silently)
      patched("TypoTopLevel", R"({"materails": {}})",
              "materails: unknown key, did you mean \"materials\"? (expected one of: name, description, dim,"),
      patched("TypoGravity", R"({"gravty": [0, -9.8]})",
              "gravty: unknown key, did you mean \"gravity\"?"),
      patched("TypoGridDx", R"({"grid": {"dxx": 0.1}})",
              "grid.dxx: unknown key, did you mean \"dx\"? (expected one of: dx, domain_min, "
              "domain_max, walls)"),
      patched("UnknownTimeKey", R"({"time": {"fps": 30}})",
              "time.fps: unknown key (expected one of: frame_dt, frames, cfl, max_dt)"),
      patched("UnknownMaterialKey", R"({"materials": {"jelly": {"Young": 5}}})",
              "materials.jelly.Young: unknown key (expected one of: model, E, nu, rho,"),
      patched("UnknownShapeKey",
              shape_object(R"({"type": "box", "min": [0.2, 0.2], "max": [0.6, 0.6], "radius": 1})"),
              "objects[0].shape.radius: unknown key (expected one of: type, min, max, transform)"),
      patched("TypoBoundaryFriction", boundary("slip", R"(, "frction": 0.1)"),
              "boundaries[0].frction: unknown key, did you mean \"friction\"?"),
      // --- wrong types
      patched("StringForNumber", R"({"materials": {"jelly": {"E": "stiff"}}})",
              "materials.jelly.E: must be a number, got a string"),
      patched("NumberForArray", R"({"grid": {"domain_min": 0}})",
              "grid.domain_min: must be an array of 2 numbers, got an integer (0)"),
      patched("StringForVector", R"({"gravity": "down"})",
              "gravity: must be an array of 2 numbers, got a string"),
      patched("StringInVector", R"({"grid": {"domain_min": [0, "a"]}})",
              "grid.domain_min[1]: must be a number, got a string"),
      patched("NumberForObject", R"({"grid": 5})", "grid: must be an object, got an integer (5)"),
      patched("StringForBoolean", R"({"materials": {"jelly": {"inextensible": "no"}}})",
              "materials.jelly.inextensible: must be true or false, got a string"),
      patched("MaterialsIsArray", R"({"materials": []})",
              "materials: must be an object of NAME: {...}, got an array"),
      patched("ObjectsIsObject", R"({"objects": {"shape": 1}})",
              "objects: must be an array, got an object"),
      patched("FormatsIsString", R"({"output": {"formats": "ply"}})",
              "output.formats: must be an array of strings, got a string"),
      // --- vectors of the wrong length for dim
      patched("DomainMinThreeEntriesIn2D", R"({"grid": {"domain_min": [0, 0, 0]}})",
              "grid.domain_min: must be an array of 2 numbers, got 3 entries"),
      patched("GravityThreeEntriesIn2D", R"({"gravity": [0, -9.8, 0]})",
              "gravity: must be an array of 2 numbers, got 3 entries"),
      patched("VelocityOneEntry", sphere_object(R"(, "velocity": [1])"),
              "objects[0].velocity: must be an array of 2 numbers, got 1 entry"),
      patched("FiberScaleThreeEntriesIn2D",
              R"({"materials": {"jelly": {"model": "qr_aniso", "fiber_scale": [1, 2, 3]}}})",
              "materials.jelly.fiber_scale: must be an array of 1 number in 2D, got 3 entries"),
      patched("FiberScaleSecondNonZeroIn2D",
              R"({"materials": {"jelly": {"model": "qr_aniso", "fiber_scale": [1, 2]}}})",
              "materials.jelly.fiber_scale[1]: must be 0 in 2D (only a1 has a fiber stiffness), "
              "got 2"),
      // --- dim
      patched("DimFour", R"({"dim": 4})", "dim: must be 2 or 3, got 4"),
      patched("DimOne", R"({"dim": 1})", "dim: must be 2 or 3, got 1"),
      patched("DimMissing", R"({"dim": null})", "dim: required"),
      patched("DimString", R"({"dim": "2"})", "dim: must be an integer, got a string"),
      patched("DimFraction", R"({"dim": 2.5})", "dim: must be an integer, got a number (2.5)"),
      // --- top level
      patched("EmptyName", R"({"name": ""})", "name: must not be empty"),
      patched("NegativeSeed", R"({"seed": -1})", "seed: must be >= 0, got -1"),
      patched("HugeSeed", R"({"seed": 18446744073709551615})",
              "seed: too large, got 18446744073709551615"),
      patched("UnknownTransfer", R"({"transfer": "mls"})",
              "transfer: unknown value \"mls\" (expected one of: apic, pic, flip)"),
      patched("FlipRatioAboveOne", R"({"flip_ratio": 1.5})",
              "flip_ratio: must be in [0, 1], got 1.5"),
      patched("UnknownIntegrator", R"({"integrator": "rk4"})",
              "integrator: unknown value \"rk4\" (expected one of: explicit, implicit)"),
      // --- grid
      patched("DxZero", R"({"grid": {"dx": 0}})", "grid.dx: must be > 0, got 0"),
      patched("DxNegative", R"({"grid": {"dx": -0.1}})", "grid.dx: must be > 0, got -0.1"),
      patched("DxMissing", R"({"grid": {"dx": null}})", "grid.dx: required"),
      patched("DxTooSmallForDomain", R"({"grid": {"dx": 1e-9}})",
              "grid.dx: too small for the domain: 1000000000 cells along axis 0 (at most "
              "16777216)"),
      patched("DomainMaxBelowMin", R"({"grid": {"domain_max": [1, -1]}})",
              "grid.domain_max: must be > domain_min in every entry (entry 1: -1 <= 0)"),
      patched("DomainMaxEqualsMin", R"({"grid": {"domain_max": [0, 1]}})",
              "grid.domain_max: must be > domain_min in every entry (entry 0: 0 <= 0)"),
      patched(
          "UnknownWalls", R"({"grid": {"walls": "bouncy"}})",
          "grid.walls: unknown value \"bouncy\" (expected one of: sticky, slip, separate, none)"),
      patched("GridMissing", R"({"grid": null})", "grid: required"),
      // --- time
      patched("CflAboveOne", R"({"time": {"cfl": 1.5}})", "time.cfl: must be in (0, 1], got 1.5"),
      patched("CflZero", R"({"time": {"cfl": 0}})", "time.cfl: must be in (0, 1], got 0"),
      patched("FramesZero", R"({"time": {"frames": 0}})",
              "time.frames: must be in [1, 1e8], got 0"),
      patched("FramesNegative", R"({"time": {"frames": -1}})",
              "time.frames: must be in [1, 1e8], got -1"),
      patched("FramesFraction", R"({"time": {"frames": 2.5}})",
              "time.frames: must be an integer, got a number (2.5)"),
      patched("FrameDtNegative", R"({"time": {"frame_dt": -0.01}})",
              "time.frame_dt: must be > 0, got -0.01"),
      patched("MaxDtZero", R"({"time": {"max_dt": 0}})", "time.max_dt: must be > 0, got 0"),
      patched("TimeMissing", R"({"time": null})", "time: required"),
      // --- damage solver
      patched("UnknownDamageSolver", R"({"damage": {"solver": "magic"}})",
              "damage.solver: unknown value \"magic\" (expected one of: none, explicit, implicit)"),
      patched("DamageL0Negative", R"({"damage": {"l0": -1}})", "damage.l0: must be > 0, got -1"),
      patched("DamageZetaZero", R"({"damage": {"zeta": 0}})", "damage.zeta: must be > 0, got 0"),
      patched("DamageTransferRemoved", R"({"damage": {"transfer": "flip"}})",
              "damage.transfer: no longer used: the implicit damage solver solves for the "
              "particles' damage directly, with no grid-to-particle transfer; remove the key"),
      // --- materials
      patched("NuAboveHalf", R"({"materials": {"jelly": {"nu": 0.7}}})",
              "materials.jelly.nu: must be in (-1, 0.5), got 0.7"),
      patched("NuExactlyHalf", R"({"materials": {"jelly": {"nu": 0.5}}})",
              "materials.jelly.nu: must be in (-1, 0.5), got 0.5"),
      patched("NuMinusOne", R"({"materials": {"jelly": {"nu": -1}}})",
              "materials.jelly.nu: must be in (-1, 0.5), got -1"),
      patched("NuBelowMinusOne", R"({"materials": {"jelly": {"nu": -1.5}}})",
              "materials.jelly.nu: must be in (-1, 0.5), got -1.5"),
      patched("EZero", R"({"materials": {"jelly": {"E": 0}}})",
              "materials.jelly.E: must be > 0, got 0"),
      patched("ENegative", R"({"materials": {"jelly": {"E": -5}}})",
              "materials.jelly.E: must be > 0, got -5"),
      patched("RhoNegative", R"({"materials": {"jelly": {"rho": -2}}})",
              "materials.jelly.rho: must be > 0, got -2"),
      patched("RhoZero", R"({"materials": {"jelly": {"rho": 0}}})",
              "materials.jelly.rho: must be > 0, got 0"),
      patched("UnknownModel", R"({"materials": {"jelly": {"model": "rubber"}}})",
              "materials.jelly.model: unknown model \"rubber\" (expected one of: qr_aniso, "
              "fixed_corotated, neo_hookean, stvk_hencky, surface_qr, curve_qr)"),
      patched("ModelMissing", R"({"materials": {"jelly": {"model": null}}})",
              "materials.jelly.model: required"),
      patched("FiberScaleNegative",
              R"({"materials": {"jelly": {"model": "qr_aniso", "fiber_scale": [-1]}}})",
              "materials.jelly.fiber_scale[0]: must be >= 0, got -1"),
      patched("FiberScaleOnIsotropicModel", R"({"materials": {"jelly": {"fiber_scale": [2]}}})",
              "materials.jelly.fiber_scale: must be 0 for the isotropic model \"neo_hookean\""),
      patched("DamageOnIsotropicModel",
              R"({"materials": {"jelly": {"damage": {"sigma_c": 1, "eta": 1}}}})",
              "materials.jelly.damage: not implemented yet for model \"neo_hookean\""),
      patched("DamageResidualOne", with_damage(R"({"sigma_c": 1, "eta": 1, "residual": 1})"),
              "materials.jelly.damage.residual: must be in [0, 1), got 1"),
      patched("DamageResidualNegative",
              with_damage(R"({"sigma_c": 1, "eta": 1, "residual": -0.1})"),
              "materials.jelly.damage.residual: must be in [0, 1), got -0.1"),
      patched("DamageAlphaBelowMinusOne",
              with_damage(R"({"sigma_c": 1, "eta": 1, "alpha": [-2, 0]})"),
              "materials.jelly.damage.alpha[0]: must be a number >= -1, got -2"),
      patched("DamageAlphaJustBelowMinusOne",
              with_damage(R"({"sigma_c": 1, "eta": 1, "alpha": -1.0001})"),
              "materials.jelly.damage.alpha: must be a number >= -1, got -1.0001"),
      patched("DamageAlphaThreeEntries",
              with_damage(R"({"sigma_c": 1, "eta": 1, "alpha": [0, 0, 0]})"),
              "materials.jelly.damage.alpha: must be a number or an array of 1 to 2 numbers, got "
              "3 entries"),
      patched("DamageSurfaceAnisotropyMinusOne",
              with_damage(R"({"sigma_c": 1, "eta": 1, "surface_anisotropy": -1})"),
              "materials.jelly.damage.surface_anisotropy: must be a number > -1, got -1"),
      patched("DamageSurfaceAnisotropySecondBelowMinusOne",
              with_damage(R"({"sigma_c": 1, "eta": 1, "surface_anisotropy": [4, -3]})"),
              "materials.jelly.damage.surface_anisotropy[1]: must be a number > -1, got -3"),
      patched("DamageSurfaceAnisotropyNotANumber",
              with_damage(R"({"sigma_c": 1, "eta": 1, "surface_anisotropy": "strong"})"),
              "materials.jelly.damage.surface_anisotropy: must be a number or an array of 1 to 2 "
              "numbers, got a string"),
      patched("DamageSigmaCMissing", with_damage(R"({"eta": 1})"),
              "materials.jelly.damage.sigma_c: required"),
      patched("DamageSigmaCZero", with_damage(R"({"sigma_c": 0, "eta": 1})"),
              "materials.jelly.damage.sigma_c: must be > 0, got 0"),
      patched("DamageEtaZero", with_damage(R"({"sigma_c": 1, "eta": 0})"),
              "materials.jelly.damage.eta: must be > 0, got 0"),
      patched("DamageUnknownKey", with_damage(R"({"sigma_c": 1, "eta": 1, "sigmac": 2})"),
              "materials.jelly.damage.sigmac: unknown key, did you mean \"sigma_c\"?"),
      patched("UnknownPlasticity",
              R"({"materials": {"jelly": {"plasticity": {"type": "cam_clay"}}}})",
              "materials.jelly.plasticity.type: unknown value \"cam_clay\" (expected one of: "
              "von_mises, drucker_prager)"),
      // --- objects
      patched("ObjectUnknownMaterial",
              R"({"objects": [{"shape": {"type": "sphere", "center": [0.5, 0.5], "radius": 0.1},
                               "material": "steel"}]})",
              "objects[0].material: unknown material \"steel\" (defined: jelly)"),
      patched(
          "ObjectMaterialMissing",
          R"({"objects": [{"shape": {"type": "sphere", "center": [0.5, 0.5], "radius": 0.1}}]})",
          "objects[0].material: required"),
      patched("ObjectShapeMissing", R"({"objects": [{"shape": null}]})",
              "objects[0].shape: required"),
      patched("PpcZero", sphere_object(R"(, "ppc": 0)"),
              "objects[0].ppc: must be in [1, 4096], got 0"),
      patched("PpcNegative", sphere_object(R"(, "ppc": -4)"),
              "objects[0].ppc: must be in [1, 4096], got -4"),
      patched("PpcFraction", sphere_object(R"(, "ppc": 2.5)"),
              "objects[0].ppc: must be an integer, got a number (2.5)"),
      patched("GridSamplingNeedsSquarePpc", sphere_object(R"(, "ppc": 3, "sampling": "grid")"),
              "objects[0].ppc: must be a perfect square with \"sampling\": \"grid\", got 3"),
      patched("UnknownSampling", sphere_object(R"(, "sampling": "poisson")"),
              "objects[0].sampling: unknown value \"poisson\" (expected one of: random, grid)"),
      patched("AngularVelocityArrayIn2D", sphere_object(R"(, "angular_velocity": [0, 1])"),
              "objects[0].angular_velocity: must be a number, got an array"),
      patched("ObjectOutsideDomain",
              shape_object(R"({"type": "box", "min": [1.5, 0.2], "max": [2, 0.6]})"),
              "objects[0].shape: lies outside the grid domain along axis 0 (shape spans [1.5, 2], "
              "domain [0, 1])"),
      // --- shapes
      patched("UnknownShapeType", shape_object(R"({"type": "donut"})"),
              "objects[0].shape.type: unknown value \"donut\" (expected one of: box, sphere, "
              "cylinder, tube, half_space, mesh, cone, torus, wedge, particles)"),
      patched("ShapeTypeMissing", shape_object(R"({"center": [0.5, 0.5]})"),
              "objects[0].shape.type: required"),
      patched("SphereRadiusNegative",
              shape_object(R"({"type": "sphere", "center": [0.5, 0.5], "radius": -1})"),
              "objects[0].shape.radius: must be > 0, got -1"),
      patched("SphereRadiusZero",
              shape_object(R"({"type": "sphere", "center": [0.5, 0.5], "radius": 0})"),
              "objects[0].shape.radius: must be > 0, got 0"),
      patched("TubeInnerEqualsOuter",
              shape_object(R"({"type": "tube", "center": [0.5, 0.5], "axis": [0, 1], "radius": 0.2,
                               "inner_radius": 0.2, "height": 0.5})"),
              "objects[0].shape.inner_radius: must be in [0, radius = 0.2), got 0.2"),
      patched("TubeInnerAboveOuter",
              shape_object(R"({"type": "tube", "center": [0.5, 0.5], "axis": [0, 1], "radius": 0.2,
                               "inner_radius": 0.3, "height": 0.5})"),
              "objects[0].shape.inner_radius: must be in [0, radius = 0.2), got 0.3"),
      patched("CylinderHeightZero",
              shape_object(R"({"type": "cylinder", "center": [0.5, 0.5], "axis": [0, 1],
                               "radius": 0.2, "height": 0})"),
              "objects[0].shape.height: must be > 0, got 0"),
      patched("CylinderAxisZero",
              shape_object(R"({"type": "cylinder", "center": [0.5, 0.5], "axis": [0, 0],
                               "radius": 0.2, "height": 0.5})"),
              "objects[0].shape.axis: must be non-zero"),
      patched("BoxMinAboveMax",
              shape_object(R"({"type": "box", "min": [0.5, 0.2], "max": [0.4, 0.6]})"),
              "objects[0].shape.max: must be > min in every entry (entry 0: 0.4 <= 0.5)"),
      patched("TransformScaleZero",
              shape_object(R"({"type": "box", "min": [0.2, 0.2], "max": [0.4, 0.6],
                               "transform": {"scale": 0}})"),
              "objects[0].shape.transform.scale: must be > 0, got 0"),
      patched("TransformRotateObjectIn2D",
              shape_object(R"({"type": "box", "min": [0.2, 0.2], "max": [0.4, 0.6],
                               "transform": {"rotate": {"angle_deg": 30}}})"),
              "objects[0].shape.transform.rotate: must be a number, got an object"),
      patched("HalfSpaceObject",
              shape_object(R"({"type": "half_space", "point": [0, 0], "normal": [0, 1]})"),
              "objects[0].shape.type: \"half_space\" is only allowed for boundaries"),
      // --- fibers
      patched("UnknownFiberType", sphere_object(R"(, "fibers": {"type": "spiral"})"),
              "objects[0].fibers.type: unknown value \"spiral\" (expected one of: constant, "
              "radial, circumferential, longitudinal, random, flow, from_file)"),
      patched("FiberA1Zero", sphere_object(R"(, "fibers": {"a1": [0, 0]})"),
              "objects[0].fibers.a1: must be non-zero"),
      patched("FiberA2ParallelToA1", sphere_object(R"(, "fibers": {"a1": [1, 0], "a2": [2, 0]})"),
              "objects[0].fibers.a2: must not be parallel to a1"),
      patched("FiberAxisZero",
              sphere_object(R"(, "fibers": {"type": "longitudinal", "axis": [0, 0]})"),
              "objects[0].fibers.axis: must be non-zero"),
      patched("FibersIsString", sphere_object(R"(, "fibers": "radial")"),
              "objects[0].fibers: must be an object, got a string"),
      // --- boundaries
      patched(
          "UnknownBoundaryType", boundary("glue", ""),
          "boundaries[0].type: unknown value \"glue\" (expected one of: sticky, slip, separate)"),
      patched("BoundaryTypeMissing", R"({"boundaries": [{"shape": {"type": "box"}}]})",
              "boundaries[0].type: required"),
      patched("BoundaryShapeMissing", R"({"boundaries": [{"type": "sticky"}]})",
              "boundaries[0].shape: required"),
      patched("FrictionNegative", boundary("slip", R"(, "friction": -1)"),
              "boundaries[0].friction: must be >= 0, got -1"),
      patched("StartAfterEnd", boundary("sticky", R"(, "start": 2, "end": 1)"),
              "boundaries[0].end: must be > start (2), got 1"),
      patched("StartEqualsEnd", boundary("sticky", R"(, "start": 1, "end": 1)"),
              "boundaries[0].end: must be > start (1), got 1"),
      patched("HalfSpaceNormalZero",
              R"({"boundaries": [{"type": "slip", "shape": {"type": "half_space", "point": [0, 0],
                                                             "normal": [0, 0]}}]})",
              "boundaries[0].shape.normal: must be non-zero"),
      patched("BoundaryVelocityWrongLength", boundary("sticky", R"(, "velocity": [0, 1, 0])"),
              "boundaries[0].velocity: must be an array of 2 numbers, got 3 entries"),
      // --- output
      patched("OutputEveryZero", R"({"output": {"every": 0}})",
              "output.every: must be >= 1, got 0"),
      patched("CheckpointEveryNegative", R"({"output": {"checkpoint_every": -1}})",
              "output.checkpoint_every: must be >= 0, got -1"),
      patched("UnknownFormat", R"({"output": {"formats": ["ply", "obj"]}})",
              "output.formats[1]: unknown format \"obj\" (expected one of: ply, bgeo, vtu)"),
      patched("NoFormats", R"({"output": {"formats": []}})",
              "output.formats: must name at least one format (ply)"),
      patched("DuplicateFormat", R"({"output": {"formats": ["ply", "ply"]}})",
              "output.formats[1]: duplicate format \"ply\""),
      patched("UnknownField", R"({"output": {"fields": ["driving_force", "stress"]}})",
              "output.fields[1]: unknown field \"stress\" (expected one of: plastic_strain, "
              "fiber_tension, driving_force, damage_laplacian)"),
      patched("DuplicateField",
              R"({"output": {"fields": ["damage_laplacian", "damage_laplacian"]}})",
              "output.fields[1]: duplicate field \"damage_laplacian\""),
      patched("FieldsIsString", R"({"output": {"fields": "driving_force"}})",
              "output.fields: must be an array of strings, got a string"),
      patched("DamageToleranceOutOfRange", R"({"damage": {"solver": "implicit", "tolerance": 2}})",
              "damage.tolerance: must be in (0, 1), got 2"),
      patched("DamageIterationsZero", R"({"damage": {"solver": "implicit", "max_iterations": 0}})",
              "damage.max_iterations: must be in [1, 100000], got 0"),
      patched("SplitDamageZero", R"({"damage": {"split_fields": true, "split_damage": 0}})",
              "damage.split_damage: must be in (0, 1], got 0"),
      patched("SplitFieldsNotBoolean", R"({"damage": {"split_fields": 1}})",
              "damage.split_fields: must be true or false, got an integer (1)"),
      patched("CgToleranceRemoved", R"({"damage": {"cg_tolerance": 1e-6}})",
              "damage.cg_tolerance: replaced by damage.tolerance (the implicit damage solver is "
              "no longer a CG solve on the grid)"),
      patched("CgIterationsRemoved", R"({"damage": {"cg_max_iterations": 5}})",
              "damage.cg_max_iterations: replaced by damage.max_iterations (the implicit damage "
              "solver is no longer a CG solve on the grid)"),
      // particles objects read a file (their errors: particles_file_test.cpp)
      patched("ParticlesFileMissing",
              shape_object(R"({"type": "particles", "file": "no_such_points.ply"})"),
              "objects[0].shape.file: '"),
      patched("FibersFromFileHasNoFileKey",
              sphere_object(R"(, "fibers": {"type": "from_file", "file": "f.ply"})"),
              "objects[0].fibers.file: unknown key"),
      // surface mesh shapes are 3D only (the rest of their errors: mesh_object_test.cpp)
      patched("MeshShapeIn2D", shape_object(R"({"type": "mesh", "file": "bunny.obj"})"),
              "objects[0].shape.file: a 2D scene's \"mesh\" is a triangle mesh file"),
      // plasticity's keys, per yield surface
      patched("PlasticityNotAnObject", R"({"materials": {"jelly": {"plasticity": 3}}})",
              "materials.jelly.plasticity: must be null or an object, got an integer (3)"),
      patched("VonMisesWithoutYieldStress",
              R"({"materials": {"jelly": {"plasticity": {"type": "von_mises"}}}})",
              "materials.jelly.plasticity.yield_stress: required"),
      patched("VonMisesZeroYieldStress",
              R"({"materials": {"jelly": {"plasticity": {"type": "von_mises",
                                                         "yield_stress": 0}}}})",
              "materials.jelly.plasticity.yield_stress: must be > 0, got 0"),
      patched("VonMisesNegativeHardening",
              R"({"materials": {"jelly": {"plasticity": {"type": "von_mises", "yield_stress": 1,
                                                         "hardening": -2}}}})",
              "materials.jelly.plasticity.hardening: must be >= 0, got -2"),
      patched("VonMisesTakesNoFrictionAngle",
              R"({"materials": {"jelly": {"plasticity": {"type": "von_mises", "yield_stress": 1,
                                                         "friction_angle": 30}}}})",
              "materials.jelly.plasticity.friction_angle: unknown key"),
      patched("DruckerPragerFrictionAngleOutOfRange",
              R"({"materials": {"jelly": {"plasticity": {"type": "drucker_prager",
                                                         "friction_angle": 90}}}})",
              "materials.jelly.plasticity.friction_angle: must be in (0, 90) degrees, got 90"),
      patched("DruckerPragerNegativeCohesion",
              R"({"materials": {"jelly": {"plasticity": {"type": "drucker_prager",
                                                         "friction_angle": 30, "cohesion": -1}}}})",
              "materials.jelly.plasticity.cohesion: must be >= 0, got -1"),
      patched("DruckerPragerVolumeCorrectionNotBoolean",
              R"({"materials": {"jelly": {"plasticity": {"type": "drucker_prager",
                                                         "friction_angle": 30,
                                                         "volume_correction": 1}}}})",
              "materials.jelly.plasticity.volume_correction: must be"),
      // --- the implicit integrator's keys
      patched("ImplicitWithCrackFields",
              R"({"integrator": "implicit", "damage": {"split_fields": true}})",
              "damage.split_fields: crack fields are not supported by the implicit integrator"),
      patched("ImplicitToleranceOutOfRange", R"({"implicit": {"tolerance": 2}})",
              "implicit.tolerance: must be in (0, 1), got 2"),
      patched("ImplicitIterationsZero", R"({"implicit": {"max_iterations": 0}})",
              "implicit.max_iterations: must be in [1, 1000], got 0"),
      patched("ImplicitTypo", R"({"implicit": {"cg_tol": 0.1}})", "implicit.cg_tol"),
      patched("FiberSpreadTooLarge", sphere_object(R"(, "fibers": {"spread": 120})"),
              "objects[0].fibers.spread: must be in [0, 90] degrees, got 120"),
      patched("ImplicitPreconditionerUnknown", R"({"implicit": {"preconditioner": "amg"}})",
              "implicit.preconditioner"),
      patched("ImplicitMultigridAfterZero", R"({"implicit": {"multigrid_after": 0}})",
              "implicit.multigrid_after: must be in [1, 1e6], got 0"),
      // --- inextensibility
      patched("RelaxationWithoutInextensible",
              R"({"materials": {"jelly": {"inextensibility_relaxation": 1e5}}})",
              "materials.jelly.inextensibility_relaxation: relaxes the inextensibility "
              "constraint: set \"inextensible\": true"),
      patched("RelaxationNegative",
              R"({"materials": {"jelly": {"inextensible": true, "inextensibility_relaxation": -1}}})",
              "materials.jelly.inextensibility_relaxation: must be"),
      patched("InextensibleWithCrackFields",
              R"({"materials": {"jelly": {"inextensible": true}}, "damage": {"split_fields": true}})",
              "damage.split_fields: crack fields are not supported with inextensible materials "
              "(materials.jelly is)"),
      patched("InextensibilityToleranceOutOfRange", R"({"inextensibility": {"tolerance": 0}})",
              "inextensibility.tolerance: must be in (0, 1), got 0"),
      patched("InextensibilityIterationsZero", R"({"inextensibility": {"max_iterations": 0}})",
              "inextensibility.max_iterations: must be in [1, 1e6], got 0"),
      patched("InextensibilityTypo", R"({"inextensibility": {"tol": 0.1}})", "inextensibility.tol"),
      patched("InextensibilityPreconditionerUnknown",
              R"({"inextensibility": {"preconditioner": "amg"}})",
              "inextensibility.preconditioner: "),
      patched("FlowFibersWithoutSinks",
              sphere_object(R"(, "fibers": {"type": "flow", "sources": [[0.4, 0.5]]})"),
              "objects[0].fibers.sinks: required (an array of points)"),
      patched("FlowFibersTakeNoCenter",
              sphere_object(R"(, "fibers": {"type": "flow", "sources": [[0.4, 0.5]],
                                             "sinks": [[0.6, 0.5]], "center": [0.5, 0.5]})"),
              "objects[0].fibers.center: unknown key"),
      // --- --set overrides
      overridden("SetUnknownPath", {"materials.steel.E=1"},
                 "materials.steel.E: override \"materials.steel.E=1\": \"materials.steel\" does "
                 "not exist"),
      overridden("SetTypoInPath", {"materails.jelly.E=1"},
                 "materails.jelly.E: override \"materails.jelly.E=1\": \"materails\" does not "
                 "exist, did you mean \"materials\"?"),
      overridden("SetUnknownKey", {"grid.dxx=0.1"}, "grid.dxx: unknown key, did you mean \"dx\"?"),
      overridden("SetIndexOutOfRange", {"objects.3.ppc=1"},
                 "objects.3.ppc: override \"objects.3.ppc=1\": \"objects.3\" does not exist (array "
                 "of 1 entry)"),
      overridden("SetIndexNotANumber", {"objects.x.ppc=1"},
                 "objects.x.ppc: override \"objects.x.ppc=1\": \"objects.x\" does not exist"),
      overridden("SetThroughNumber", {"dim.x=1"},
                 "dim.x: override \"dim.x=1\": \"dim\" is an integer (2), not an object or array"),
      overridden("SetEmptyComponent", {"grid..dx=1"},
                 "grid..dx: override \"grid..dx=1\": empty path component"),
      overridden("SetWithoutValue", {"grid.dx"},
                 "(override): override \"grid.dx\" must look like a.b.c=VALUE"),
      overridden("SetBadValueType", {"time.cfl=fast"}, "time.cfl: must be a number, got a string"),
      overridden("SetValueOutOfRange", {"materials.jelly.nu=0.7"},
                 "materials.jelly.nu: must be in (-1, 0.5), got 0.7"),
      overridden("SetVectorWrongLength", {"gravity=[0, -9.8, 0]"},
                 "gravity: must be an array of 2 numbers, got 3 entries"),
  };
  return t;
}

void PrintTo(const BrokenScene& b, std::ostream* os) { *os << b.name; }

class SceneErrors : public ::testing::TestWithParam<BrokenScene> {};

TEST_P(SceneErrors, NameFilePathAndReason) {
  const BrokenScene& c = GetParam();
  std::string file;
  if (c.missing) {
    file = test::write_temp("no_such_scene.json", "");
    std::filesystem::remove(file);
  } else if (c.raw) {
    file = test::write_temp(c.name + ".json", *c.raw);
  } else {
    json doc = test::minimal_scene_2d();
    doc.merge_patch(json::parse(c.patch));
    file = test::write_temp(c.name + ".json", doc.dump(2));
  }
  std::string msg;
  try {
    load_scene(file, c.overrides);
  } catch (const SceneError& e) {
    msg = e.what();
    EXPECT_EQ(e.file(), file);
    EXPECT_EQ(msg, e.file() + ": " + e.path() + ": " + e.reason());
  }
  ASSERT_FALSE(msg.empty()) << "accepted: " << c.patch;
  EXPECT_EQ(msg.rfind(file + ": ", 0), 0u) << msg;
  EXPECT_NE(msg.find(file + ": " + c.expected), std::string::npos)
      << "message:  " << msg << "\nexpected: " << file << ": " << c.expected;
}

INSTANTIATE_TEST_SUITE_P(Table, SceneErrors, ::testing::ValuesIn(broken_scenes()),
                         [](const ::testing::TestParamInfo<BrokenScene>& i) {
                           return i.param.name;
                         });

TEST(SceneErrors, TableIsLargeAndNamesAreUnique) {
  std::vector<BrokenScene> t = broken_scenes();
  EXPECT_GE(t.size(), 20u);
  std::set<std::string> names;
  for (const BrokenScene& c : t) EXPECT_TRUE(names.insert(c.name).second) << c.name;
}

// 3D-only rules.
TEST(SceneErrors3D, VectorsNeedThreeEntriesAndRotateIsAxisAngle) {
  json doc = test::minimal_scene_2d();
  doc["dim"] = 3;
  EXPECT_NE(test::scene_error(doc).find("grid.domain_min: must be an array of 3 numbers"),
            std::string::npos);
  doc["grid"]["domain_min"] = {0, 0, 0};
  doc["grid"]["domain_max"] = {1, 1, 1};
  doc["objects"][0]["shape"] = {
      {"type", "box"}, {"min", {0.2, 0.2, 0.2}}, {"max", {0.6, 0.6, 0.6}}};
  EXPECT_EQ(test::scene_error(doc), "");
  doc["objects"][0]["shape"]["transform"] = {{"rotate", 30}};
  EXPECT_NE(test::scene_error(doc).find("objects[0].shape.transform.rotate: must be {\"axis\""),
            std::string::npos);
  doc["objects"][0]["shape"]["transform"] = {{"rotate", {{"axis", {0, 0, 0}}, {"angle_deg", 30}}}};
  EXPECT_NE(test::scene_error(doc).find("objects[0].shape.transform.rotate.axis: must be non-zero"),
            std::string::npos);
  doc["objects"][0]["shape"]["transform"] = {{"rotate", {{"axis", {0, 0, 1}}}}};
  EXPECT_NE(test::scene_error(doc).find("objects[0].shape.transform.rotate.angle_deg: required"),
            std::string::npos);
  doc["objects"][0]["shape"]["transform"] = nullptr;
  doc["objects"][0]["angular_velocity"] = 2;
  EXPECT_NE(
      test::scene_error(doc).find("objects[0].angular_velocity: must be an array of 3 numbers"),
      std::string::npos);
  doc["objects"][0].erase("angular_velocity");
  doc["materials"]["jelly"]["model"] = "qr_aniso";
  doc["materials"]["jelly"]["fiber_scale"] = {1};
  EXPECT_NE(test::scene_error(doc).find(
                "materials.jelly.fiber_scale: must be an array of 2 numbers in 3D"),
            std::string::npos);
  doc["materials"]["jelly"]["fiber_scale"] = {1, -2};
  EXPECT_NE(test::scene_error(doc).find("materials.jelly.fiber_scale[1]: must be >= 0, got -2"),
            std::string::npos);
  doc["materials"]["jelly"]["fiber_scale"] = 3;  // a scalar sets gamma1 only
  EXPECT_EQ(test::scene_error(doc), "");
  doc["materials"]["jelly"]["model"] = "fixed_corotated";
  EXPECT_NE(test::scene_error(doc).find("materials.jelly.fiber_scale: must be 0 for the isotropic"),
            std::string::npos);
  doc["materials"]["jelly"]["fiber_scale"] = {0, 0};  // zeros are fine for any model
  EXPECT_EQ(test::scene_error(doc), "");
}

TEST(SceneErrors, DirectoryIsNotAScene) {
  std::string dir = std::filesystem::temp_directory_path().string();
  try {
    load_scene(dir);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": (file): is a directory, not a scene file");
  }
}

TEST(SceneErrors, WhatIsFilePathReason) {
  SceneError e("a.json", "grid.dx", "must be > 0, got 0");
  EXPECT_STREQ(e.what(), "a.json: grid.dx: must be > 0, got 0");
  EXPECT_EQ(e.file(), "a.json");
  EXPECT_EQ(e.path(), "grid.dx");
  EXPECT_EQ(e.reason(), "must be > 0, got 0");
}

}  // namespace
}  // namespace tear
