// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "mirage/core/time.hpp"

// Duration arithmetic shared by the pose buffer and the track gate (internal).
namespace mirage::navpose::detail {

inline double seconds(core::Nanos d) { return double(d.count()) * 1e-9; }

}  // namespace mirage::navpose::detail
