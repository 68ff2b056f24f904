// SPDX-License-Identifier: Apache-2.0
#pragma once
// One fuzz input through both decoders, auto-detecting and with each expected model; shared by
// the libFuzzer target and the g++ corpus test.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "mirage/velodyne/data_packet.hpp"
#include "mirage/velodyne/packetizer.hpp"
#include "mirage/velodyne/position_packet.hpp"

namespace mirage::velodyne::test {

struct FuzzCounters {
    DecodeCounters data;      // auto-detect
    DecodeCounters expected;  // one per expected model
    PositionCounters position;
};

inline void fuzz_one(std::span<const std::uint8_t> bytes, FuzzCounters& c) {
    DecodedPacket d;
    const DecodeStatus s = decode_data(bytes, nullptr, d);
    c.data.add(s);
    if (s == DecodeStatus::Ok) {
        // Touch every decoded field so sanitizers see any uninitialised/out-of-range read.
        volatile float sink = 0;
        for (const Firing& f : d.firing) sink = sink + f.x + f.y + f.z + f.azimuth_deg;
        (void)sink;
    }
    for (Model m : kAllModels) c.expected.add(decode_data(bytes, &descriptor(m), d));
    DecodedPosition p;
    c.position.add(decode_position(bytes, p));
}

// Valid packets of every model × return mode and every position layout, built once.
inline const std::vector<std::vector<std::uint8_t>>& seed_packets() {
    static const std::vector<std::vector<std::uint8_t>> seeds = [] {
        std::vector<std::vector<std::uint8_t>> out;
        for (Model m : kAllModels)
            for (ReturnMode mode : kAllReturnModes) {
                PacketizerOptions o;
                o.mode = mode;
                o.position_packets = false;
                std::vector<std::uint8_t> first;
                Packetizer pk(descriptor(m), o, [&](const wire::PacketView& v) {
                    if (first.empty()) first.assign(v.bytes.begin(), v.bytes.end());
                });
                std::vector<core::PointRecord> pts(pk.pulses_per_packet());
                for (std::size_t k = 0; k < pts.size(); ++k) {
                    pts[k].pulse = k;
                    pts[k].channel = static_cast<std::uint16_t>(
                        k % static_cast<std::size_t>(descriptor(m).lasers));
                    pts[k].range_m = 1.0f + static_cast<float>(k % 97);
                    pts[k].intensity = static_cast<std::uint16_t>(k * 331);
                }
                pk.add(pts);
                pk.advance_to(pk.pulses_per_packet());
                out.push_back(first);
            }
        for (PositionLayout l :
             {PositionLayout::Vlp16, PositionLayout::Vlp32c, PositionLayout::Hdl32e}) {
            std::vector<std::uint8_t> b(kPositionPacketSize);
            encode_position(l, core::GpsTime{}, GeoFix{47.5, -122.3}, {},
                            std::span<std::uint8_t, kPositionPacketSize>(b.data(), b.size()));
            out.push_back(b);
        }
        return out;
    }();
    return seeds;
}

// Structured input for a coverage-guided fuzzer: byte 0 picks a seed packet, bytes 1–2 may
// resize it, then (offset lo, offset hi, xor) triples mutate it. Reaches the field checks that
// random bytes of random length rarely get to.
inline void fuzz_structured(std::span<const std::uint8_t> data, FuzzCounters& c) {
    if (data.size() < 3) return;
    const auto& seeds = seed_packets();
    std::vector<std::uint8_t> b = seeds[data[0] % seeds.size()];
    if (data[1] == 0xFF) b.resize(static_cast<std::size_t>(data[2]) * 5u);
    for (std::size_t i = 3; i + 2 < data.size() && !b.empty(); i += 3) {
        const std::size_t off = (data[i] | (static_cast<std::size_t>(data[i + 1]) << 8)) % b.size();
        b[off] = static_cast<std::uint8_t>(b[off] ^ data[i + 2]);
    }
    b.shrink_to_fit();
    fuzz_one(b, c);
}

}  // namespace mirage::velodyne::test
