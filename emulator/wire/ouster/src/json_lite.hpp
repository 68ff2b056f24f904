// SPDX-License-Identifier: Apache-2.0
#pragma once
// A small JSON reader for sensor metadata (no JSON library is a project dependency). Values are
// kept as parsed; numbers as double. Objects keep their key order.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace mirage::ouster::json {

struct Member;

struct Value {
    enum class Kind { Null, Bool, Number, String, Array, Object } kind = Kind::Null;
    bool boolean = false;
    double number = 0;
    std::string text;
    std::vector<Value> items;
    std::vector<Member> members;  // vector of an incomplete type: allowed since C++17

    const Value* find(std::string_view key) const;  // objects only; nullptr when absent
};

struct Member {
    std::string key;
    Value value;
};

// Throws std::runtime_error("line L: <problem>") on malformed input (callers rewrap).
Value parse(std::string_view text);

}  // namespace mirage::ouster::json
