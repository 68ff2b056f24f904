// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cstdint>
#include <optional>

namespace mirage::nav {

// The lower envelope of a delay-like value (arrival − sender time): the smallest over the
// current and the previous block of `block_ns`, so it follows a slow drift between the two
// clocks while ignoring messages that arrived late (docs/nav-protocols.md §12.3).
class LowerEnvelope {
  public:
    explicit LowerEnvelope(std::int64_t block_ns) : block_ns_(block_ns) {}

    // `value` seen at host time `at_ns`; returns the envelope.
    std::int64_t add(std::int64_t value, std::int64_t at_ns) {
        if (!value_) {
            block_min_ = prev_block_min_ = value;
            block_start_ = at_ns;
        }
        if (at_ns - block_start_ > block_ns_) {
            prev_block_min_ = block_min_;
            block_min_ = value;
            block_start_ = at_ns;
        }
        block_min_ = std::min(block_min_, value);
        value_ = std::min(prev_block_min_, block_min_);
        return *value_;
    }
    std::optional<std::int64_t> value() const { return value_; }

  private:
    std::int64_t block_ns_;
    std::int64_t block_min_ = 0, prev_block_min_ = 0, block_start_ = 0;
    std::optional<std::int64_t> value_;
};

}  // namespace mirage::nav
