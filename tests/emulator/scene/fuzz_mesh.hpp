// SPDX-License-Identifier: Apache-2.0
#pragma once
// What every mesh a reader returns must satisfy: triangles index existing vertices, one
// material per triangle, finite coordinates; and one fuzz input through a mesh reader.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "mirage/core/error.hpp"
#include "mirage/scene/mesh_io.hpp"
#include "mirage/scene/scene.hpp"

namespace mirage::scene::test {

inline void check_mesh(const Mesh& m, std::uint32_t materials) {
    const auto n = static_cast<long long>(m.vertices.size());
    if (m.materials.size() != m.triangles.size()) __builtin_trap();
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k)
            if (t[k] < 0 || t[k] >= n) __builtin_trap();
    for (const auto& v : m.vertices)
        if (!v.allFinite()) __builtin_trap();
    for (const std::uint32_t mat : m.materials)
        if (mat >= materials) __builtin_trap();
}

// `parse` is parse_obj or parse_ply: bad content must end in ConfigError, a mesh be consistent.
template <class Parse>
void fuzz_mesh_reader(Parse parse, const std::uint8_t* data, std::size_t size) {
    MaterialBinding materials;
    materials.fallback = 0;
    materials.by_name = {{"roof", 1}, {"wall", 2}};
    LoadStats stats;
    try {
        const std::string_view text(reinterpret_cast<const char*>(data), size);
        check_mesh(parse(text, "fuzz", materials, stats), 3);
    } catch (const ConfigError&) {
    }
}

}  // namespace mirage::scene::test
