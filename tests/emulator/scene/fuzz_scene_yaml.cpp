// SPDX-License-Identifier: Apache-2.0
// libFuzzer: scene YAML text, loaded in memory against recordings/scenes (so `file:` may name its
// meshes and rasters). Inputs with '/' or '\' (paths and YAML escapes that could spell one) are
// rejected so no file outside that folder is read. Bad content must end in ConfigError or
// IoError; a loaded scene must be consistent.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_mesh.hpp"
#include "mirage/core/error.hpp"
#include "mirage/scene/loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace mirage::scene;
    const std::string text(reinterpret_cast<const char*>(data), size);
    if (text.find_first_of("/\\") != std::string::npos) return -1;  // not added to the corpus
    try {
        const Scene s = load_scene_text(text, "fuzz.yaml", MIRAGE_SOURCE_DIR "/recordings/scenes");
        const auto materials = static_cast<std::uint32_t>(s.materials.size());
        for (const Mesh& m : s.meshes) test::check_mesh(m, materials);
        for (const Instance& i : s.instances)
            if (i.mesh >= s.meshes.size()) __builtin_trap();
    } catch (const mirage::ConfigError&) {
    } catch (const mirage::IoError&) {
    }
    return 0;
}
