// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the Ouster decoders on arbitrary bytes (issue 3 item 8). The first byte picks
// the profile and beam count; the rest is the datagram. Built with Clang only:
//   -fsanitize=fuzzer,address,undefined; run e.g. `fuzz_ouster_decode -max_total_time=60`.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "mirage/ouster/decoder.hpp"

namespace {

using namespace mirage::ouster;

const std::vector<Decoder>& decoders() {
    static std::vector<Decoder> all = [] {
        std::vector<Decoder> v;
        for (Profile p : {Profile::Legacy, Profile::Rng19Rfl8Sig16Nir16, Profile::Rng15Rfl8Nir8})
            for (int beams : {32, 64, 128})
                v.emplace_back(make_descriptor(ProductLine::OS1, beams, {1024, 10}, p));
        return v;
    }();
    return all;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    static std::vector<Decoder> decs = decoders();
    Decoder& dec = decs[data[0] % decs.size()];
    const std::span<const std::uint8_t> bytes(data + 1, size - 1);
    const DecodeStatus s = dec.decode(bytes);
    if (s == DecodeStatus::Ok) {
        std::vector<OusterPoint> pts;
        dec.points(PointFrame::Sensor, pts);
        if (pts.size() > std::size_t{dec.descriptor().beams} * dec.descriptor().columns_per_packet)
            __builtin_trap();
    }
    ImuPacket imu;
    dec.decode_imu(bytes, imu);
    return 0;
}
