// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <vector>

#include "mirage/nav/nav_sample.hpp"

namespace mirage::novatel {

struct EncoderOptions {
    std::uint8_t port_address = 0x20;  // COM1
    std::uint8_t time_status = 180;    // FINESTEERING
    std::uint32_t receiver_status = 0;
    std::uint16_t software_build = 0;
    // Geoid height N for the MSL heights of BESTPOS/INSPVAX (MSL = ellipsoidal − N).
    float undulation_m = 0.0F;
};

// Fake-INS encoders: whole frames (header + body + CRC). Header time = the sample's GPS time
// truncated to ms (INSPVAS carries the full seconds as f64 in its body). Fields the sample does
// not have are written as zeros.
class NovatelEncoder {
  public:
    explicit NovatelEncoder(EncoderOptions options = {}) : options_(options) {}

    std::vector<std::uint8_t> bestpos(const nav::NavSample& s);
    std::vector<std::uint8_t> inspvax(const nav::NavSample& s);
    std::vector<std::uint8_t> inspvas(const nav::NavSample& s);

  private:
    EncoderOptions options_;
};

}  // namespace mirage::novatel
