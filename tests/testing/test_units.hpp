// SPDX-License-Identifier: Apache-2.0
// Unit constants shared by the tests (one definition, so that tests can share a unity build).
#pragma once
#include <cstdint>
#include <numbers>

#include "mirage/core/time.hpp"

namespace mirage::test {

inline constexpr double kDeg = std::numbers::pi / 180.0;  // one degree, rad
inline constexpr std::int64_t kS = core::kNsPerSecond;    // one second, ns

}  // namespace mirage::test
