// SPDX-License-Identifier: Apache-2.0
#include "mirage/scene/yaml_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>

#include "mirage/core/error.hpp"
#include "text_util.hpp"

namespace mirage::scene {
namespace {

using detail::quote;

std::string join(std::initializer_list<std::string_view> keys) {
    std::string out;
    for (std::string_view k : keys) {
        if (!out.empty()) out += ", ";
        out += k;
    }
    return out;
}

std::string fmt_num(double v) {
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

}  // namespace

YAML::Node YamlReader::load(const std::string& file, const std::string* text) const {
    try {
        return text ? YAML::Load(*text) : YAML::LoadFile(file);
    } catch (const YAML::BadFile&) {
        throw ConfigError(label_ + ": cannot open file");
    } catch (const YAML::ParserException& e) {
        throw ConfigError(label_ + ": line " + std::to_string(e.mark.line + 1) +
                          ": YAML syntax error: " + e.msg);
    }
}

void YamlReader::fail(const std::string& key, const std::string& msg, const YAML::Node& at) const {
    std::string m = label_ + ": ";
    if (!key.empty()) m += key + ": ";
    m += msg;
    if (at.IsDefined() && !at.Mark().is_null()) {
        m += " (line " + std::to_string(at.Mark().line + 1) + ")";
    }
    throw ConfigError(m);
}

std::string YamlReader::sub(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : path + "." + std::string(key);
}
std::string YamlReader::item(const std::string& path, std::size_t i) {
    return path + "[" + std::to_string(i) + "]";
}

// Every key must be a known one, and appear once.
void YamlReader::check_keys(const YAML::Node& map, const std::string& path,
                            std::initializer_list<std::string_view> allowed) const {
    std::set<std::string> seen;
    for (const auto& kv : map) {
        const YAML::Node key = kv.first;
        if (!key.IsScalar()) fail(path, "keys must be plain strings", key);
        const std::string k = key.Scalar();
        if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) {
            fail(sub(path, k), "unknown key (allowed: " + join(allowed) + ")", key);
        }
        if (!seen.insert(k).second) fail(sub(path, k), "duplicate key", key);
    }
}

void YamlReader::require_map(const YAML::Node& n, const std::string& path) const {
    if (!n.IsMap()) fail(path, "expected a map", n);
}

double YamlReader::number(const YAML::Node& n, const std::string& path) const {
    if (!n.IsScalar()) fail(path, "expected a number", n);
    const std::string& s = n.Scalar();
    auto v = detail::parse_double(s);
    if (!v) {
        if (s == ".nan" || s == ".NaN" || s == ".NAN" || s == ".inf" || s == "-.inf" ||
            s == "+.inf" || s == ".Inf" || s == "-.Inf") {
            fail(path, "expected a finite number, got " + quote(s), n);
        }
        fail(path, "expected a number, got " + quote(s), n);
    }
    if (!std::isfinite(*v)) fail(path, "expected a finite number, got " + quote(s), n);
    return *v;
}

double YamlReader::number_in(const YAML::Node& n, const std::string& path, double lo,
                             double hi) const {
    const double v = number(n, path);
    if (v < lo || v > hi) {
        fail(path, "must be in [" + fmt_num(lo) + ", " + fmt_num(hi) + "], got " + n.Scalar(), n);
    }
    return v;
}

double YamlReader::positive(const YAML::Node& n, const std::string& path) const {
    const double v = number(n, path);
    if (v <= 0) fail(path, "must be positive, got " + n.Scalar(), n);
    return v;
}

long long YamlReader::integer(const YAML::Node& n, const std::string& path, long long lo,
                              long long hi) const {
    if (!n.IsScalar()) fail(path, "expected an integer", n);
    auto v = detail::parse_int(n.Scalar());
    if (!v) fail(path, "expected an integer, got " + quote(n.Scalar()), n);
    if (*v < lo || *v > hi) {
        fail(path,
             "must be in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + n.Scalar(),
             n);
    }
    return *v;
}

bool YamlReader::boolean(const YAML::Node& n, const std::string& path) const {
    if (!n.IsScalar()) fail(path, "expected true or false", n);
    const std::string& s = n.Scalar();
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
    fail(path, "expected true or false, got " + quote(s), n);
}

std::string YamlReader::string(const YAML::Node& n, const std::string& path) const {
    if (!n.IsScalar() || n.Scalar().empty()) fail(path, "expected a non-empty string", n);
    return n.Scalar();
}

std::vector<double> YamlReader::numbers(const YAML::Node& n, const std::string& path,
                                        std::size_t count) const {
    const std::string expect = "expected " + std::to_string(count) + " numbers";
    if (!n.IsSequence() || n.size() != count) fail(path, expect, n);
    std::vector<double> v;
    for (std::size_t i = 0; i < count; ++i) v.push_back(number(n[i], item(path, i)));
    return v;
}

}  // namespace mirage::scene
