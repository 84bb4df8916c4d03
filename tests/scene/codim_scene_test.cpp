// Codimensional objects in scenes (kind "surface" and "curves"): generated and file meshes,
// their checks, and the errors that name the file, the element and the reason.
#include "scene_test_util.h"

#include "tear/scene/sampling.h"

namespace tear {
namespace {

using nlohmann::json;
using test::scene_error;

// A 3D scene over the unit cube with a cloth, a yarn and a jelly material and `objects`.
json codim_scene(const std::vector<json>& objects, int dim = 3) {
  json doc = test::minimal_scene_2d();
  doc["dim"] = dim;
  if (dim == 3)
    doc["grid"] = {{"dx", 0.05}, {"domain_min", {0, 0, 0}}, {"domain_max", {1, 1, 1}}};
  doc["materials"]["cloth"] = {{"model", "surface_qr"}, {"E", 1e4}, {"nu", 0.3}, {"rho", 200}};
  doc["materials"]["yarn"] = {{"model", "curve_qr"}, {"E", 1e4}, {"nu", 0.3}, {"rho", 300}};
  doc["objects"] = objects;
  return doc;
}

json sheet(const json& shape_extra = json::object()) {
  json shape = {{"type", "sheet"}, {"center", {0.5, 0.5, 0.5}}, {"size", {0.4, 0.3}},
                {"resolution", {8, 6}}};
  shape.update(shape_extra);
  return {{"kind", "surface"}, {"material", "cloth"}, {"thickness", 0.002}, {"shape", shape}};
}

json mesh_object(const std::string& kind, const std::string& file) {
  return {{"kind", kind},
          {"material", kind == "surface" ? "cloth" : "yarn"},
          {kind == "surface" ? "thickness" : "radius", 0.002},
          {"shape", {{"type", "mesh"}, {"file", file}}}};
}

TEST(CodimScene, SheetAndRopeResolveWithTheirDefaults) {
  json rope = {{"kind", "curves"}, {"material", "yarn"}, {"radius", 0.001},
               {"shape", {{"type", "rope"}, {"from", {0.2, 0.8, 0.5}}, {"to", {0.8, 0.8, 0.5}},
                          {"segments", 30}}}};
  const Scene s = parse_scene(codim_scene({sheet(), rope}), "ok.json");
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0].kind, ObjectKind::Surface);
  EXPECT_EQ(s.objects[0].mesh->vertices.size(), 9u * 7u);
  EXPECT_EQ(s.objects[0].mesh->elements.size(), 2u * 8u * 6u);
  EXPECT_EQ(s.objects[1].kind, ObjectKind::Curves);
  EXPECT_EQ(s.objects[1].mesh->elements.size(), 30u);
  const json& o = s.resolved["objects"][0];
  EXPECT_EQ(o["shape"]["triangulation"], "regular");
  EXPECT_EQ(o["thickness"], 0.002);
  const json& cloth = s.resolved["materials"]["cloth"];
  // Physical defaults: k = E, gamma = mu, c_F 0.3.
  EXPECT_EQ(cloth["normal_stiffness"], 1e4);
  EXPECT_NEAR(cloth["shear_stiffness"].get<double>(), 1e4 / 2.6, 1e-9);
  EXPECT_NEAR(cloth["friction"].get<double>(), 0.3, 1e-12);
  // The resolved scene loads again to the same scene.
  const Scene again = parse_scene(s.resolved, "again.json");
  EXPECT_EQ(again.resolved, s.resolved);
  EXPECT_EQ(again.objects[0].mesh->vertices, s.objects[0].mesh->vertices);
}

TEST(CodimScene, RandomTriangulationIsSeededAndKeepsTheBorder) {
  const json doc = codim_scene({sheet({{"triangulation", "random"}})});
  const Scene a = parse_scene(doc, "a.json"), b = parse_scene(doc, "b.json");
  EXPECT_EQ(a.objects[0].mesh->vertices, b.objects[0].mesh->vertices);
  EXPECT_EQ(a.objects[0].mesh->elements, b.objects[0].mesh->elements);
  json other = doc;
  other["seed"] = 7;
  const Scene c = parse_scene(other, "c.json");
  EXPECT_NE(a.objects[0].mesh->vertices, c.objects[0].mesh->vertices);
  const Scene regular = parse_scene(codim_scene({sheet()}), "r.json");
  // Border vertices stay where the regular sheet has them; the area is the sheet's.
  const CodimMesh& m = *a.objects[0].mesh;
  double area = 0;
  for (const auto& t : m.elements)
    area += (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm() / 2;
  EXPECT_NEAR(area, 0.4 * 0.3, 1e-12);
  for (size_t v = 0; v < m.vertices.size(); ++v) {
    const Vec3d& x = regular.objects[0].mesh->vertices[v];
    const bool border = std::abs(std::abs(x.x() - 0.5) - 0.2) < 1e-12 ||
                        std::abs(std::abs(x.z() - 0.5) - 0.15) < 1e-12;
    if (border) {
      EXPECT_EQ(m.vertices[v], x);
    }
  }
}

TEST(CodimScene, MeshFilesGiveSurfacesAndCurves) {
  const std::string obj = test::write_temp("codim_quad.obj",
                                           "v 0.3 0.5 0.3\nv 0.7 0.5 0.3\nv 0.7 0.5 0.7\nv 0.3 0.5 0.7\n"
                                           "f 1 2 3 4\n");
  const std::string lines = test::write_temp("codim_lines.obj",
                                             "v 0.3 0.5 0.3\nv 0.5 0.6 0.3\nv 0.7 0.5 0.3\n"
                                             "v 0.3 0.3 0.6\nv 0.6 0.3 0.6\nl 1 2 3\nl 4 5\n");
  const std::string ply = test::write_temp(
      "codim_edges.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement edge 2\nproperty int vertex1\nproperty int vertex2\n"
      "end_header\n0.2 0.2 0.2\n0.4 0.2 0.2\n0.4 0.4 0.2\n0 1\n1 2\n");
  const Scene s = parse_scene(
      codim_scene({mesh_object("surface", obj), mesh_object("curves", lines),
                   mesh_object("curves", ply)}),
      "files.json");
  EXPECT_EQ(s.objects[0].mesh->elements.size(), 2u);  // the quad as a fan
  EXPECT_EQ(s.objects[1].mesh->elements.size(), 3u);  // 2 + 1 segments
  EXPECT_EQ(s.objects[2].mesh->elements.size(), 2u);
  const std::vector<Particles<3>> groups = sample_scene_groups<3>(s);
  ASSERT_EQ(groups.size(), 5u);
  EXPECT_EQ(groups[1].size(), 5u + 3u);  // curve vertices of both objects
  EXPECT_EQ(groups[2].element_vertices[3], (std::array<uint32_t, 3>{5, 6, 6}));  // offset
}

// Hair on a scalp: every strand rooted on the sphere's cap, straight along the outward normal.
TEST(CodimScene, StrandsGrowOutOfTheCapOfTheirSphere) {
  const Vec3d centre(0.5, 0.4, 0.5), up(0, 0, 1);
  json hair = {{"kind", "curves"}, {"material", "yarn"}, {"radius", 0.0005},
               {"shape", {{"type", "strands"}, {"center", {0.5, 0.4, 0.5}}, {"radius", 0.1},
                          {"direction", {0, 0, 1}}, {"cap_angle", 70}, {"count", 200},
                          {"length", 0.15}, {"segments", 12}}}};
  const Scene s = parse_scene(codim_scene({hair}), "hair.json");
  const CodimMesh& m = *s.objects[0].mesh;
  ASSERT_EQ(m.vertices.size(), 200u * 13u);
  ASSERT_EQ(m.elements.size(), 200u * 12u);
  double lowest = 1;
  for (int k = 0; k < 200; ++k) {
    const Vec3d root = m.vertices[size_t(k * 13)], tip = m.vertices[size_t(k * 13 + 12)];
    EXPECT_NEAR((root - centre).norm(), 0.1, 1e-12);
    EXPECT_NEAR((tip - centre).norm(), 0.25, 1e-12);
    EXPECT_LT(((tip - root).normalized() - (root - centre).normalized()).norm(), 1e-12);
    lowest = std::min(lowest, (root - centre).normalized().dot(up));
    EXPECT_EQ(m.elements[size_t(k * 12)], (std::array<uint32_t, 3>{uint32_t(k * 13), uint32_t(k * 13 + 1), 0}));
  }
  // The cap is filled to its rim at 70 degrees from the direction.
  EXPECT_GT(lowest, std::cos(70 * 3.14159265358979323846 / 180) - 1e-12);
  EXPECT_LT(lowest, std::cos(65 * 3.14159265358979323846 / 180));
  // In 2D the roots are spread evenly over the arc.
  json doc2 = codim_scene({hair}, 2);
  doc2["objects"][0]["shape"] = {{"type", "strands"}, {"center", {0.5, 0.4}}, {"radius", 0.1},
                                 {"cap_angle", 90}, {"count", 5}, {"length", 0.15},
                                 {"segments", 6}};
  const Scene s2 = parse_scene(doc2, "hair2.json");
  const CodimMesh& m2 = *s2.objects[0].mesh;
  ASSERT_EQ(m2.vertices.size(), 35u);
  EXPECT_NEAR(m2.vertices[0].x(), 0.5 + 0.1, 1e-12);  // -90 degrees from up (+y): along +x
  EXPECT_NEAR(m2.vertices[14].y(), 0.5, 1e-12);       // the middle strand: straight up
  EXPECT_NEAR(m2.vertices[28].x(), 0.5 - 0.1, 1e-12);
}

// A knit swatch: one yarn (each segment joins consecutive vertices) whose courses cross each
// other in the swatch's plane with the yarn in front at some crossings and behind at others
// (interlocked, not lying side by side), apart in depth where they cross, inside its size.
TEST(CodimScene, KnitSwatchIsOneYarnWhoseCoursesInterlock) {
  const int wales = 5, courses = 4;
  const double W = 0.02, H = 0.015;
  json knit = {{"kind", "curves"}, {"material", "yarn"}, {"radius", 0.0005},
               {"shape", {{"type", "knit"}, {"center", {0.5, 0.4, 0.5}}, {"size", {wales * W, courses * H}},
                          {"wales", wales}, {"courses", courses}, {"segments_per_loop", 12}}}};
  const Scene s = parse_scene(codim_scene({knit}), "knit.json");
  const CodimMesh& m = *s.objects[0].mesh;
  ASSERT_EQ(m.elements.size() + 1, m.vertices.size());
  EXPECT_GT(m.vertices.size(), size_t(courses * (wales * 12 + 1)));  // and the turns between
  for (size_t e = 0; e < m.elements.size(); ++e)
    ASSERT_EQ(m.elements[e], (std::array<uint32_t, 3>{uint32_t(e), uint32_t(e + 1), 0}));
  for (const Vec3d& v : m.vertices) {
    EXPECT_LE(std::abs(v.x() - 0.5), wales * W / 2 + 0.15 * W);  // the end loops' bulges
    EXPECT_LE(std::abs(v.y() - 0.4), courses * H / 2 + 0.25 * H + 1e-12);
  }
  // Crossings of the segments' projections onto the swatch's plane (z): which is in front.
  int front = 0, behind = 0;
  double closest = 1;
  for (size_t a = 0; a < m.elements.size(); ++a)
    for (size_t b = a + 2; b < m.elements.size(); ++b) {
      const Vec3d p = m.vertices[a], r = m.vertices[a + 1] - p, q = m.vertices[b], t = m.vertices[b + 1] - q;
      const double den = r.x() * t.y() - r.y() * t.x();
      if (std::abs(den) < 1e-15) continue;
      const double u = ((q - p).x() * t.y() - (q - p).y() * t.x()) / den,
                   w = ((q - p).x() * r.y() - (q - p).y() * r.x()) / den;
      if (u < 0 || u > 1 || w < 0 || w > 1) continue;
      const double dz = (q + w * t).z() - (p + u * r).z();
      (dz > 0 ? front : behind) += 1;
      closest = std::min(closest, std::abs(dz));
    }
  EXPECT_GE(front, wales * (courses - 1));
  EXPECT_GE(behind, wales * (courses - 1));
  EXPECT_GT(closest, 0.2 * std::min(W, H)) << front << " / " << behind;
  // 2D has no depth to interlock in.
  json doc2 = codim_scene({knit}, 2);
  doc2["objects"][0]["shape"]["center"] = {0.5, 0.4};
  EXPECT_NE(scene_error(doc2, "knit2.json").find("objects[0].shape.type: a \"knit\" swatch needs a 3D scene"),
            std::string::npos)
      << scene_error(doc2, "knit2.json");
}

struct Broken {
  std::string name;
  json doc;
  std::string expected;  // substring of the message
};

std::vector<Broken> broken() {
  const std::string flat = test::write_temp(
      "codim_flat.obj", "v 0.3 0.5 0.3\nv 0.5 0.5 0.3\nv 0.7 0.5 0.3\nv 0.3 0.5 0.6\n"
                        "f 1 2 4\nf 1 2 3\n");
  const std::string twice = test::write_temp(
      "codim_twice.obj", "v 0.3 0.5 0.3\nv 0.5 0.5 0.3\nv 0.5 0.5 0.3\nv 0.3 0.5 0.6\nf 1 2 4\nf 1 3 4\n");
  const std::string repeated = test::write_temp(
      "codim_repeated.obj", "v 0.3 0.5 0.3\nv 0.5 0.5 0.3\nv 0.3 0.5 0.6\nf 1 2 3\nf 1 1 2\n");
  const std::string loose = test::write_temp(
      "codim_loose.obj", "v 0.3 0.5 0.3\nv 0.5 0.5 0.3\nv 0.3 0.5 0.6\nv 0.6 0.6 0.6\nf 1 2 3\n");
  const std::string outside = test::write_temp(
      "codim_outside.obj", "v 0.3 0.5 0.3\nv 0.5 0.5 0.3\nv 0.3 0.5 0.99\nf 1 2 3\n");
  const std::string range = test::write_temp(
      "codim_range.ply",
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nelement edge 1\nproperty int vertex1\nproperty int vertex2\n"
      "end_header\n0.2 0.2 0.2\n0.4 0.2 0.2\n0 2\n");
  const std::string faces_only = test::write_temp(
      "codim_faces.obj", "v 0.3 0.5 0.3\nv 0.5 0.5 0.3\nv 0.3 0.5 0.6\nf 1 2 3\n");
  json volume_cloth = codim_scene({{{"material", "cloth"},
                                    {"shape", {{"type", "box"}, {"min", {0.2, 0.2, 0.2}},
                                               {"max", {0.4, 0.4, 0.4}}}}}});
  json yarn_sheet = codim_scene({sheet()});
  yarn_sheet["objects"][0]["material"] = "yarn";
  json jelly_keys = codim_scene({sheet()});
  jelly_keys["materials"]["jelly"]["friction"] = 0.2;
  json both = codim_scene({sheet()});
  both["materials"]["cloth"]["friction"] = 0.2;
  both["materials"]["cloth"]["friction_angle"] = 20;
  json damage = codim_scene({sheet()});
  damage["damage"] = {{"solver", "explicit"}};
  json implicit = codim_scene({sheet()});
  implicit["integrator"] = "implicit";
  implicit["implicit"] = {{"preconditioner", "multigrid"}};
  json surface_2d = codim_scene({sheet()}, 2);
  json resolution = codim_scene({sheet({{"resolution", {8, 2.5}}})});
  json strands = codim_scene({{{"kind", "curves"}, {"material", "yarn"}, {"radius", 0.001},
                                {"shape", {{"type", "strands"}, {"center", {0.5, 0.4, 0.5}},
                                           {"radius", 0.1}, {"cap_angle", 0}, {"count", 3},
                                           {"length", 0.1}, {"segments", 4}}}}});
  json bgeo = codim_scene({sheet()});
  bgeo["output"] = {{"mesh_formats", {"ply", "bgeo"}}};
  json plastic = codim_scene({sheet()});
  plastic["materials"]["cloth"]["plasticity"] = {{"type", "von_mises"}, {"yield_stress", 5}};
  return {
      {"ZeroAreaTriangle", codim_scene({mesh_object("surface", flat)}),
       "objects[0].shape: '" + flat + "': triangle 1 has zero area (vertices 0, 1, 2)"},
      {"RepeatedVertices", codim_scene({mesh_object("surface", twice)}),
       "objects[0].shape: '" + twice + "': vertices 1 and 2 are at the same point"},
      {"VertexTwiceInATriangle", codim_scene({mesh_object("surface", repeated)}),
       "'" + repeated + "': triangle 1 uses vertex 0 twice"},
      {"UnusedVertex", codim_scene({mesh_object("surface", loose)}),
       "'" + loose + "': vertex 3 (0.6, 0.6, 0.6) belongs to no triangle"},
      {"MeshOutsideTheDomain", codim_scene({mesh_object("surface", outside)}),
       "'" + outside + "': vertex 2 (0.3, 0.5, 0.99) is outside the grid domain less one cell"},
      {"EdgeIndexOutOfRange", codim_scene({mesh_object("curves", range)}),
       "objects[0].shape.file: "},
      {"CurvesFromAFileOfFaces", codim_scene({mesh_object("curves", faces_only)}),
       "has no lines (OBJ \"l\" statements or a PLY edge element); its faces are a surface"},
      {"VolumeObjectOfACodimMaterial", volume_cloth,
       "objects[0].material: material \"cloth\" is surface_qr, a model for surfaces: give the "
       "object \"kind\": \"surface\""},
      {"SheetOfACurveMaterial", yarn_sheet,
       "objects[0].material: material \"yarn\" is curve_qr, not a model for surfaces"},
      {"CodimKeysOnASolid", jelly_keys,
       "materials.jelly.friction: only for the codimensional models"},
      {"FrictionTwice", both, "materials.cloth.friction_angle: give \"friction\""},
      {"WithDamage", damage, "damage.solver: damage does not run beside codimensional objects"},
      {"WithMultigrid", implicit,
       "implicit.preconditioner: \"multigrid\" does not take codimensional objects"},
      {"SurfaceIn2D", surface_2d, "objects[0].kind: a \"surface\" needs a 3D scene"},
      {"FractionalResolution", resolution,
       "objects[0].shape.resolution[1]: must be a whole number of quads"},
      {"PlasticCloth", plastic, "materials.cloth.plasticity: not for the codimensional model"},
      {"MeshFormatBgeo", bgeo, "output.mesh_formats[1]: "},
      {"StrandsOnAPoint", strands, "objects[0].shape.cap_angle: must be > 0 for more than one strand"},
  };
}

TEST(CodimScene, BadInputIsRefusedWithFileElementAndReason) {
  for (const Broken& b : broken()) {
    const std::string message = scene_error(b.doc, "broken.json");
    EXPECT_NE(message.find(b.expected), std::string::npos)
        << b.name << "\n  got:      " << message << "\n  expected: " << b.expected;
    EXPECT_EQ(message.rfind("broken.json: ", 0), 0u) << b.name << ": " << message;
  }
}

}  // namespace
}  // namespace tear
