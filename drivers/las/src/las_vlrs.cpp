// SPDX-License-Identifier: Apache-2.0
#include "las_vlrs.hpp"

#include <algorithm>
#include <cstring>
#include <limits>

#include "las_layout.hpp"
#include "mirage/core/error.hpp"

namespace mirage::las {
namespace {

using namespace layout;

std::vector<std::uint8_t> vlr(const char* user, std::uint16_t id, const char* description,
                              std::size_t payload) {
    std::vector<std::uint8_t> v(kVlrHeaderSize + payload, 0);
    put_text(v.data() + 2, 16, user);
    put_u16(v.data() + 18, id);
    put_u16(v.data() + 20, static_cast<std::uint16_t>(payload));
    put_text(v.data() + 22, 32, description);
    return v;
}

// One float extra-bytes descriptor (Table 24): data type 9, no options.
void put_float_field(std::uint8_t* d, const char* name, const char* description) {
    d[2] = 9;
    put_text(d + 4, 32, name);
    put_text(d + 160, 32, description);
}

}  // namespace

std::vector<std::uint8_t> wkt_vlr(const std::string& wkt, const std::string& prefix) {
    if (wkt.size() + 1 > std::numeric_limits<std::uint16_t>::max())
        throw ConfigError(prefix + "WKT longer than a VLR can hold");
    auto v = vlr("LASF_Projection", kWktRecordId, "OGC WKT coordinate system", wkt.size() + 1);
    std::memcpy(v.data() + kVlrHeaderSize, wkt.data(), wkt.size());
    return v;
}

std::vector<std::uint8_t> waveform_descriptor_vlr(const WaveformPackets& w) {
    auto v = vlr("LASF_Spec", kWaveformDescriptorRecordId, "Waveform packet descriptor",
                 kWaveDescriptorSize);
    std::uint8_t* d = v.data() + kVlrHeaderSize;
    d[0] = w.bits;
    d[1] = 0;  // no compression
    put_u32(d + 2, w.samples);
    put_u32(d + 6, w.spacing_ps);
    put_f64(d + 10, w.gain);
    put_f64(d + 18, w.offset);
    return v;
}

std::vector<std::uint8_t> echo_extra_bytes_vlr() {
    auto v = vlr("LASF_Spec", kExtraBytesRecordId, "Waveform echo fields",
                 3 * kExtraBytesDescriptorSize);
    std::uint8_t* d = v.data() + kVlrHeaderSize;
    put_float_field(d, "amplitude", "echo peak above baseline [counts]");
    put_float_field(d + kExtraBytesDescriptorSize, "echo width", "fitted Gaussian sigma [ns]");
    put_float_field(d + 2 * kExtraBytesDescriptorSize, "deviation",
                    "RMS of samples about the fit [counts]");
    return v;
}

}  // namespace mirage::las
