// SPDX-License-Identifier: Apache-2.0
// Decoders on truncated, oversized, corrupted and foreign packets; the g++ fuzz corpus.
#include <gtest/gtest.h>

#include <random>

#include "fuzz_decode_one.hpp"
#include "mirage/velodyne/packetizer.hpp"
#include "velodyne_test_util.hpp"

namespace mirage::velodyne {
namespace {

std::vector<std::uint8_t> sample_packet(Model m, ReturnMode mode, int which = 1) {
    const ModelDescriptor& md = descriptor(m);
    const sensor::SensorModel s = test::preset_at(md, 600);
    std::vector<test::CollectedPacket> out;
    PacketizerOptions o;
    o.position_packets = false;
    Packetizer pk(md, mode, s, core::parse_time("2024-05-05T05:05:05Z"), test::collect_into(out),
                  o);
    const std::uint64_t n = 3 * pk.pulses_per_packet();
    test::SyntheticOptions so;
    so.max_range_m = 90;
    pk.add(test::synthetic_returns(*s.scan, n, {}, so));
    pk.advance_to(n);
    return out.at(static_cast<std::size_t>(which)).bytes;
}

std::vector<std::uint8_t> sample_position(PositionLayout layout) {
    std::vector<std::uint8_t> b(kPositionPacketSize);
    encode_position(layout, core::parse_time("2024-05-05T05:05:05Z"), GeoFix{48.1, 11.5}, {},
                    std::span<std::uint8_t, kPositionPacketSize>(b.data(), b.size()));
    return b;
}

DecodeStatus decode(const std::vector<std::uint8_t>& b, const ModelDescriptor* expected = nullptr) {
    DecodedPacket d;
    return decode_data(b, expected, d);
}

TEST(VelodyneBadInput, wrong_sizes_are_rejected_before_anything_is_read) {
    const auto good = sample_packet(Model::Vlp16, ReturnMode::Strongest);
    EXPECT_EQ(decode(good), DecodeStatus::Ok);
    for (std::size_t n : {0u, 1u, 100u, 1205u}) {
        // A heap copy of exactly n bytes, so ASan catches any read past it.
        std::vector<std::uint8_t> t(good.begin(), good.begin() + static_cast<long>(n));
        t.shrink_to_fit();
        EXPECT_EQ(decode(t), DecodeStatus::WrongSize) << n;
    }
    std::vector<std::uint8_t> big = good;
    big.push_back(0);
    EXPECT_EQ(decode(big), DecodeStatus::WrongSize);
    big.resize(1248);
    EXPECT_EQ(decode(big), DecodeStatus::WrongSize);
    const auto pos = sample_position(PositionLayout::Vlp16);
    EXPECT_EQ(decode(pos), DecodeStatus::WrongSize);
}

TEST(VelodyneBadInput, statuses_come_in_the_fixed_order_length_flags_ids_fields) {
    auto p = sample_packet(Model::Vlp16, ReturnMode::Strongest);
    auto bad_flag = p;
    bad_flag[700] = 0x00;  // block 7 flag low byte
    EXPECT_EQ(decode(bad_flag), DecodeStatus::BadBlockFlag);
    auto bad_product = p;
    bad_product[1205] = 0x99;
    EXPECT_EQ(decode(bad_product), DecodeStatus::UnknownProduct);
    auto bad_mode = p;
    bad_mode[1204] = 0x40;
    EXPECT_EQ(decode(bad_mode), DecodeStatus::BadReturnMode);
    auto bad_az = p;
    bad_az[302] = 0xA0;  // block 3 azimuth = 0x8CA0 = 36000
    bad_az[303] = 0x8C;
    EXPECT_EQ(decode(bad_az), DecodeStatus::BadAzimuth);
    auto bad_ts = p;
    bad_ts[1203] = 0xFF;
    EXPECT_EQ(decode(bad_ts), DecodeStatus::BadTimestamp);
    // Several faults at once: the first check in the order wins.
    auto many = bad_az;
    many[1204] = 0x40;
    EXPECT_EQ(decode(many), DecodeStatus::BadReturnMode);
    many[1205] = 0x99;
    EXPECT_EQ(decode(many), DecodeStatus::UnknownProduct);
    many[0] = 0;
    EXPECT_EQ(decode(many), DecodeStatus::BadBlockFlag);
    many.pop_back();
    EXPECT_EQ(decode(many), DecodeStatus::WrongSize);
    // Dual pairs must share one azimuth.
    auto dual = sample_packet(Model::Hdl32e, ReturnMode::Dual);
    EXPECT_EQ(decode(dual), DecodeStatus::Ok);
    dual[102] ^= 1;  // block 1 azimuth differs from block 0
    EXPECT_EQ(decode(dual), DecodeStatus::BadAzimuth);
}

TEST(VelodyneBadInput, packets_of_another_model_are_told_apart) {
    const auto v16 = sample_packet(Model::Vlp16, ReturnMode::Strongest);
    const auto v32 = sample_packet(Model::Vlp32c, ReturnMode::Dual);
    const auto h64 = sample_packet(Model::Hdl64eS3, ReturnMode::Strongest);
    const auto* md16 = &descriptor(Model::Vlp16);
    const auto* md64 = &descriptor(Model::Hdl64eS3);
    EXPECT_EQ(decode(v32, md16), DecodeStatus::ProductMismatch);
    EXPECT_EQ(decode(h64, md16), DecodeStatus::BadBlockFlag);
    EXPECT_EQ(decode(v16, md64), DecodeStatus::BadBlockFlag);
    DecodedPacket d;
    ASSERT_EQ(decode_data(h64, nullptr, d), DecodeStatus::Ok);
    EXPECT_EQ(d.model->model, Model::Hdl64eS3);
    ASSERT_EQ(decode_data(v32, nullptr, d), DecodeStatus::Ok);
    EXPECT_EQ(d.model->model, Model::Vlp32c);
    EXPECT_EQ(d.mode, ReturnMode::Dual);
    // HDL-64E status bytes: packet 1 of the cycle carries 'M' (minutes) = 5.
    EXPECT_EQ(h64[1204], 'M');
    EXPECT_EQ(h64[1205], 5);
    // Position packets are not data packets and vice versa.
    DecodedPosition p;
    EXPECT_EQ(decode_position(v16, p), PositionStatus::WrongSize);
}

TEST(VelodyneBadInput, position_decoder_checks_size_sentence_and_checksum) {
    auto p = sample_position(PositionLayout::Vlp16);
    DecodedPosition d;
    ASSERT_EQ(decode_position(p, d), PositionStatus::Ok);
    auto t = p;
    t.pop_back();
    EXPECT_EQ(decode_position(t, d), PositionStatus::WrongSize);
    auto no = p;
    no[206] = 'X';
    EXPECT_EQ(decode_position(no, d), PositionStatus::NoSentence);
    auto cs = p;
    cs[215] ^= 0x01;  // a character of the sentence
    EXPECT_EQ(decode_position(cs, d), PositionStatus::BadChecksum);
    auto unterminated = p;
    for (std::size_t i = 207; i < 512; ++i) unterminated[i] = 'A';
    EXPECT_EQ(decode_position(unterminated, d), PositionStatus::Unterminated);
    auto star_at_end = unterminated;
    star_at_end[511] = '*';
    EXPECT_EQ(decode_position(star_at_end, d), PositionStatus::Unterminated);
    auto ts = p;
    ts[201] = 0xFF;
    EXPECT_EQ(decode_position(ts, d), PositionStatus::BadTimestamp);
}

// g++ stand-in for the libFuzzer target: 20 000 random, truncated and bit-flipped inputs.
TEST(VelodyneFuzzCorpus, mutated_packets_always_get_a_status_and_counts_add_up) {
    std::vector<std::vector<std::uint8_t>> seeds;
    for (Model m : kAllModels)
        for (ReturnMode mode : kAllReturnModes) seeds.push_back(sample_packet(m, mode));
    for (PositionLayout l : {PositionLayout::Vlp16, PositionLayout::Vlp32c, PositionLayout::Hdl32e})
        seeds.push_back(sample_position(l));
    std::mt19937_64 rng(20240505);
    test::FuzzCounters c;
    std::uint64_t wrong_size_inputs = 0, inputs = 0;
    const int kInputs = 20'000;
    for (int i = 0; i < kInputs; ++i) {
        const auto& seed = seeds[rng() % seeds.size()];
        std::vector<std::uint8_t> in;
        switch (i % 4) {
            case 0: {  // random bytes, random length around the two packet sizes
                const std::size_t n = (rng() % 2) ? 1206 : rng() % 1400;
                in.resize(n);
                for (auto& b : in) b = static_cast<std::uint8_t>(rng());
                break;
            }
            case 1:  // truncated or extended seed
                in.assign(seed.begin(), seed.begin() + static_cast<long>(rng() % seed.size()));
                if (rng() % 2) in.resize(seed.size() + 1 + rng() % 64, 0xEE);
                break;
            default: {  // 1–8 bit flips
                in = seed;
                const int flips = 1 + static_cast<int>(rng() % 8);
                for (int f = 0; f < flips; ++f)
                    in[rng() % in.size()] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
                break;
            }
        }
        in.shrink_to_fit();
        if (in.size() != kDataPacketSize) ++wrong_size_inputs;
        ++inputs;
        test::fuzz_one(in, c);
    }
    EXPECT_EQ(c.data.total(), inputs);
    EXPECT_EQ(c.expected.total(), inputs * 5);
    EXPECT_EQ(c.position.total(), inputs);
    EXPECT_EQ(c.data[DecodeStatus::WrongSize], wrong_size_inputs);
    EXPECT_EQ(c.expected[DecodeStatus::WrongSize], 5 * wrong_size_inputs);
    // Bit flips in distances, reflectivities and timestamps leave packets valid.
    EXPECT_GT(c.data[DecodeStatus::Ok], 3'000u);
    EXPECT_GT(c.data[DecodeStatus::BadBlockFlag], 100u);
    EXPECT_GT(c.position[PositionStatus::BadChecksum], 100u);
    for (std::size_t s = 0; s < kDecodeStatusCount; ++s)
        std::printf("data %-17s %6llu\n", to_string(static_cast<DecodeStatus>(s)),
                    static_cast<unsigned long long>(c.data.count[s]));
    for (std::size_t s = 0; s < kPositionStatusCount; ++s)
        std::printf("position %-14s %6llu\n", to_string(static_cast<PositionStatus>(s)),
                    static_cast<unsigned long long>(c.position.count[s]));
}

}  // namespace
}  // namespace mirage::velodyne
