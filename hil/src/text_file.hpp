// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <fmt/format.h>

#include <fstream>
#include <string>

#include "mirage/core/error.hpp"

namespace mirage::hil {

// Writes `text` to `path` (replacing it); IoError naming the component and the file on failure.
inline void write_text_file(const std::string& path, const std::string& text,
                            const std::string& component) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f << text;
    f.close();
    if (!f) throw IoError(fmt::format("{}: cannot write '{}'", component, path));
}

}  // namespace mirage::hil
