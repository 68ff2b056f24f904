// SPDX-License-Identifier: Apache-2.0
// libFuzzer: the Ouster lidar and IMU decoders on arbitrary bytes. Byte 0 picks the descriptor
// (profile × beams × columns per packet, fuzz_ouster_kinds.hpp) and, with bit 7 set, has the
// harness write a valid CRC-64 footer over the rest, so mutated columns get past the footer check
// into the column decoding. The rest is one datagram, decoded as a lidar and as an IMU packet; an
// input of several whole packets is also decoded packet by packet (measurement-ID gaps across
// packets).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "fuzz_ouster_kinds.hpp"
#include "mirage/ouster/decoder.hpp"

namespace {

using namespace mirage::ouster;

const std::vector<Descriptor>& kinds() { return test::fuzz_kinds(); }

void check_points(const Decoder& dec) {
    std::vector<OusterPoint> pts;
    dec.points(PointFrame::Sensor, pts);
    dec.points(PointFrame::Lidar, pts);
    const std::size_t most =
        std::size_t{dec.descriptor().beams} * dec.descriptor().columns_per_packet;
    if (pts.size() > 2 * most) __builtin_trap();
    for (const OusterPoint& p : pts)
        if (p.row >= dec.descriptor().beams || p.range_mm == 0) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const Descriptor& d = kinds()[(data[0] & 0x7F) % kinds().size()];
    std::vector<std::uint8_t> bytes(data + 1, data + size);
    const std::size_t n = d.packet_bytes();
    const bool whole_packets = !bytes.empty() && bytes.size() % n == 0;
    if ((data[0] & 0x80) != 0 && d.profile != Profile::Legacy && bytes.size() >= 8) {
        const std::size_t each = whole_packets ? n : bytes.size();
        for (std::size_t at = 0; at + each <= bytes.size(); at += each) {
            const std::uint64_t crc = crc64_xz({bytes.data() + at, each - 8});
            std::memcpy(bytes.data() + at + each - 8, &crc, 8);  // little-endian host
        }
    }
    Decoder dec(d);
    if (dec.decode(bytes) == DecodeStatus::Ok) check_points(dec);
    ImuPacket imu;
    (void)dec.decode_imu(bytes, imu);
    if (whole_packets && bytes.size() > n) {
        Decoder seq(d);
        for (std::size_t at = 0; at < bytes.size(); at += n)
            if (seq.decode(std::span(bytes).subspan(at, n)) == DecodeStatus::Ok) check_points(seq);
        const DecodeCounters& c = seq.counters();
        if (c.packets != bytes.size() / n) __builtin_trap();
    }
    return 0;
}
