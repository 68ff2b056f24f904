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

// One extra-bytes descriptor (Table 24) of a data type (1 u8, 5 u32, 9 f32, 10 f64), no options.
void put_field(std::uint8_t* d, std::uint8_t type, const char* name, const char* description) {
    d[2] = type;
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

std::vector<std::uint8_t> extra_bytes_vlr(bool echo, bool events) {
    const std::size_t fields = (echo ? 3 : 0) + (events ? 3 : 0);
    auto v = vlr("LASF_Spec", kExtraBytesRecordId,
                 echo && events ? "Echo and photon-event fields"
                 : echo         ? "Waveform echo fields"
                                : "Photon-event fields",
                 fields * kExtraBytesDescriptorSize);
    std::uint8_t* d = v.data() + kVlrHeaderSize;
    if (echo) {
        put_field(d, 9, "amplitude", "echo peak above baseline [counts]");
        put_field(d += kExtraBytesDescriptorSize, 9, "echo width", "fitted Gaussian sigma [ns]");
        put_field(d += kExtraBytesDescriptorSize, 9, "deviation",
                  "RMS of samples about the fit [counts]");
        d += kExtraBytesDescriptorSize;
    }
    if (events) {
        put_field(d, 5, "pixel", "array pixel: column + row * columns");
        put_field(d += kExtraBytesDescriptorSize, 1, "event",
                  "1 signal 2 noise 3 afterpulse 4 xtalk");
        put_field(d += kExtraBytesDescriptorSize, 10, "time of flight", "since emission [ns]");
    }
    return v;
}

}  // namespace mirage::las
