// SPDX-License-Identifier: Apache-2.0
// Random returns (fixed seed) → packetizer → decoder, every model × return mode.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "mirage/velodyne/data_packet.hpp"
#include "mirage/velodyne/packetizer.hpp"
#include "mirage/velodyne/sensor_clock.hpp"
#include "velodyne_test_util.hpp"

namespace mirage::velodyne {
namespace {

using test::angle_diff_deg;

struct Tally {
    std::uint64_t slots = 0, returns = 0, azimuth_checks = 0;
    double worst_range_err_m = 0, worst_azimuth_err_deg = 0, worst_xyz_err_m = 0;
};

// The return the device reports for a pulse: §1.5 selection among the encodable returns.
const core::PointRecord* expected_return(const std::vector<const core::PointRecord*>& rs,
                                         ReturnMode mode, int r) {
    if (rs.empty()) return nullptr;
    const core::PointRecord* strongest = rs.front();
    const core::PointRecord* last = rs.front();
    for (const auto* p : rs) {
        if (p->n_laser > strongest->n_laser) strongest = p;
        if (p->return_number > last->return_number) last = p;
    }
    if (mode == ReturnMode::Strongest) return strongest;
    if (mode == ReturnMode::Last) return last;
    if (r == 0) return last;
    if (strongest != last) return strongest;
    const core::PointRecord* second = nullptr;
    for (const auto* p : rs)
        if (p != strongest && (second == nullptr || p->n_laser > second->n_laser)) second = p;
    return second != nullptr ? second : strongest;
}

void run_roundtrip(Model model, ReturnMode mode, double rpm, std::uint64_t packets, Tally& tally) {
    const ModelDescriptor& md = descriptor(model);
    const sensor::SensorModel sensor = test::preset_at(md, rpm);
    const auto& pattern = *sensor.scan;
    const core::GpsTime start = core::parse_time("2024-03-01T12:34:56.789123456Z");
    const auto S = static_cast<std::uint64_t>(md.sequences_per_packet(mode));
    const auto L = static_cast<std::uint64_t>(md.lasers);
    const std::uint64_t n = packets * S * L;
    test::SyntheticOptions so;
    so.seed = 1000 + static_cast<std::uint64_t>(model) * 10 + static_cast<std::uint64_t>(mode);
    so.max_range_m = sensor.receiver.max_range_m + 10.0;  // some beyond max range
    const auto points = test::synthetic_returns(pattern, n, start, so);

    std::vector<test::CollectedPacket> out;
    PacketizerOptions popt;
    popt.position_packets = false;
    Packetizer pk(md, mode, sensor, start, test::collect_into(out), popt);
    // Deliver in uneven chunks, as the pipeline does.
    std::size_t i = 0;
    std::uint64_t next_pulse = 0;
    while (i < points.size()) {
        const std::size_t j = std::min(points.size(), i + 777);
        pk.add(std::span(points).subspan(i, j - i));
        next_pulse = j < points.size() ? points[j].pulse : n;
        pk.advance_to(next_pulse);
        i = j;
    }
    pk.advance_to(n);
    pk.finish();
    EXPECT_EQ(out.size(), packets);

    std::vector<sensor::PulseSpec> spec(static_cast<std::size_t>(n));
    pattern.pulses(0, spec.size(), spec.data());
    std::vector<std::uint64_t> slot_of_laser(L);
    for (std::uint64_t k = 0; k < L; ++k) slot_of_laser[spec[k].channel] = k;
    std::map<std::uint64_t, std::vector<const core::PointRecord*>> by_pulse;
    std::uint64_t out_of_range = 0;
    for (const auto& p : points) {
        if (p.range_m <= sensor.receiver.max_range_m)
            by_pulse[p.pulse].push_back(&p);
        else
            ++out_of_range;
    }
    EXPECT_EQ(pk.stats().returns_out_of_range, out_of_range);

    const double step = md.azimuth_step_deg(rpm);
    const std::int64_t start_unix = core::unix_ns_from_gps(start);
    for (std::uint64_t P = 0; P < out.size(); ++P) {
        SCOPED_TRACE("packet " + std::to_string(P));
        DecodedPacket d;
        ASSERT_EQ(decode_data(out[P].bytes, &md, d), DecodeStatus::Ok);
        EXPECT_EQ(d.mode == ReturnMode::Dual, mode == ReturnMode::Dual);
        const std::uint64_t s0 = P * S;
        // Timestamp: µs past the UTC hour of the packet's first firing (closed form).
        const std::int64_t first_ns =
            start_unix + static_cast<std::int64_t>(s0) * md.sequence_period_ns;
        EXPECT_EQ(d.timestamp_us,
                  static_cast<std::uint32_t>((first_ns % 3'600'000'000'000LL) / 1000));
        // Send time = the packet's last firing.
        EXPECT_EQ(out[P].time, start + core::Nanos(spec[(P + 1) * S * L - 1].t_ns));
        for (int b = 0; b < kBlocksPerPacket; ++b) {
            const std::uint64_t s = s0 + static_cast<std::uint64_t>(md.block_sequence(mode, b));
            const auto want =
                std::llround(std::fmod(static_cast<double>(s) * step, 360.0) * 100.0) % 36000;
            EXPECT_EQ(d.block_azimuth[static_cast<std::size_t>(b)], want) << "block " << b;
            EXPECT_EQ(out[P].bytes[static_cast<std::size_t>(100 * b + 1)], md.block_flag(b) >> 8);
        }
        for (const Firing& f : d.firing) {
            ++tally.slots;
            const std::uint64_t k = (s0 + f.sequence) * L + slot_of_laser[f.laser];
            const sensor::PulseSpec& ps = spec[k];
            ASSERT_EQ(ps.channel, f.laser);
            EXPECT_EQ(f.time_offset_ns, ps.t_ns - spec[s0 * L].t_ns);
            const double az_err = std::abs(angle_diff_deg(f.azimuth_deg, ps.azimuth_deg));
            tally.worst_azimuth_err_deg = std::max(tally.worst_azimuth_err_deg, az_err);
            EXPECT_LE(az_err, 0.012) << "laser " << int(f.laser);
            const auto it = by_pulse.find(k);
            const core::PointRecord* want =
                it == by_pulse.end() ? nullptr : expected_return(it->second, mode, f.ret);
            if (want == nullptr) {
                EXPECT_EQ(f.raw_distance, 0);
                continue;
            }
            ++tally.returns;
            EXPECT_EQ(f.raw_distance, std::lround(want->range_m / md.distance_lsb_m));
            const double err = std::abs(f.distance_m - want->range_m);
            tally.worst_range_err_m = std::max(tally.worst_range_err_m, err);
            EXPECT_LE(err, md.distance_lsb_m / 2 + 1e-5);
            EXPECT_EQ(f.reflectivity, (want->intensity + 128) / 257);
            const Eigen::Vector3d p(f.x, f.y, f.z);
            const Eigen::Vector3d q = ps.dir.cast<double>() * static_cast<double>(f.distance_m);
            const double xyz_err = (p - q).norm();
            tally.worst_xyz_err_m = std::max(tally.worst_xyz_err_m, xyz_err);
            EXPECT_LE(xyz_err, 1e-4 + f.distance_m * 2.5e-4);
        }
    }
}

void run_all_models(ReturnMode mode) {
    for (Model m : kAllModels) {
        SCOPED_TRACE(std::string(descriptor(m).name));
        Tally t;
        run_roundtrip(m, mode, 600, 20, t);
        std::printf(
            "%-12s %-9s slots %llu returns %llu worst |dR| %.4f mm, |daz| %.5f deg, "
            "|dxyz| %.3f mm\n",
            std::string(descriptor(m).name).c_str(), to_string(mode),
            static_cast<unsigned long long>(t.slots), static_cast<unsigned long long>(t.returns),
            1e3 * t.worst_range_err_m, t.worst_azimuth_err_deg, 1e3 * t.worst_xyz_err_m);
        EXPECT_GT(t.returns, t.slots / 2);
    }
}

TEST(VelodyneRoundTrip, strongest_mode_every_model_decodes_to_the_encoded_returns) {
    run_all_models(ReturnMode::Strongest);
}

TEST(VelodyneRoundTrip, last_mode_every_model_decodes_to_the_encoded_returns) {
    run_all_models(ReturnMode::Last);
}

TEST(VelodyneRoundTrip, dual_mode_every_model_decodes_last_and_strongest_blocks) {
    run_all_models(ReturnMode::Dual);
}

TEST(VelodyneRoundTrip, other_rpm_keeps_azimuths_and_timestamps_on_the_closed_form) {
    for (Model m : kAllModels) {
        SCOPED_TRACE(std::string(descriptor(m).name));
        Tally t;
        run_roundtrip(m, ReturnMode::Strongest, 1137.5, 8, t);
        run_roundtrip(m, ReturnMode::Dual, 300, 8, t);
        EXPECT_GT(t.returns, t.slots / 2);
    }
}

TEST(VelodyneRoundTrip, single_return_per_pulse_makes_identical_dual_blocks) {
    const ModelDescriptor& md = descriptor(Model::Vlp16);
    const sensor::SensorModel sensor = test::preset_at(md, 600);
    test::SyntheticOptions so;
    so.max_returns = 1;
    so.max_range_m = 90;
    const std::uint64_t n = 3 * 12 * 16;
    const auto points = test::synthetic_returns(*sensor.scan, n, core::GpsTime{}, so);
    std::vector<test::CollectedPacket> out;
    PacketizerOptions popt;
    popt.position_packets = false;
    Packetizer pk(md, ReturnMode::Dual, sensor, core::GpsTime{}, test::collect_into(out), popt);
    pk.add(points);
    pk.advance_to(n);
    ASSERT_EQ(out.size(), 3u);
    for (const auto& p : out)
        for (int b = 0; b < 12; b += 2)
            EXPECT_TRUE(std::equal(p.bytes.begin() + 100 * b, p.bytes.begin() + 100 * b + 100,
                                   p.bytes.begin() + 100 * (b + 1)))
                << "block pair " << b;
}

}  // namespace
}  // namespace mirage::velodyne
