// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <string_view>

#include "mirage/scene/scene.hpp"

namespace mirage::scene {

// How faces of a mesh file get their Scene material: OBJ `usemtl <name>` picks by_name[name]
// when present, every other face uses `fallback`.
struct MaterialBinding {
    std::uint32_t fallback = 0;
    std::map<std::string, std::uint32_t, std::less<>> by_name;
};

// Wavefront OBJ: `v x y z [w | r g b]`, `f` with `i`, `i/t`, `i//n`, `i/t/n` index forms
// (negative = relative to the vertices read so far), polygons fan-triangulated, `usemtl`.
// Texture/normal data, groups, smoothing and free-form statements are read and ignored; any
// other statement is an error. Throws ConfigError "obj '<name>': line N: ..." on bad content
// (malformed number, NaN/Inf, index 0 or out of range, face with < 3 vertices) and IoError when
// the file cannot be read. Degenerate triangles are dropped and counted in `stats`.
Mesh parse_obj(std::string_view text, const std::string& name, const MaterialBinding& materials,
               LoadStats& stats);
Mesh read_obj(const std::string& path, const MaterialBinding& materials, LoadStats& stats);

// Stanford PLY, format ascii / binary_little_endian / binary_big_endian 1.0. Element `vertex`
// with scalar properties x, y, z of any type; element `face` with a list property
// `vertex_indices` (or `vertex_index`) of any count/index types, polygons fan-triangulated; other
// properties and elements are skipped. Every face uses materials.fallback. Element counts and
// list lengths are checked against the bytes left before anything is allocated. Throws
// ConfigError "ply '<name>': header line N: ..." / "ply '<name>': vertex[i]: ..." (ASCII bodies
// also name the line), IoError when the file cannot be read.
Mesh parse_ply(std::string_view bytes, const std::string& name, const MaterialBinding& materials,
               LoadStats& stats);
Mesh read_ply(const std::string& path, const MaterialBinding& materials, LoadStats& stats);

// Whole file as bytes; IoError("<component> '<path>': cannot open ...") when unreadable.
std::string read_file_bytes(const std::string& path, std::string_view component);

}  // namespace mirage::scene
