// scene/: the section parsers behind parse_scene (internal to scene/). Each validates one
// section of the document, fills the Scene and returns the section fully resolved.
#pragma once

#include "tear/scene/scene_json.h"

namespace tear::scene_detail {

// "materials": fills scene->materials in name order.
json parse_materials(const Reader& r, const json& doc, Scene* scene);
// One shape description at `path`; half_space is allowed only for colliders.
json parse_shape(const Reader& r, const json& j, const std::string& path, bool allow_half_space,
                 Shape* shape);
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
