// SPDX-License-Identifier: Apache-2.0
#include "mirage/velodyne/data_packet.hpp"

#include <cmath>
#include <numbers>
#include <numeric>

#include "byte_io.hpp"

namespace mirage::velodyne {

const char* to_string(DecodeStatus s) {
    switch (s) {
        case DecodeStatus::Ok:
            return "ok";
        case DecodeStatus::WrongSize:
            return "wrong size";
        case DecodeStatus::BadBlockFlag:
            return "bad block flag";
        case DecodeStatus::UnknownProduct:
            return "unknown product";
        case DecodeStatus::ProductMismatch:
            return "product mismatch";
        case DecodeStatus::BadReturnMode:
            return "bad return mode";
        case DecodeStatus::BadAzimuth:
            return "bad azimuth";
        case DecodeStatus::BadTimestamp:
            return "bad timestamp";
    }
    return "?";
}

std::uint64_t DecodeCounters::total() const {
    return std::accumulate(count.begin(), count.end(), std::uint64_t{0});
}

void encode_data(const RawDataPacket& p, std::span<std::uint8_t, kDataPacketSize> out) {
    std::uint8_t* o = out.data();
    for (std::size_t b = 0; b < kBlocksPerPacket; ++b) {
        std::uint8_t* blk = o + kBlockSize * b;
        const RawBlock& rb = p.block[b];
        detail::put_u16(blk, rb.flag);
        detail::put_u16(blk + 2, rb.azimuth);
        for (std::size_t c = 0; c < kSlotsPerBlock; ++c) {
            detail::put_u16(blk + 4 + 3 * c, rb.channel[c].distance);
            blk[6 + 3 * c] = rb.channel[c].reflectivity;
        }
    }
    detail::put_u32(o + kTimestampOffset, p.timestamp_us);
    o[kFactoryOffset] = p.factory1;
    o[kFactoryOffset + 1] = p.factory2;
}

RawDataPacket parse_data(std::span<const std::uint8_t, kDataPacketSize> in) {
    RawDataPacket p;
    const std::uint8_t* i = in.data();
    for (std::size_t b = 0; b < kBlocksPerPacket; ++b) {
        const std::uint8_t* blk = i + kBlockSize * b;
        RawBlock& rb = p.block[b];
        rb.flag = detail::get_u16(blk);
        rb.azimuth = detail::get_u16(blk + 2);
        for (std::size_t c = 0; c < kSlotsPerBlock; ++c) {
            rb.channel[c].distance = detail::get_u16(blk + 4 + 3 * c);
            rb.channel[c].reflectivity = blk[6 + 3 * c];
        }
    }
    p.timestamp_us = detail::get_u32(i + kTimestampOffset);
    p.factory1 = i[kFactoryOffset];
    p.factory2 = i[kFactoryOffset + 1];
    return p;
}

namespace {

bool valid_return_mode(std::uint8_t b) { return b >= 0x37 && b <= 0x39; }

}  // namespace

DecodeStatus decode_data(std::span<const std::uint8_t> bytes, const ModelDescriptor* expected,
                         DecodedPacket& out) {
    // 1. Length: everything below reads inside these 1206 bytes.
    if (bytes.size() != kDataPacketSize) return DecodeStatus::WrongSize;
    const std::uint8_t* p = bytes.data();

    // 2. Block flags: all 0xEEFF, or 0xEEFF/0xDDFF alternating (HDL-64E).
    bool all_upper = true, upper_lower = true;
    for (std::size_t b = 0; b < kBlocksPerPacket; ++b) {
        const std::uint16_t flag = detail::get_u16(p + kBlockSize * b);
        all_upper = all_upper && flag == kUpperBlockFlag;
        upper_lower = upper_lower && flag == (b % 2 ? kLowerBlockFlag : kUpperBlockFlag);
    }
    const bool want64 = expected != nullptr && expected->blocks_per_sequence == 2;
    if (expected != nullptr ? !(want64 ? upper_lower : all_upper) : !(all_upper || upper_lower))
        return DecodeStatus::BadBlockFlag;

    // 3. Ids: product and return mode (HDL-64E: status bytes instead; dual from the azimuths).
    const std::uint8_t f1 = p[kFactoryOffset], f2 = p[kFactoryOffset + 1];
    const ModelDescriptor* model = nullptr;
    ReturnMode mode = ReturnMode::Strongest;
    if (upper_lower) {
        model = &descriptor(Model::Hdl64eS3);
        if (detail::get_u16(p + 2) == detail::get_u16(p + 2 * kBlockSize + 2))
            mode = ReturnMode::Dual;
    } else {
        const auto m = model_from_product_id(f2);
        if (!m) return DecodeStatus::UnknownProduct;
        model = &descriptor(*m);
        if (expected != nullptr && expected->model != *m) return DecodeStatus::ProductMismatch;
        if (!valid_return_mode(f1)) return DecodeStatus::BadReturnMode;
        mode = static_cast<ReturnMode>(f1);
    }

    // 4. Fields.
    std::array<std::uint16_t, kBlocksPerPacket> az{};
    for (std::size_t b = 0; b < kBlocksPerPacket; ++b) {
        az[b] = detail::get_u16(p + kBlockSize * b + 2);
        if (az[b] >= kAzimuthCounts) return DecodeStatus::BadAzimuth;
    }
    const ModelDescriptor& md = *model;
    if (mode == ReturnMode::Dual) {
        // Blocks holding the same sequence must share its azimuth.
        for (int b = 1; b < kBlocksPerPacket; ++b) {
            const int prev = b - (md.blocks_per_sequence == 2 ? 2 : 1);
            if (md.block_sequence(mode, b) == md.block_sequence(mode, prev) &&
                md.block_flag(b) == md.block_flag(prev) &&
                az[static_cast<std::size_t>(b)] != az[static_cast<std::size_t>(prev)])
                return DecodeStatus::BadAzimuth;
        }
    }
    const std::uint32_t ts = detail::get_u32(p + kTimestampOffset);
    if (ts >= 3'600'000'000u) return DecodeStatus::BadTimestamp;

    out.model = model;
    out.mode = mode;
    out.timestamp_us = ts;
    out.factory1 = f1;
    out.factory2 = f2;
    out.block_azimuth = az;

    // Rotor rate from the first and last block azimuths (mod 360°) over their sequence distance:
    // the per-block interpolation of §1.6 averaged over the packet.
    const double period = static_cast<double>(md.sequence_period_ns);
    const int q_last = md.block_sequence(mode, kBlocksPerPacket - 1);
    const int d_counts =
        (static_cast<int>(az[kBlocksPerPacket - 1]) - static_cast<int>(az[0]) + kAzimuthCounts) %
        kAzimuthCounts;
    const double deg_per_ns = q_last > 0 ? 0.01 * d_counts / (q_last * period) : 0.0;
    constexpr double kRad = std::numbers::pi / 180.0;

    for (int b = 0; b < kBlocksPerPacket; ++b) {
        const std::uint8_t* blk = p + kBlockSize * static_cast<std::size_t>(b);
        const int qb = md.block_sequence(mode, b);
        const double block_az = 0.01 * az[static_cast<std::size_t>(b)];
        for (int c = 0; c < kSlotsPerBlock; ++c) {
            const auto si = md.slot_info(mode, b, c);
            Firing& f = out.firing[static_cast<std::size_t>(kSlotsPerBlock * b + c)];
            const auto l = static_cast<std::size_t>(si.laser);
            const LaserInfo& li = md.laser[l];
            const std::int64_t t_block =
                (si.sequence - qb) * md.sequence_period_ns + li.firing_offset_ns;
            double a = block_az + deg_per_ns * static_cast<double>(t_block) + li.azimuth_offset_deg;
            a = std::fmod(a, 360.0);
            if (a < 0) a += 360.0;
            f.azimuth_deg = static_cast<float>(a);
            if (f.azimuth_deg >= 360.0f) f.azimuth_deg = 0.0f;
            f.raw_distance = detail::get_u16(blk + 4 + 3 * c);
            f.reflectivity = blk[6 + 3 * c];
            f.laser = static_cast<std::uint8_t>(si.laser);
            f.ret = static_cast<std::uint8_t>(si.ret);
            f.sequence = static_cast<std::uint8_t>(si.sequence);
            f.time_offset_ns = static_cast<std::int32_t>(si.sequence * md.sequence_period_ns +
                                                         li.firing_offset_ns);
            const double d = f.raw_distance * md.distance_lsb_m;
            f.distance_m = static_cast<float>(d);
            if (f.raw_distance == 0) {
                f.x = f.y = f.z = 0;
                continue;
            }
            const double el = li.elevation_deg * kRad, ar = a * kRad;
            const double xy = d * std::cos(el);
            f.x = static_cast<float>(xy * std::cos(ar));
            f.y = static_cast<float>(-xy * std::sin(ar));
            f.z = static_cast<float>(d * std::sin(el));
        }
    }
    return DecodeStatus::Ok;
}

}  // namespace mirage::velodyne
