// SPDX-License-Identifier: Apache-2.0
// libFuzzer target (Clang): clang++ -fsanitize=fuzzer,address,undefined. NmeaDecoder::feed must
// take any bytes, in any split, without reading out of bounds, throwing or emitting a sample
// with non-finite values; one-shot framing and the typed parsers likewise.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "mirage/nmea/nmea_decoder.hpp"
#include "mirage/nmea/sentence.hpp"
#include "mirage/nmea/sentences.hpp"

namespace {

void check(const mirage::nav::NavSample& s) {
    const double pi2 = 2.0 * 3.14159265358979323846;
    const bool bad = !std::isfinite(s.lat_deg) || !std::isfinite(s.lon_deg) ||
                     !std::isfinite(s.height_m) || !s.velocity_ned_mps.allFinite() ||
                     !std::isfinite(s.roll_rad) || !std::isfinite(s.pitch_rad) ||
                     !(s.heading_rad >= 0.0 && s.heading_rad < pi2) ||
                     std::fabs(s.lat_deg) > 90.0 || std::fabs(s.lon_deg) > 180.0;
    if (bad) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace mirage::nmea;
    const std::span<const std::uint8_t> all(data, size);

    // Whole input at once, then the same input in two pieces split at a data-chosen point.
    NmeaDecoder a, b;
    b.set_date_hint(Date{2014, 2, 19});
    a.feed(all, check);
    const std::size_t cut = size == 0 ? 0 : data[0] % (size + 1);
    b.feed(all.first(cut), check);
    b.feed(all.subspan(cut), check);
    if (a.counters().messages_ok != b.counters().messages_ok) std::abort();

    // The input as one line through the framer and the parser of its type.
    Sentence s;
    const std::string_view line(reinterpret_cast<const char*>(data), size);
    if (parse_sentence(line, s) == FrameStatus::Ok) {
        Gga g;
        Rmc r;
        Vtg v;
        Hdt h;
        Zda z;
        Pashr p;
        PtnlAvr t;
        (void)parse_gga(s, g);
        (void)parse_rmc(s, r);
        (void)parse_vtg(s, v);
        (void)parse_hdt(s, h);
        (void)parse_zda(s, z);
        (void)parse_pashr(s, p);
        (void)parse_ptnl_avr(s, t);
    }
    return 0;
}
