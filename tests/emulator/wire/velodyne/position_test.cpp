// SPDX-License-Identifier: Apache-2.0
// Position packets (docs/wire-formats.md §1.9): $GPRMC, layouts, rate.
#include <gtest/gtest.h>

#include <atomic>

#include "mirage/velodyne/packetizer.hpp"
#include "mirage/velodyne/position_packet.hpp"
#include "mirage/velodyne/sensor_clock.hpp"
#include "velodyne_test_util.hpp"

namespace mirage::velodyne {
namespace {

TEST(VelodynePosition, gprmc_checksum_of_a_known_sentence) {
    // The HDL-32E capture's sentence (docs/wire-formats.md §6).
    const std::string s =
        "$GPRMC,220243,A,3708.5809,N,12139.7813,W,028.8,158.3,111212,013.8,E,D*03";
    EXPECT_EQ(nmea_checksum(s), 0x03);
    EXPECT_EQ(nmea_checksum("GPRMC,220243,A,3708.5809,N,12139.7813,W,028.8,158.3,111212,013.8,E,D"),
              0x03);
}

TEST(VelodynePosition, gprmc_sentence_from_the_sensor_clock_and_position) {
    // 2012-12-11 22:02:43.75 UTC, 37°08.5809' N, 121°39.7813' W.
    const core::GpsTime t = core::parse_time("2012-12-11T22:02:43.75Z");
    const GeoFix fix{37.0 + 8.5809 / 60.0, -(121.0 + 39.7813 / 60.0), 0, 0, true};
    EXPECT_EQ(gprmc_sentence(t, fix),
              "$GPRMC,220243,A,3708.5809,N,12139.7813,W,000.0,000.0,111212,,,A*6A");
    const GeoFix south{-33.8568, 151.2153, 12.34, 359.96, true};
    const std::string s = gprmc_sentence(core::parse_time("2024-02-29T23:59:59Z"), south);
    EXPECT_EQ(s.substr(0, 54), "$GPRMC,235959,A,3351.4080,S,15112.9180,E,012.3,000.0,2");
    EXPECT_EQ(nmea_checksum(s), std::stoi(s.substr(s.size() - 2), nullptr, 16));
}

TEST(VelodynePosition, every_layout_round_trips_through_the_decoder) {
    const core::GpsTime t = core::parse_time("2021-07-04T16:20:31.123456Z");
    const GeoFix fix{52.520008, 13.404954, 5.0, 90.0, true};
    for (PositionLayout layout :
         {PositionLayout::Vlp16, PositionLayout::Vlp32c, PositionLayout::Hdl32e}) {
        SCOPED_TRACE(static_cast<int>(layout));
        std::array<std::uint8_t, kPositionPacketSize> buf{};
        PositionPacketOptions o;
        o.pps = PpsStatus::Synchronizing;
        encode_position(layout, t, fix, o, buf);
        DecodedPosition d;
        ASSERT_EQ(decode_position(buf, d), PositionStatus::Ok);
        EXPECT_EQ(d.timestamp_us, 20u * 60'000'000u + 31'123'456u);
        EXPECT_EQ(d.pps, layout == PositionLayout::Hdl32e ? 0 : 1);  // HDL-32E: byte 202 unused
        ASSERT_TRUE(d.rmc);
        EXPECT_TRUE(d.fix_valid);
        EXPECT_EQ(d.hour, 16);
        EXPECT_EQ(d.minute, 20);
        EXPECT_EQ(d.second, 31);
        EXPECT_EQ(d.day, 4);
        EXPECT_EQ(d.month, 7);
        EXPECT_EQ(d.year, 2021);
        EXPECT_NEAR(d.lat_deg, fix.lat_deg, 1e-4 / 60.0);
        EXPECT_NEAR(d.lon_deg, fix.lon_deg, 1e-4 / 60.0);
        // CR LF after the sentence, zeros after it.
        const std::size_t end = kNmeaOffset + d.sentence.size();
        EXPECT_EQ(buf[end], '\r');
        EXPECT_EQ(buf[end + 1], '\n');
        EXPECT_EQ(buf[end + 2], 0);
    }
}

TEST(VelodynePosition, packetizer_sends_position_packets_at_the_model_rate) {
    for (Model m : {Model::Vlp16, Model::Vlp32c, Model::Hdl32e, Model::Hdl64eS3}) {
        const ModelDescriptor& md = descriptor(m);
        SCOPED_TRACE(std::string(md.name));
        std::vector<test::CollectedPacket> out;
        PacketizerOptions o;
        o.start = core::parse_time("2024-01-01T00:00:00Z");
        o.position = [&](core::GpsTime t) {
            // Moving north 1e-6° per ms.
            const double ms = static_cast<double>((t - o.start).count()) / 1e6;
            return GeoFix{10.0 + 1e-6 * ms, 20.0, 0, 0, true};
        };
        Packetizer pk(md, o, test::collect_into(out));
        const std::uint64_t packets =
            static_cast<std::uint64_t>(0.5 * md.packets_per_second(ReturnMode::Strongest));
        pk.advance_to(packets * pk.pulses_per_packet());
        std::uint64_t pos = 0;
        core::GpsTime prev{};
        for (const auto& p : out) {
            EXPECT_GE(p.time, prev);  // time order across both streams
            prev = p.time;
            if (p.stream != wire::Stream::Position) continue;
            DecodedPosition d;
            ASSERT_EQ(decode_position(p.bytes, d), PositionStatus::Ok);
            EXPECT_EQ(d.timestamp_us, micros_past_hour(p.time));
            EXPECT_NEAR(d.lat_deg,
                        10.0 + 1e-6 * static_cast<double>((p.time - o.start).count()) / 1e6, 2e-6);
            ++pos;
        }
        EXPECT_EQ(pos, pk.stats().position_packets);
        const double expected = md.position_period_ns > 0
                                    ? 0.5 * 1e9 / static_cast<double>(md.position_period_ns)
                                    : 0.0;
        std::printf("%-10s data %llu position %llu in 0.5 s\n", std::string(md.name).c_str(),
                    static_cast<unsigned long long>(pk.stats().data_packets),
                    static_cast<unsigned long long>(pos));
        EXPECT_NEAR(static_cast<double>(pos), expected, 1.0);
    }
}

// A real-time caller asks for the position packets due before the data packet it is about to
// render (docs/live-navigation.md §1): they come at once, none past that data packet's send time,
// and the stream (order, times, bytes) is the one emitted without asking.
TEST(VelodynePosition, side_packets_come_early_and_leave_the_stream_unchanged) {
    const ModelDescriptor& md = descriptor(Model::Vlp16);
    PacketizerOptions o;
    o.start = core::parse_time("2024-01-01T00:00:00Z");
    o.fixed_position = GeoFix{10.0, 20.0, 0, 0, true};
    std::vector<test::CollectedPacket> plain, early;
    Packetizer a(md, o, test::collect_into(plain));
    Packetizer b(md, o, test::collect_into(early));
    const std::uint64_t ppp = a.pulses_per_packet();
    std::uint64_t asked_and_came = 0;
    for (std::uint64_t k = 0; k < 800; ++k) {
        const std::size_t before = early.size();
        // Ask far beyond the packet: only what precedes its send time may come.
        b.emit_side_packets_until(b.packet_send_time(k) + std::chrono::seconds(1));
        for (std::size_t i = before; i < early.size(); ++i) {
            EXPECT_EQ(early[i].stream, wire::Stream::Position);
            EXPECT_LE(early[i].time, b.packet_send_time(k));
            EXPECT_GT(early[i].time, k ? b.packet_send_time(k - 1) : o.start - core::Nanos(1));
            ++asked_and_came;
        }
        a.advance_to((k + 1) * ppp);
        b.advance_to((k + 1) * ppp);
    }
    ASSERT_EQ(plain.size(), early.size());
    for (std::size_t i = 0; i < plain.size(); ++i) {
        EXPECT_EQ(plain[i].stream, early[i].stream) << i;
        EXPECT_EQ(plain[i].time, early[i].time) << i;
        EXPECT_EQ(plain[i].bytes, early[i].bytes) << i;
    }
    // Position packets at start + n·period up to the last data packet's send time.
    const auto span = (b.packet_send_time(799) - o.start).count();
    EXPECT_EQ(b.stats().position_packets,
              static_cast<std::uint64_t>(span / md.position_period_ns) + 1);
    EXPECT_GT(b.stats().position_packets, 50u);
    EXPECT_EQ(asked_and_came, b.stats().position_packets);
}

// A step of the clock source (docs/time.md §1): data, position and $GPRMC times jump by it from
// the next packet on; the send times (the firing schedule) do not.
TEST(VelodynePosition, clock_step_moves_every_timestamp_but_not_the_schedule) {
    const ModelDescriptor& md = descriptor(Model::Vlp16);
    std::vector<test::CollectedPacket> out;
    std::atomic<std::int64_t> step{0};
    PacketizerOptions o;
    o.start = core::parse_time("2024-01-01T00:10:00Z");
    o.fixed_position = GeoFix{10.0, 20.0, 0, 0, true};
    o.clock_step = &step;
    Packetizer pk(md, o, test::collect_into(out));
    const std::uint64_t n =
        static_cast<std::uint64_t>(md.packets_per_second(ReturnMode::Strongest));
    pk.advance_to(n / 2 * pk.pulses_per_packet());
    const std::size_t split = out.size();
    constexpr std::int64_t kStep = 2'500'000'000;
    step.store(kStep);
    pk.advance_to(n * pk.pulses_per_packet());
    int data_before = 0, data_after = 0, pos_after = 0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const auto& p = out[i];
        const std::int64_t shift = i < split ? 0 : kStep;
        const core::GpsTime stamped = p.time + core::Nanos(shift);
        if (p.stream == wire::Stream::Position) {
            DecodedPosition d;
            ASSERT_EQ(decode_position(p.bytes, d), PositionStatus::Ok);
            EXPECT_EQ(d.timestamp_us, micros_past_hour(stamped));
            const UtcFields u = utc_fields(stamped);
            EXPECT_EQ(d.second, u.second);
            EXPECT_EQ(d.minute, u.minute);
            pos_after += i >= split;
            continue;
        }
        // The schedule runs on: the send time is the closed form's, step or not.
        EXPECT_EQ(p.time, pk.packet_send_time(std::uint64_t(data_before + data_after)));
        DecodedPacket d;
        ASSERT_EQ(decode_data(p.bytes, &md, d), DecodeStatus::Ok);
        // Stamped at the first firing; sent after the last (one packet's span, under 1.4 ms).
        const std::int64_t lead_us =
            std::int64_t{micros_past_hour(stamped)} - std::int64_t{d.timestamp_us};
        EXPECT_GT(lead_us, 1000);
        EXPECT_LT(lead_us, 1400);
        (i < split ? data_before : data_after)++;
    }
    EXPECT_GT(data_before, 300);
    EXPECT_GT(data_after, 300);
    EXPECT_GT(pos_after, 20);  // VLP-16: one every 13.3 ms
}

}  // namespace
}  // namespace mirage::velodyne
