// SPDX-License-Identifier: Apache-2.0
// Reading the report files the benchmarks write (report.json, streams.json).
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace mirage::test {

// The whole file ("" when it cannot be read).
inline std::string read_text(const std::string& path) {
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// A figure that must have been measured: present (at() throws otherwise), a number (the reports
// write null for NaN) and finite.
inline double measured(const nlohmann::json& j, const char* key) {
    const nlohmann::json& v = j.at(key);
    EXPECT_TRUE(v.is_number()) << key << " = " << v.dump();
    const double x = v.is_number() ? v.get<double>() : std::nan("");
    EXPECT_TRUE(std::isfinite(x)) << key;
    return x;
}

}  // namespace mirage::test
