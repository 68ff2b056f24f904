// SPDX-License-Identifier: Apache-2.0
// libFuzzer: trajectory CSV text. Byte 0 picks the scene georeference (bits 0-1: none, UTM 32N
// with an anchor, geodetic anchor) and the interpolation (bit 2: cubic). Bad content must end in
// ConfigError; an accepted trajectory must give finite poses with unit attitudes.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/core/trajectory.hpp"

namespace {

using namespace mirage::core;

const Georef& georef(std::uint8_t which) {
    static const Georef none{};
    static const Georef utm = Georef::projected(32632, {500000, 5000000, 0});
    static const Georef geo = Georef::geodetic(47.0, 8.0, 400.0);
    return which == 1 ? utm : which == 2 ? geo : none;
}

void check(const Pose& p) {
    if (!p.position.allFinite() || std::abs(p.attitude.norm() - 1.0) > 1e-6) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const auto interp = (data[0] & 4) != 0 ? Interpolation::Cubic : Interpolation::Linear;
    const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
    try {
        const Trajectory t = parse_trajectory_csv(text, "fuzz.csv", georef(data[0] & 3), interp);
        // Inside [begin, end] (quarters of the span) and held outside it, without overflowing
        // the time arithmetic of this harness near the ends of int64 ns.
        const auto span = t.end() - t.begin();
        for (int k = 0; k <= 4; ++k) check(t.at(t.begin() + span / 4 * k));
        const GpsTime lo = t.begin(), hi = t.end();
        if (lo.time_since_epoch() > GpsTime::duration::min() + Nanos(1)) check(t.at(lo - Nanos(1)));
        if (hi.time_since_epoch() < GpsTime::duration::max() - Nanos(1)) check(t.at(hi + Nanos(1)));
    } catch (const mirage::ConfigError&) {
    }
    return 0;
}
