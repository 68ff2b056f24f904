// SPDX-License-Identifier: Apache-2.0
// Wavefront OBJ reader (geometry subset): vertices, polygonal faces, usemtl.
#include <array>
#include <climits>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "mirage/core/error.hpp"
#include "mirage/scene/mesh_io.hpp"
#include "mirage/scene/mesh_ops.hpp"
#include "text_util.hpp"

namespace mirage::scene {

namespace {

using detail::quote;

// Statements that carry no triangle geometry (texture coordinates, normals, grouping,
// material libraries, render attributes, free-form curves/surfaces, points and lines).
bool is_ignored_statement(std::string_view k) {
    static constexpr std::array<std::string_view, 34> kIgnored = {
        "vt",       "vn",     "vp",         "g",         "o",      "s",     "mtllib",
        "usemap",   "maplib", "shadow_obj", "trace_obj", "lod",    "bevel", "c_interp",
        "d_interp", "mg",     "ctech",      "stech",     "cstype", "deg",   "bmat",
        "step",     "curv",   "curv2",      "surf",      "parm",   "trim",  "hole",
        "scrv",     "sp",     "end",        "con",       "l",      "p"};
    for (std::string_view s : kIgnored) {
        if (k == s) return true;
    }
    return false;
}

class ObjParser {
  public:
    ObjParser(const std::string& name, const MaterialBinding& materials, LoadStats& stats)
        : name_(name), materials_(materials), stats_(stats), current_(materials.fallback) {}

    Mesh run(std::string_view text) {
        mesh_.name = name_;
        std::size_t pos = 0;
        long line_no = 0;
        while (pos <= text.size()) {
            std::size_t end = text.find('\n', pos);
            if (end == std::string_view::npos) end = text.size();
            line_ = ++line_no;
            std::string_view line = text.substr(pos, end - pos);
            const std::size_t hash = line.find('#');
            if (hash != std::string_view::npos) line = line.substr(0, hash);
            statement(line);
            if (end == text.size()) break;
            pos = end + 1;
        }
        return std::move(mesh_);
    }

  private:
    [[noreturn]] void fail(const std::string& msg) const {
        throw ConfigError("obj '" + name_ + "': line " + std::to_string(line_) + ": " + msg);
    }

    void statement(std::string_view line) {
        tokens_.clear();
        detail::for_each_token(line, [&](std::string_view t) { tokens_.push_back(t); });
        if (tokens_.empty()) return;
        const std::string_view key = tokens_[0];
        if (key == "v") {
            vertex();
        } else if (key == "f" || key == "fo") {
            face();
        } else if (key == "usemtl") {
            if (tokens_.size() < 2) fail("usemtl without a material name");
            const std::string_view m = detail::trim(line.substr(line.find("usemtl") + 6));
            auto it = materials_.by_name.find(m);
            current_ = it != materials_.by_name.end() ? it->second : materials_.fallback;
        } else if (!is_ignored_statement(key)) {
            fail("unknown statement " + quote(key));
        }
    }

    void vertex() {
        // v x y z [w] or v x y z r g b (vertex colours): only x, y, z matter.
        const std::size_t n = tokens_.size() - 1;
        if (n != 3 && n != 4 && n != 6 && n != 7) {
            fail("vertex needs 3 coordinates, got " + std::to_string(n) + " values");
        }
        std::array<double, 3> xyz{};
        for (std::size_t i = 0; i < n; ++i) {
            auto v = detail::parse_double(tokens_[i + 1]);
            if (!v) fail("malformed number " + quote(tokens_[i + 1]));
            if (!std::isfinite(*v)) fail("non-finite vertex value " + quote(tokens_[i + 1]));
            if (i < 3) {
                // A coordinate that overflows float would become Inf in the mesh.
                if (std::abs(*v) > 1e30)
                    fail("vertex coordinate " + quote(tokens_[i + 1]) + " out of float range");
                xyz[i] = *v;
            }
        }
        if (mesh_.vertices.size() >= static_cast<std::size_t>(INT_MAX)) fail("too many vertices");
        mesh_.vertices.emplace_back(static_cast<float>(xyz[0]), static_cast<float>(xyz[1]),
                                    static_cast<float>(xyz[2]));
    }

    int index(std::string_view token) {
        // i, i/t, i//n, i/t/n: the texture and normal parts must be integers when present.
        const std::size_t s1 = token.find('/');
        const std::string_view vpart = token.substr(0, s1);
        if (s1 != std::string_view::npos) {
            std::string_view rest = token.substr(s1 + 1);
            const std::size_t s2 = rest.find('/');
            const std::string_view tpart = rest.substr(0, s2);
            const std::string_view npart =
                s2 == std::string_view::npos ? std::string_view{} : rest.substr(s2 + 1);
            if ((!tpart.empty() && !detail::parse_int(tpart)) ||
                (s2 != std::string_view::npos && !detail::parse_int(npart)) ||
                npart.find('/') != std::string_view::npos) {
                fail("malformed face vertex " + quote(token));
            }
        }
        auto v = detail::parse_int(vpart);
        if (!v) fail("malformed face vertex " + quote(token));
        const auto nv = static_cast<long long>(mesh_.vertices.size());
        long long idx = *v > 0 ? *v - 1 : nv + *v;
        if (*v == 0) fail("face index 0 is invalid (OBJ indices start at 1)");
        if (idx < 0 || idx >= nv) {
            fail("face index " + std::to_string(*v) + " out of range (" + std::to_string(nv) +
                 " vertices)");
        }
        return static_cast<int>(idx);
    }

    void face() {
        const std::size_t n = tokens_.size() - 1;
        if (n < 3) fail("face needs at least 3 vertices, got " + std::to_string(n));
        corners_.clear();
        for (std::size_t i = 1; i <= n; ++i) corners_.push_back(index(tokens_[i]));
        for (std::size_t i = 1; i + 1 < n; ++i) {
            append_triangle(mesh_, corners_[0], corners_[i], corners_[i + 1], current_, stats_);
        }
    }

    const std::string& name_;
    const MaterialBinding& materials_;
    LoadStats& stats_;
    std::uint32_t current_;
    long line_ = 0;
    Mesh mesh_;
    std::vector<std::string_view> tokens_;
    std::vector<int> corners_;
};

}  // namespace

Mesh parse_obj(std::string_view text, const std::string& name, const MaterialBinding& materials,
               LoadStats& stats) {
    return ObjParser(name, materials, stats).run(text);
}

Mesh read_obj(const std::string& path, const MaterialBinding& materials, LoadStats& stats) {
    const std::string bytes = read_file_bytes(path, "obj");
    return parse_obj(bytes, path, materials, stats);
}

}  // namespace mirage::scene
