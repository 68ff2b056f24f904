// SPDX-License-Identifier: Apache-2.0
// Checked, typed reading of a YAML configuration file (scene files, rig files): every error is a
// ConfigError "<label>: <key path>: <problem> (line N)", e.g.
// "scene 'town.yaml': objects[2].size: expected 3 numbers (line 14)".
#pragma once
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace mirage::scene {

class YamlReader {
  public:
    // `label` opens every message: "scene 'town.yaml'", "rig 'bench.yaml'".
    explicit YamlReader(std::string label) : label_(std::move(label)) {}

    // `text`: the YAML itself, or nullptr to read `file`. Syntax errors name their line.
    YAML::Node load(const std::string& file, const std::string* text) const;

    [[noreturn]] void fail(const std::string& key, const std::string& msg,
                           const YAML::Node& at) const;
    static std::string sub(const std::string& path, std::string_view key);
    static std::string item(const std::string& path, std::size_t i);

    // Every key must be a known one, and appear once.
    void check_keys(const YAML::Node& map, const std::string& path,
                    std::initializer_list<std::string_view> allowed) const;
    void require_map(const YAML::Node& n, const std::string& path) const;
    double number(const YAML::Node& n, const std::string& path) const;
    double number_in(const YAML::Node& n, const std::string& path, double lo, double hi) const;
    double positive(const YAML::Node& n, const std::string& path) const;
    long long integer(const YAML::Node& n, const std::string& path, long long lo,
                      long long hi) const;
    bool boolean(const YAML::Node& n, const std::string& path) const;
    std::string string(const YAML::Node& n, const std::string& path) const;
    std::vector<double> numbers(const YAML::Node& n, const std::string& path,
                                std::size_t count) const;

  private:
    std::string label_;
};

}  // namespace mirage::scene
