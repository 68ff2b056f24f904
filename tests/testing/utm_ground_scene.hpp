// SPDX-License-Identifier: Apache-2.0
#pragma once
// A flat 120 × 120 m ground in UTM 32N anchored at (500000, 5000000, 0): the smallest scene a
// navigation test can place an INS in (the fake INS needs a georeference to report WGS84).
namespace mirage::test {

inline constexpr const char* kUtmGroundScene =
    R"(georef: {epsg: 32632, anchor: [500000, 5000000, 0]}
materials:
  ground: {reflectance: 0.3, classification: 2}
objects:
  - {type: plane, material: ground, size: [120, 120]}
)";

}  // namespace mirage::test
