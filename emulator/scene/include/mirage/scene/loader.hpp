// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "mirage/scene/scene.hpp"

namespace mirage::scene {

// Loads a scene YAML (docs/file-formats.md §1). Relative mesh/raster paths resolve against the
// YAML's folder. Throws ConfigError naming the file and the key path or line on any problem:
// unknown keys, missing files, malformed OBJ/PLY, NaN/Inf coordinates. Degenerate triangles are
// dropped and counted in Scene::stats.
Scene load_scene(const std::string& path);
// The same from YAML text in memory: `name` labels errors, relative paths resolve against `dir`.
Scene load_scene_text(const std::string& yaml, const std::string& name,
                      const std::filesystem::path& dir);

// "demo" or "demo:<seed>" -> the generated demo town; anything else -> load_scene(path).
Scene resolve_scene(const std::string& spec);

}  // namespace mirage::scene
