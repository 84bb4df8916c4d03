// scene/: the section parsers behind parse_scene (internal to scene/). Each validates one
// section of the document, fills the Scene and returns the section fully resolved.
#pragma once

#include "tear/scene/scene_json.h"

namespace tear::scene_detail {

// "materials": fills scene->materials in name order.
json parse_materials(const Reader& r, const json& doc, Scene* scene);
// One shape description at `path`; half_space is allowed only for colliders. A "mesh" shape
// read from a volume mesh file (.msh, .node/.ele, .vtu) is the solid its elements fill; the
// elements themselves (checked, in the shape's local frame) go to *volume where it is given.
json parse_shape(const Reader& r, const json& j, const std::string& path, bool allow_half_space,
                 Shape* shape, std::shared_ptr<const FemMesh>* volume = nullptr);
// The index in scene.materials of the material named at obj["material"] (also recorded in
// (*out)["material"]); an unknown name fails listing the defined ones.
int material_index(const Reader& r, const json& obj, const std::string& path, const Scene& scene,
                   json* out);
// A shape's optional "transform" (translate, rotate, scale) into *t.
json parse_transform(const Reader& r, const json& shape, const std::string& path,
                     ShapeTransform* t);
// A codimensional object (objects[i] with "kind" "surface" or "curves"; scene_codim.cpp): its
// mesh made, checked and placed. `index` seeds a random triangulation.
json parse_codim_object(const Reader& r, const json& o, const std::string& path,
                        const Scene& scene, size_t index, ObjectSpec* spec);
// "objects": needs scene->materials (names) and scene->dx-independent fields only.
json parse_objects(const Reader& r, const json& doc, Scene* scene);
// "boundaries".
json parse_boundaries(const Reader& r, const json& doc, Scene* scene);

// The file named by j["file"] (required, non-empty), relative to the scene file's folder: its
// absolute path, also recorded in (*out)["file"].
std::string scene_file(const Reader& r, const json& j, const std::string& path, json* out);

// ppc = k^dim for an integer k >= 1: returns k, else 0.
int ppc_root(int ppc, int dim);

}  // namespace tear::scene_detail
