// SPDX-License-Identifier: Apache-2.0
// Open writers known to the SIGINT/SIGTERM finaliser (las_signal.cpp).
#pragma once

namespace mirage::las {

class LasWriter;

namespace detail {
// Returns false when the fixed-size table is full (the writer then works unprotected).
bool register_writer(LasWriter* w) noexcept;
void unregister_writer(LasWriter* w) noexcept;
}  // namespace detail

}  // namespace mirage::las
