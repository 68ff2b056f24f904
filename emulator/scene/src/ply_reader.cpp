// SPDX-License-Identifier: Apache-2.0
// Stanford PLY reader: ascii, binary_little_endian, binary_big_endian (format 1.0).
#include <climits>
#include <cmath>
#include <cstring>
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

enum class Type { I8, U8, I16, U16, I32, U32, F32, F64 };
enum class Format { Ascii, BinaryLE, BinaryBE };

bool type_from_name(std::string_view s, Type& t) {
    struct Entry {
        std::string_view name;
        Type type;
    };
    static constexpr Entry kTypes[] = {
        {"char", Type::I8},    {"int8", Type::I8},     {"uchar", Type::U8},
        {"uint8", Type::U8},   {"short", Type::I16},   {"int16", Type::I16},
        {"ushort", Type::U16}, {"uint16", Type::U16},  {"int", Type::I32},
        {"int32", Type::I32},  {"uint", Type::U32},    {"uint32", Type::U32},
        {"float", Type::F32},  {"float32", Type::F32}, {"double", Type::F64},
        {"float64", Type::F64}};
    for (const Entry& e : kTypes) {
        if (e.name == s) {
            t = e.type;
            return true;
        }
    }
    return false;
}

std::size_t type_size(Type t) {
    switch (t) {
        case Type::I8:
        case Type::U8:
            return 1;
        case Type::I16:
        case Type::U16:
            return 2;
        case Type::I32:
        case Type::U32:
        case Type::F32:
            return 4;
        case Type::F64:
            return 8;
    }
    return 1;
}

bool is_integer(Type t) { return t != Type::F32 && t != Type::F64; }

struct Property {
    std::string name;
    bool is_list = false;
    Type type = Type::F32;       // scalar type, or list item type
    Type count_type = Type::U8;  // list count type
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> props;
    std::size_t header_line = 0;
};

class PlyParser {
  public:
    PlyParser(std::string_view bytes, const std::string& name, const MaterialBinding& materials,
              LoadStats& stats)
        : data_(bytes), name_(name), materials_(materials), stats_(stats) {}

    Mesh run() {
        header();
        body();
        return build();
    }

  private:
    // ---- errors ---------------------------------------------------------------------------
    [[noreturn]] void fail_header(std::size_t line, const std::string& msg) const {
        throw ConfigError("ply '" + name_ + "': header line " + std::to_string(line) + ": " + msg);
    }
    [[noreturn]] void fail_item(const std::string& msg) const {
        std::string where = "ply '" + name_ + "': ";
        if (format_ == Format::Ascii) where += "line " + std::to_string(line_) + ": ";
        throw ConfigError(where + elem_->name + "[" + std::to_string(item_) + "]: " + msg);
    }
    [[noreturn]] void fail(const std::string& msg) const {
        throw ConfigError("ply '" + name_ + "': " + msg);
    }

    // ---- header ---------------------------------------------------------------------------
    void header() {
        if (data_.substr(0, 4) != "ply\n" && data_.substr(0, 5) != "ply\r\n") {
            fail("not a PLY file (no 'ply' magic line)");
        }
        std::size_t pos = 0;
        std::size_t line_no = 0;
        bool have_format = false;
        for (;;) {
            const std::size_t nl = data_.find('\n', pos);
            if (nl == std::string_view::npos) {
                fail("header has no end_header line");
            }
            ++line_no;
            std::string_view line = data_.substr(pos, nl - pos);
            if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
            pos = nl + 1;
            std::vector<std::string_view> tok;
            detail::for_each_token(line, [&](std::string_view t) { tok.push_back(t); });
            if (line_no == 1) continue;  // the magic, checked above
            if (tok.empty()) continue;
            const std::string_view key = tok[0];
            if (key == "comment" || key == "obj_info") continue;
            if (key == "format") {
                if (have_format) fail_header(line_no, "second format line");
                if (tok.size() != 3) fail_header(line_no, "expected 'format <type> 1.0'");
                if (tok[1] == "ascii") {
                    format_ = Format::Ascii;
                } else if (tok[1] == "binary_little_endian") {
                    format_ = Format::BinaryLE;
                } else if (tok[1] == "binary_big_endian") {
                    format_ = Format::BinaryBE;
                } else {
                    fail_header(line_no, "unknown format " + quote(tok[1]));
                }
                if (tok[2] != "1.0" && tok[2] != "1") {
                    fail_header(line_no, "unsupported version " + quote(tok[2]));
                }
                have_format = true;
            } else if (key == "element") {
                if (tok.size() != 3) fail_header(line_no, "expected 'element <name> <count>'");
                auto n = detail::parse_int(tok[2]);
                if (!n || *n < 0) fail_header(line_no, "bad element count " + quote(tok[2]));
                Element e;
                e.name = std::string(tok[1]);
                e.count = static_cast<std::uint64_t>(*n);
                e.header_line = line_no;
                for (const Element& o : elements_) {
                    if (o.name == e.name)
                        fail_header(line_no, "duplicate element " + quote(tok[1]));
                }
                elements_.push_back(std::move(e));
            } else if (key == "property") {
                if (elements_.empty()) fail_header(line_no, "property before any element");
                Property p;
                if (tok.size() >= 2 && tok[1] == "list") {
                    if (tok.size() != 5) {
                        fail_header(line_no,
                                    "expected 'property list <count type> <item type> <name>'");
                    }
                    p.is_list = true;
                    if (!type_from_name(tok[2], p.count_type)) {
                        fail_header(line_no, "unknown type " + quote(tok[2]));
                    }
                    if (!is_integer(p.count_type)) {
                        fail_header(line_no, "list count type must be an integer type");
                    }
                    if (!type_from_name(tok[3], p.type)) {
                        fail_header(line_no, "unknown type " + quote(tok[3]));
                    }
                    p.name = std::string(tok[4]);
                } else {
                    if (tok.size() != 3) fail_header(line_no, "expected 'property <type> <name>'");
                    if (!type_from_name(tok[1], p.type)) {
                        fail_header(line_no, "unknown type " + quote(tok[1]));
                    }
                    p.name = std::string(tok[2]);
                }
                elements_.back().props.push_back(std::move(p));
            } else if (key == "end_header") {
                if (!have_format) fail_header(line_no, "end_header before a format line");
                body_ = pos;
                header_lines_ = line_no;
                return;
            } else {
                fail_header(line_no, "unknown keyword " + quote(key));
            }
        }
    }

    // ---- body -----------------------------------------------------------------------------
    void body() {
        // Locate what we need before reading anything.
        for (std::size_t e = 0; e < elements_.size(); ++e) {
            const Element& el = elements_[e];
            if (el.name == "vertex") {
                vertex_elem_ = e;
                for (std::size_t i = 0; i < el.props.size(); ++i) {
                    const Property& p = el.props[i];
                    int axis = p.name == "x" ? 0 : p.name == "y" ? 1 : p.name == "z" ? 2 : -1;
                    if (axis < 0) continue;
                    if (p.is_list)
                        fail_header(el.header_line, "vertex property " + p.name + " is a list");
                    xyz_[axis] = static_cast<int>(i);
                }
                for (int a = 0; a < 3; ++a) {
                    if (xyz_[a] < 0) {
                        fail_header(el.header_line, std::string("vertex element has no '") +
                                                        "xyz"[a] + "' property");
                    }
                }
            } else if (el.name == "face") {
                face_elem_ = e;
                for (std::size_t i = 0; i < el.props.size(); ++i) {
                    const Property& p = el.props[i];
                    if (p.name == "vertex_indices" || p.name == "vertex_index") {
                        if (!p.is_list) fail_header(el.header_line, p.name + " is not a list");
                        if (face_prop_ >= 0) fail_header(el.header_line, "two vertex index lists");
                        face_prop_ = static_cast<int>(i);
                    }
                }
                if (face_prop_ < 0) {
                    fail_header(el.header_line, "face element has no vertex_indices list");
                }
            }
        }
        if (vertex_elem_ == kNone) fail("no vertex element");
        if (face_elem_ == kNone) fail("no face element (a point cloud is not a mesh)");
        check_room();
        vertex_count_ = elements_[vertex_elem_].count;
        if (vertex_count_ > static_cast<std::uint64_t>(INT_MAX)) fail("too many vertices");

        pos_ = body_;
        line_ = header_lines_ + 1;
        for (std::size_t e = 0; e < elements_.size(); ++e) {
            elem_ = &elements_[e];
            if (e == vertex_elem_) {
                mesh_.vertices.reserve(static_cast<std::size_t>(elem_->count));
            } else if (e == face_elem_) {
                face_start_.reserve(static_cast<std::size_t>(elem_->count) + 1);
            }
            if (elem_->props.empty()) continue;  // nothing to read, whatever the count
            for (item_ = 0; item_ < elem_->count; ++item_) {
                read_item(e);
            }
        }
        face_start_.push_back(face_index_.size());
    }

    // Minimum bytes every element needs, checked for the whole body before any allocation so
    // that a header claiming billions of items in a small file fails at once, clearly.
    void check_room() {
        const std::uint64_t left = data_.size() - body_;
        // An ASCII file may lack the final separator.
        const std::uint64_t avail = format_ == Format::Ascii ? left + 1 : left;
        std::uint64_t used = 0;
        for (const Element& el : elements_) {
            if (el.props.empty() || el.count == 0) continue;
            std::uint64_t min_item = 0;
            for (const Property& p : el.props) {
                // ASCII: one digit and one separator, even for an empty list.
                min_item +=
                    format_ == Format::Ascii ? 2 : type_size(p.is_list ? p.count_type : p.type);
            }
            if (el.count > (avail - used) / min_item) {
                fail("element '" + el.name + "' (header line " + std::to_string(el.header_line) +
                     ") declares " + std::to_string(el.count) + " items needing at least " +
                     std::to_string(min_item) + " bytes each, but only " +
                     std::to_string(left > used ? left - used : 0) +
                     " bytes are left for it (truncated file?)");
            }
            used += el.count * min_item;
        }
    }

    void read_item(std::size_t e) {
        double xyz[3] = {0, 0, 0};
        for (std::size_t i = 0; i < elem_->props.size(); ++i) {
            const Property& p = elem_->props[i];
            if (!p.is_list) {
                const double v = scalar(p.type);
                if (e == vertex_elem_) {
                    for (int a = 0; a < 3; ++a) {
                        if (xyz_[a] == static_cast<int>(i)) xyz[a] = v;
                    }
                }
                continue;
            }
            const double cnt = scalar(p.count_type);
            if (cnt < 0)
                fail_item("negative list length " + std::to_string(static_cast<long long>(cnt)));
            const auto n = static_cast<std::uint64_t>(cnt);
            // Each item needs type_size bytes (binary) or >= 2 bytes (ASCII) of what is left.
            const std::uint64_t left = data_.size() - pos_;
            const std::uint64_t per = format_ == Format::Ascii ? 2 : type_size(p.type);
            if (n > (left + (format_ == Format::Ascii ? 1 : 0)) / per) {
                fail_item("list of " + std::to_string(n) + " items runs past the end of the file");
            }
            const bool is_face = e == face_elem_ && static_cast<int>(i) == face_prop_;
            if (is_face) {
                if (n < 3)
                    fail_item("face with " + std::to_string(n) + " vertices (need at least 3)");
                face_start_.push_back(face_index_.size());
            }
            for (std::uint64_t k = 0; k < n; ++k) {
                const double v = scalar(p.type);
                if (!is_face) continue;
                if (!std::isfinite(v) || v != std::floor(v)) {
                    fail_item("vertex index " + std::to_string(v) + " is not an integer");
                }
                if (v < 0 || v >= static_cast<double>(vertex_count_)) {
                    fail_item("vertex index " + std::to_string(static_cast<long long>(v)) +
                              " out of range (" + std::to_string(vertex_count_) + " vertices)");
                }
                face_index_.push_back(static_cast<int>(v));
            }
        }
        if (e == vertex_elem_) {
            for (double c : xyz) {
                if (!std::isfinite(c) || std::abs(c) > 1e30) {
                    fail_item("non-finite or out-of-range coordinate " + std::to_string(c));
                }
            }
            mesh_.vertices.emplace_back(static_cast<float>(xyz[0]), static_cast<float>(xyz[1]),
                                        static_cast<float>(xyz[2]));
        }
    }

    double scalar(Type t) { return format_ == Format::Ascii ? ascii_scalar(t) : binary_scalar(t); }

    double binary_scalar(Type t) {
        const std::size_t n = type_size(t);
        if (data_.size() - pos_ < n) {
            fail_item("truncated: binary data ends at byte " + std::to_string(data_.size()));
        }
        std::uint64_t u = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const auto b = static_cast<unsigned char>(data_[pos_ + i]);
            const std::size_t shift = format_ == Format::BinaryLE ? i : n - 1 - i;
            u |= static_cast<std::uint64_t>(b) << (8 * shift);
        }
        pos_ += n;
        switch (t) {
            case Type::I8:
                return static_cast<std::int8_t>(static_cast<std::uint8_t>(u));
            case Type::U8:
                return static_cast<double>(u);
            case Type::I16:
                return static_cast<std::int16_t>(static_cast<std::uint16_t>(u));
            case Type::U16:
                return static_cast<double>(u);
            case Type::I32:
                return static_cast<std::int32_t>(static_cast<std::uint32_t>(u));
            case Type::U32:
                return static_cast<double>(u);
            case Type::F32: {
                const auto u32 = static_cast<std::uint32_t>(u);
                float f;
                std::memcpy(&f, &u32, sizeof f);
                return f;
            }
            case Type::F64: {
                double d;
                std::memcpy(&d, &u, sizeof d);
                return d;
            }
        }
        return 0;
    }

    double ascii_scalar(Type t) {
        // Next whitespace-separated token, counting lines for error messages.
        while (pos_ < data_.size() && (detail::is_space(data_[pos_]) || data_[pos_] == '\n')) {
            if (data_[pos_] == '\n') ++line_;
            ++pos_;
        }
        if (pos_ >= data_.size()) fail_item("truncated: file ends inside the element");
        std::size_t end = pos_;
        while (end < data_.size() && !detail::is_space(data_[end]) && data_[end] != '\n') ++end;
        const std::string_view tok = data_.substr(pos_, end - pos_);
        pos_ = end;
        if (is_integer(t)) {
            auto v = detail::parse_int(tok);
            if (!v) fail_item("malformed integer " + quote(tok));
            return static_cast<double>(*v);
        }
        auto v = detail::parse_double(tok);
        if (!v) fail_item("malformed number " + quote(tok));
        return *v;
    }

    Mesh build() {
        mesh_.name = name_;
        const std::size_t faces = face_start_.size() - 1;
        for (std::size_t f = 0; f < faces; ++f) {
            const std::size_t b = face_start_[f], e = face_start_[f + 1];
            for (std::size_t k = b + 1; k + 1 < e; ++k) {
                append_triangle(mesh_, face_index_[b], face_index_[k], face_index_[k + 1],
                                materials_.fallback, stats_);
            }
        }
        return std::move(mesh_);
    }

    static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

    std::string_view data_;
    const std::string& name_;
    const MaterialBinding& materials_;
    LoadStats& stats_;

    Format format_ = Format::Ascii;
    std::vector<Element> elements_;
    std::size_t body_ = 0;
    std::size_t header_lines_ = 0;
    std::size_t vertex_elem_ = kNone, face_elem_ = kNone;
    int xyz_[3] = {-1, -1, -1};
    int face_prop_ = -1;
    std::uint64_t vertex_count_ = 0;

    std::size_t pos_ = 0;
    std::size_t line_ = 0;
    const Element* elem_ = nullptr;
    std::uint64_t item_ = 0;

    Mesh mesh_;
    std::vector<int> face_index_;
    std::vector<std::size_t> face_start_;
};

}  // namespace

Mesh parse_ply(std::string_view bytes, const std::string& name, const MaterialBinding& materials,
               LoadStats& stats) {
    return PlyParser(bytes, name, materials, stats).run();
}

Mesh read_ply(const std::string& path, const MaterialBinding& materials, LoadStats& stats) {
    const std::string bytes = read_file_bytes(path, "ply");
    return parse_ply(bytes, path, materials, stats);
}

}  // namespace mirage::scene
