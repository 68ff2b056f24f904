// SPDX-License-Identifier: Apache-2.0
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/scene/mesh_io.hpp"
#include "text_util.hpp"

namespace mirage::scene {

std::string read_file_bytes(const std::string& path, std::string_view component) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw IoError(std::string(component) + " '" + path + "': cannot open (" +
                      std::strerror(errno) + ")");
    }
    std::string data;
    char buf[1 << 16];
    while (in.read(buf, sizeof buf) || in.gcount() > 0) {
        data.append(buf, static_cast<std::size_t>(in.gcount()));
    }
    if (in.bad()) throw IoError(std::string(component) + " '" + path + "': read error");
    return data;
}

namespace detail {

std::string quote(std::string_view token) {
    std::string out = "'";
    std::size_t n = 0;
    for (char c : token) {
        if (++n > 32) {
            out += "...";
            break;
        }
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x20 && u < 0x7f) {
            out += c;
        } else {
            static const char* hex = "0123456789abcdef";
            out += "\\x";
            out += hex[u >> 4];
            out += hex[u & 15];
        }
    }
    return out + "'";
}

}  // namespace detail
}  // namespace mirage::scene
