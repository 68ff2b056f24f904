// SPDX-License-Identifier: Apache-2.0
// libFuzzer: sensor YAML text. Bad content must end in ConfigError; an accepted model must
// describe itself and fire finite, unit-length pulses with channels in range.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/sensor/sensor.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace mirage::sensor;
    SensorModel m;
    try {
        m = load_sensor_yaml_text(std::string(reinterpret_cast<const char*>(data), size),
                                  "fuzz.yaml");
    } catch (const mirage::ConfigError&) {
        return 0;
    }
    if (!m.scan) __builtin_trap();
    (void)describe(m);
    PulseSpec p[64];
    for (const std::uint64_t first : {std::uint64_t{0}, std::uint64_t{1} << 33}) {
        m.scan->pulses(first, 64, p);
        for (const PulseSpec& s : p)
            if (!s.dir.allFinite() || std::abs(s.dir.norm() - 1.0f) > 1e-3f ||
                s.channel >= m.scan->channels())
                __builtin_trap();
    }
    return 0;
}
