// SPDX-License-Identifier: Apache-2.0
// Packetizer → decoder round trips, closed-form timing, dropped packets, IMU interleaving.
#include "mirage/ouster/packetizer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <numbers>

#include "mirage/ouster/decoder.hpp"
#include "mirage/sensor/spinning.hpp"
#include "ouster_test_util.hpp"

namespace mirage::ouster {
namespace {

using test::Captured;

const core::GpsTime kStart = core::GpsTime(std::chrono::seconds(1'400'000'000));

PacketizerConfig config() {
    PacketizerConfig c;
    c.start = kStart;
    c.first_frame_id = 65530;  // wraps within the tests
    c.clock.mode = TimestampMode::InternalOsc;
    c.clock.power_on = kStart - std::chrono::seconds(765);
    return c;
}

double max_range_m(Profile p) { return p == Profile::Rng15Rfl8Nir8 ? 250.0 : 500.0; }

// Random returns → packets → decoder: every pixel equal within the profile's quantisation,
// measurement/frame IDs and timestamps equal to the closed forms.
TEST(OusterPacketizer, round_trip_every_profile_for_several_modes_and_beam_counts) {
    const struct {
        const char* preset;
    } cases[] = {{"os1-64-1024x10"}, {"os0-32-512x20"}, {"os2-128-2048x10"}, {"os1-128-512x10"}};
    for (Profile prof : {Profile::Legacy, Profile::Rng19Rfl8Sig16Nir16, Profile::Rng15Rfl8Nir8})
        for (const auto& cs : cases) {
            Descriptor d = make_descriptor(cs.preset, prof);
            d.beam_origin_mm = 0;  // pure quantisation round trip (correction tested below)
            const std::uint64_t H = d.beams, W = d.mode.columns;
            // 1.25 frames, at most 48 packets (frame wrap included for the small modes).
            const std::uint64_t packets =
                std::min<std::uint64_t>(48, (W + W / 4) / d.columns_per_packet);
            const std::uint64_t pulses = packets * d.columns_per_packet * H + H / 2;
            const auto pts = test::random_returns(d, pulses, max_range_m(prof), 99);
            std::vector<Captured> out;
            OusterPacketizer pk(d, config(), test::collect(out));
            test::packetize(pk, pts, pulses, 1000);
            ASSERT_EQ(out.size(), packets) << cs.preset;  // the partial packet is not sent

            std::map<std::uint64_t, const core::PointRecord*> by_pulse;
            for (const auto& p : pts) by_pulse[p.pulse] = &p;
            Decoder dec(d);
            const double q_mm = prof == Profile::Rng15Rfl8Nir8 ? 4.0 : 0.5;
            std::uint64_t checked = 0, bad = 0, returns = 0;
            for (std::size_t i = 0; i < out.size(); ++i) {
                ASSERT_EQ(out[i].stream, wire::Stream::Data);
                ASSERT_EQ(out[i].bytes.size(), d.packet_bytes());
                ASSERT_EQ(dec.decode(out[i].bytes), DecodeStatus::Ok) << cs.preset << " " << i;
                const auto& pk_in = dec.packet();
                for (std::size_t c = 0; c < d.columns_per_packet; ++c) {
                    const std::uint64_t s = i * d.columns_per_packet + c;
                    const auto& h = pk_in.columns[c];
                    EXPECT_EQ(h.measurement_id, s % W);
                    EXPECT_EQ(h.frame_id, std::uint16_t(65530 + s / W));
                    const auto t =
                        kStart + core::Nanos(std::llround(double(s) * d.column_period_ns()));
                    EXPECT_EQ(h.timestamp_ns,
                              std::uint64_t((t - (kStart - std::chrono::seconds(765))).count()));
                    for (std::size_t r = 0; r < H; ++r) {
                        const auto& px = pk_in.pixels[c * H + r];
                        const auto it = by_pulse.find(s * H + r);
                        ++checked;
                        if (it == by_pulse.end()) {
                            bad += px.range_mm != 0;
                            continue;
                        }
                        ++returns;
                        const auto& p = *it->second;
                        bad += std::abs(double(px.range_mm) - double(p.range_m) * 1000.0) > q_mm;
                        bad += px.reflectivity != (p.intensity >> 8);
                        if (prof != Profile::Rng15Rfl8Nir8) bad += px.signal != p.n_laser;
                    }
                }
                EXPECT_EQ(out[i].time,
                          kStart + core::Nanos(std::llround(double((i + 1) * d.columns_per_packet) *
                                                            d.column_period_ns())));
            }
            EXPECT_EQ(bad, 0u) << cs.preset << " " << to_string(prof);
            EXPECT_EQ(checked, packets * d.columns_per_packet * H);
            EXPECT_EQ(returns, std::uint64_t(std::count_if(pts.begin(), pts.end(), [&](auto& p) {
                          return p.pulse < packets * d.columns_per_packet * H;
                      })));
            EXPECT_EQ(pk.stats().returns, pts.size());  // the partial packet's too (not sent)
            EXPECT_EQ(dec.counters().measurement_id_gaps, 0u);
            EXPECT_EQ(dec.counters().missing_columns, 0u);
        }
}

TEST(OusterPacketizer, column_times_match_the_preset_pattern_and_closed_form) {
    const auto model = sensor::preset("os1-64-1024x10");
    const Descriptor d = make_descriptor("os1-64-1024x10", Profile::Legacy);
    OusterPacketizer pk(d, config(), {});
    EXPECT_EQ((pk.column_time(1) - kStart).count(), 97656);   // 97 656.25 ns
    EXPECT_EQ((pk.column_time(2) - kStart).count(), 195313);  // 195 312.5 → rounds up
    EXPECT_EQ((pk.column_time(1024) - kStart).count(), 100'000'000);
    EXPECT_EQ(pk.measurement_id(1030), 6);
    EXPECT_EQ(pk.frame_id(1030), 65531);
    std::vector<sensor::PulseSpec> spec(64 * 40);
    model.scan->pulses(64 * 1000, spec.size(), spec.data());
    for (std::size_t i = 0; i < spec.size(); i += 7)
        EXPECT_EQ(spec[i].t_ns, (pk.column_time(1000 + i / 64) - kStart).count()) << i;
}

// Points decoded with the SDK formula (§2.8) land on the renderer's hit: the pattern's direction
// times the range, within the beam-origin residual; the sensor frame is the lidar frame turned
// 180° about z and lifted by 36.18 mm.
TEST(OusterPacketizer, decoded_points_lie_on_the_rendered_rays) {
    for (const char* name : {"os1-128-1024x10", "os2-128-1024x10"}) {
        const auto model = sensor::preset(name);
        const Descriptor d = make_descriptor(name, Profile::Rng19Rfl8Sig16Nir16);
        const std::uint64_t H = d.beams, first = 16 * 300 * H, n = 16 * 2 * H;
        std::vector<sensor::PulseSpec> spec(n);
        model.scan->pulses(first, n, spec.data());
        std::vector<core::PointRecord> pts;
        for (std::uint64_t k = 0; k < n; ++k) {
            core::PointRecord p;
            p.pulse = first + k;
            p.channel = spec[k].channel;
            p.range_m = float(10.0 + 0.37 * double(k % 97));
            pts.push_back(p);
        }
        std::vector<Captured> out;
        OusterPacketizer pk(d, config(), test::collect(out));
        pk.add(pts);
        pk.advance_to(first + n);
        ASSERT_EQ(out.size(), 300u + 2u);  // 300 empty packets before, then ours
        Decoder dec(d);
        std::vector<OusterPoint> lidar, sensor;
        for (std::size_t i = 300; i < out.size(); ++i) {
            ASSERT_EQ(dec.decode(out[i].bytes), DecodeStatus::Ok);
            dec.points(PointFrame::Lidar, lidar);
            dec.points(PointFrame::Sensor, sensor);
        }
        ASSERT_EQ(lidar.size(), n);
        double worst = 0, bound = 0;
        for (std::uint64_t k = 0; k < n; ++k) {
            const auto& q = lidar[k];
            ASSERT_EQ(q.row, spec[k].channel);
            const Eigen::Vector3d truth = spec[k].dir.cast<double>() * double(pts[k].range_m);
            worst = std::max(worst, (Eigen::Vector3d(q.x, q.y, q.z) - truth).norm());
            // n·sin(angle between the beam and the column plane), + float dir + 0.5 mm
            const double el = d.altitude_deg[q.row] * std::numbers::pi / 180.0;
            const double az = d.azimuth_deg[q.row] * std::numbers::pi / 180.0;
            bound =
                std::max(bound, d.beam_origin_mm * 1e-3 *
                                        std::sqrt(1 - std::pow(std::cos(el) * std::cos(az), 2)) +
                                    1e-5 * double(pts[k].range_m) + 0.0006);
            EXPECT_NEAR(sensor[k].x, -q.x, 1e-9);
            EXPECT_NEAR(sensor[k].y, -q.y, 1e-9);
            EXPECT_NEAR(sensor[k].z, q.z + d.lidar_to_sensor[11] * 1e-3, 1e-9);
        }
        std::printf("%s: worst decoded-vs-rendered distance %.2f mm (bound %.2f mm)\n", name,
                    worst * 1e3, bound * 1e3);
        EXPECT_LE(worst, bound) << name;
        EXPECT_GT(worst, 0.0);
    }
}

TEST(OusterPacketizer, dropped_packets_mid_frame_are_detected_and_counted) {
    const Descriptor d = make_descriptor("os1-64-512x10", Profile::Rng19Rfl8Sig16Nir16);
    std::vector<Captured> out;
    OusterPacketizer pk(d, config(), test::collect(out));
    const std::uint64_t per_packet = 16 * 64;
    pk.advance_to(per_packet * 48);  // 1.5 frames of 32 packets
    ASSERT_EQ(out.size(), 48u);
    Decoder all(d), dropped(d);
    for (std::size_t i = 0; i < out.size(); ++i) {
        EXPECT_EQ(all.decode(out[i].bytes), DecodeStatus::Ok);
        // Drop packet 5 (mid frame) and packets 31–32 (across the frame boundary).
        if (i != 5 && i != 31 && i != 32) {
            EXPECT_EQ(dropped.decode(out[i].bytes), DecodeStatus::Ok);
        }
    }
    EXPECT_EQ(all.counters().measurement_id_gaps, 0u);
    EXPECT_EQ(all.counters().frames, 2u);
    EXPECT_EQ(dropped.counters().measurement_id_gaps, 2u);
    EXPECT_EQ(dropped.counters().missing_columns, 16u + 32u);
    EXPECT_EQ(dropped.counters().errors(), 0u);
}

TEST(OusterPacketizer, extra_and_out_of_range_returns_follow_single_return_rules) {
    Descriptor d = make_descriptor("os1-32-1024x10", Profile::Rng15Rfl8Nir8);
    d.beam_origin_mm = 0;
    std::vector<Captured> out;
    OusterPacketizer pk(d, config(), test::collect(out));
    std::vector<core::PointRecord> pts(4);
    pts[0].pulse = 3, pts[0].range_m = 20.0f, pts[0].n_laser = 50;    // weaker first return
    pts[1].pulse = 3, pts[1].range_m = 30.0f, pts[1].n_laser = 500;   // strongest: kept
    pts[2].pulse = 4, pts[2].range_m = 300.0f, pts[2].n_laser = 500;  // > 262.136 m: no return
    pts[3].pulse = 5, pts[3].range_m = 262.0f, pts[3].n_laser = 500;
    pk.add(pts);
    pk.advance_to(16 * 32);
    ASSERT_EQ(out.size(), 1u);
    Decoder dec(d);
    ASSERT_EQ(dec.decode(out[0].bytes), DecodeStatus::Ok);
    EXPECT_EQ(dec.packet().pixels[3].range_mm, 30'000u);
    EXPECT_EQ(dec.packet().pixels[4].range_mm, 0u);
    EXPECT_EQ(dec.packet().pixels[5].range_mm, 262'000u);
    EXPECT_EQ(pk.stats().extra_returns, 1u);
    EXPECT_EQ(pk.stats().out_of_range, 1u);
    EXPECT_EQ(pk.stats().returns, 2u);
}

TEST(OusterPacketizer, imu_packets_are_interleaved_in_time_order_at_100_hz) {
    const Descriptor d = make_descriptor("os2-128-1024x10", Profile::Rng19Rfl8Sig16Nir16);
    auto cfg = config();
    int calls = 0;
    cfg.imu = [&](core::GpsTime) {
        ++calls;
        ImuReading r;
        r.accel_g = {0, 0, 1};
        return r;
    };
    std::vector<Captured> out;
    OusterPacketizer pk(d, cfg, test::collect(out));
    pk.advance_to(std::uint64_t{128} * 1024 + 5);  // one frame = 100 ms
    pk.finish();
    std::size_t imu = 0, lidar = 0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        if (i > 0) {
            EXPECT_LE(out[i - 1].time, out[i].time) << i;
        }
        if (out[i].stream == wire::Stream::Imu) {
            ImuPacket p;
            ASSERT_TRUE(decode_imu_packet(out[i].bytes, p));
            EXPECT_EQ(out[i].time, kStart + std::chrono::milliseconds(10) * std::int64_t(imu));
            EXPECT_EQ(p.sys_ns, 765'000'000'000ull + 10'000'000ull * imu);
            EXPECT_FLOAT_EQ(p.accel_g[2], 1.0f);
            ++imu;
        } else {
            ++lidar;
        }
    }
    EXPECT_EQ(lidar, 64u);
    EXPECT_EQ(imu, 11u);  // t = 0, 10, …, 100 ms (the frame's columns reach 100 ms)
    EXPECT_EQ(calls, 11);
}

// Asked ahead of each lidar packet (a real-time caller, docs/live-navigation.md §1), the IMU
// packets due before it come at once and never past its send time; the stream is unchanged.
TEST(OusterPacketizer, imu_packets_come_early_and_leave_the_stream_unchanged) {
    const Descriptor d = make_descriptor("os2-128-1024x10", Profile::Rng19Rfl8Sig16Nir16);
    auto cfg = config();
    cfg.imu = [](core::GpsTime t) {
        ImuReading r;
        r.accel_g = {0, 0, double((t - kStart).count()) * 1e-9};
        return r;
    };
    std::vector<Captured> plain, early;
    OusterPacketizer a(d, cfg, test::collect(plain));
    OusterPacketizer b(d, cfg, test::collect(early));
    const std::uint64_t cols = d.columns_per_packet, ppp = cols * d.beams;
    std::size_t asked_and_came = 0;
    for (std::uint64_t k = 0; k < 128; ++k) {  // two frames
        const std::size_t before = early.size();
        const core::GpsTime send = b.column_time((k + 1) * cols);
        b.emit_side_packets_until(send + std::chrono::seconds(1));
        for (std::size_t i = before; i < early.size(); ++i) {
            EXPECT_EQ(early[i].stream, wire::Stream::Imu);
            EXPECT_LE(early[i].time, send);
            EXPECT_GT(early[i].time, k ? b.column_time(k * cols) : kStart - core::Nanos(1));
            ++asked_and_came;
        }
        a.advance_to((k + 1) * ppp);
        b.advance_to((k + 1) * ppp);
    }
    a.finish();
    b.finish();
    ASSERT_EQ(plain.size(), early.size());
    for (std::size_t i = 0; i < plain.size(); ++i) {
        EXPECT_EQ(plain[i].stream, early[i].stream) << i;
        EXPECT_EQ(plain[i].time, early[i].time) << i;
        EXPECT_EQ(plain[i].bytes, early[i].bytes) << i;
    }
    EXPECT_EQ(b.stats().imu_packets, 21u);  // t = 0, 10, …, 200 ms
    EXPECT_EQ(asked_and_came, 21u);
}

// A step of the time source (docs/time.md §1) moves the sync-pulse and PTP stamps by it; the
// internal oscillator runs on.
TEST(OusterSensorClock, step_moves_the_followed_modes_only) {
    std::atomic<std::int64_t> step{0};
    const core::GpsTime t = kStart + core::Nanos(123'456'789);
    for (TimestampMode m :
         {TimestampMode::InternalOsc, TimestampMode::SyncPulseIn, TimestampMode::Ptp1588}) {
        SCOPED_TRACE(to_string(m));
        SensorClock c{m, kStart, &step};
        step.store(0);
        const std::uint64_t before = c.ns(t);
        step.store(-1'750'000'000);
        const std::int64_t moved = static_cast<std::int64_t>(c.ns(t) - before);
        EXPECT_EQ(moved, m == TimestampMode::InternalOsc ? 0 : -1'750'000'000);
    }
}

}  // namespace
}  // namespace mirage::ouster
