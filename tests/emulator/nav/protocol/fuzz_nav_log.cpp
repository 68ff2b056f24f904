// SPDX-License-Identifier: Apache-2.0
// libFuzzer: recorded navigation logs through navproto::read_nav_log (from an in-memory file) and
// the trajectory built from them. Byte 0 picks the protocol (NMEA, NovAtel, NCOM, OxTS CAN,
// SBG CAN; CAN logs are candump text); the rest is the log. Nothing may be thrown but the
// documented "no usable pose" ConfigError.
#include <cstddef>
#include <cstdint>

#include "fuzz_file.hpp"
#include "mirage/core/error.hpp"
#include "mirage/navproto/nav_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace mirage::navproto;
    if (size == 0) return 0;
    static mirage::testing::FuzzFile file;
    static const auto frame = mirage::navpose::NavFrame::tangent_plane(47.0, 8.0, 400.0);
    const auto protocol = static_cast<NavProtocol>(data[0] % 5);
    NavLogOptions options;
    options.nmea_date = "2024-03-01";  // not the host's date: the same input, the same run
    const NavLog log = read_nav_log(file.write(data + 1, size - 1), protocol, options);
    if (log.stats.bytes != size - 1 || log.samples.size() > log.stats.samples) __builtin_trap();
    (void)nav_log_summary(log);
    try {
        (void)nav_log_trajectory(log, frame);
    } catch (const mirage::ConfigError&) {
    }
    return 0;
}
