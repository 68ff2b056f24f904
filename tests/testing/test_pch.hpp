// SPDX-License-Identifier: Apache-2.0
// The precompiled header of every test (tests/CMakeLists.txt, docs/testing.md §1): GoogleTest,
// Eigen and the standard headers most tests include. Parsing them took about half of a test
// file's compile time; this header is parsed once per build. It adds nothing a test relies on:
// each test file still includes what it uses.
#pragma once
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>
