// SPDX-License-Identifier: Apache-2.0
// Golden outputs: fixed renders of the example scene (a LAS file, Velodyne dual-return packets,
// Ouster RNG19 packets) compared field by field with files committed in recordings/golden/.
// Any change to the physics, the encoders or the file writers shows here. Integer fields and
// times must match exactly; coordinates, distances and intensities may differ by one unit,
// because -march=native lets the compiler fuse multiply-adds differently on another CPU
// (docs/testing.md). After an intended change:
//     MIRAGE_UPDATE_GOLDEN=1 ctest -L golden
// rewrites the files (then look at the diff in a viewer before committing them).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "cli_run.hpp"
#include "mirage/las/las_reader.hpp"
#include "mirage/ouster/decoder.hpp"
#include "mirage/ouster/descriptor.hpp"
#include "mirage/pcap/pcap.hpp"
#include "mirage/velodyne/data_packet.hpp"
#include "mirage/velodyne/model.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

namespace fs = std::filesystem;

const std::string kScene = "--scene " + (source_dir() / "recordings/scenes/example.yaml").string();
const std::string kStart = "--start 2024-03-01T12:00:00Z --seed 7";

fs::path golden(const std::string& name) { return source_dir() / "recordings/golden" / name; }

// Runs `mirage <args> <out>` and returns the file it wrote; under MIRAGE_UPDATE_GOLDEN=1 the file
// becomes the golden one.
fs::path produce(const TempDir& dir, const std::string& name, const std::string& args) {
    const fs::path out = dir.path() / name;
    const auto r = run_mirage(args + " " + out.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const char* update = std::getenv("MIRAGE_UPDATE_GOLDEN");
    if (update && std::string(update) == "1")
        fs::copy_file(out, golden(name), fs::copy_options::overwrite_existing);
    return out;
}

bool near(double a, double b, double units) { return std::abs(a - b) <= units; }

TEST(Golden, vlp16_las_of_the_example_scene) {
    TempDir dir;
    const fs::path out = produce(dir, "example_vlp16.las",
                                 "render " + kScene + " --sensor vlp16 --trajectory static:0,0,2 " +
                                     kStart + " --duration 0.01 --format 7 --out");
    const auto got = las::LasFile::read(out.string());
    const auto want = las::LasFile::read(golden("example_vlp16.las").string());
    ASSERT_TRUE(got.validate().empty());
    ASSERT_EQ(got.points().size(), want.points().size());
    ASSERT_GT(want.points().size(), 1000u);
    for (std::size_t i = 0; i < want.points().size(); ++i) {
        const auto& a = got.points()[i];
        const auto& b = want.points()[i];
        ASSERT_TRUE(near(a.raw_x, b.raw_x, 1) && near(a.raw_y, b.raw_y, 1) &&
                    near(a.raw_z, b.raw_z, 1))
            << "point " << i;
        ASSERT_TRUE(near(a.intensity, b.intensity, 1)) << "point " << i;
        ASSERT_EQ(a.gps_time, b.gps_time) << "point " << i;
        ASSERT_EQ(a.return_number, b.return_number) << "point " << i;
        ASSERT_EQ(a.number_of_returns, b.number_of_returns) << "point " << i;
        ASSERT_EQ(a.classification, b.classification) << "point " << i;
        ASSERT_EQ(a.scanner_channel, b.scanner_channel) << "point " << i;
        ASSERT_EQ(a.red, b.red) << "point " << i;
    }
}

TEST(Golden, vlp16_dual_return_packets_of_the_example_scene) {
    TempDir dir;
    const fs::path out =
        produce(dir, "example_vlp16_dual.pcap",
                "emulate " + kScene + " --sensor vlp16 --pose 0,0,2 --return-mode dual " + kStart +
                    " --duration 0.02 --as-fast-as-possible --pcap");
    const auto got = pcap::read_udp(out.string());
    const auto want = pcap::read_udp(golden("example_vlp16_dual.pcap").string());
    ASSERT_EQ(got.size(), want.size());
    ASSERT_GT(want.size(), 10u);
    const auto* model = &velodyne::descriptor(velodyne::Model::Vlp16);
    for (std::size_t i = 0; i < want.size(); ++i) {
        ASSERT_EQ(got[i].time_ns, want[i].time_ns) << "packet " << i;
        ASSERT_EQ(got[i].dst.port, want[i].dst.port) << "packet " << i;
        if (want[i].dst.port != 2368) {  // position packets: no float arithmetic, exact
            ASSERT_EQ(got[i].payload, want[i].payload) << "position packet " << i;
            continue;
        }
        velodyne::DecodedPacket a, b;
        ASSERT_EQ(velodyne::decode_data(got[i].payload, model, a), velodyne::DecodeStatus::Ok);
        ASSERT_EQ(velodyne::decode_data(want[i].payload, model, b), velodyne::DecodeStatus::Ok);
        ASSERT_EQ(a.timestamp_us, b.timestamp_us) << "packet " << i;
        ASSERT_EQ(a.block_azimuth, b.block_azimuth) << "packet " << i;
        for (std::size_t f = 0; f < a.firing.size(); ++f) {
            ASSERT_TRUE(near(a.firing[f].raw_distance, b.firing[f].raw_distance, 1) &&
                        near(a.firing[f].reflectivity, b.firing[f].reflectivity, 1))
                << "packet " << i << " slot " << f;
        }
    }
}

TEST(Golden, ouster_rng19_packets_of_the_example_scene) {
    TempDir dir;
    const fs::path out = produce(dir, "example_os1_rng19.pcap",
                                 "emulate " + kScene + " --sensor os1-64-1024x10 --pose 0,0,2 " +
                                     "--profile RNG19_RFL8_SIG16_NIR16 --imu-port 0 " + kStart +
                                     " --duration 0.005 --as-fast-as-possible --pcap");
    const auto got = pcap::read_udp(out.string());
    const auto want = pcap::read_udp(golden("example_os1_rng19.pcap").string());
    ASSERT_EQ(got.size(), want.size());
    ASSERT_GE(want.size(), 3u);
    const auto d = ouster::make_descriptor("os1-64-1024x10", ouster::Profile::Rng19Rfl8Sig16Nir16);
    ouster::Decoder da(d), db(d);
    for (std::size_t i = 0; i < want.size(); ++i) {
        ASSERT_EQ(got[i].time_ns, want[i].time_ns) << "packet " << i;
        ASSERT_EQ(da.decode(got[i].payload), ouster::DecodeStatus::Ok) << "packet " << i;
        ASSERT_EQ(db.decode(want[i].payload), ouster::DecodeStatus::Ok) << "packet " << i;
        const auto& a = da.packet();
        const auto& b = db.packet();
        ASSERT_EQ(a.header.frame_id, b.header.frame_id) << "packet " << i;
        for (std::size_t c = 0; c < b.columns.size(); ++c) {
            ASSERT_EQ(a.columns[c].timestamp_ns, b.columns[c].timestamp_ns) << "packet " << i;
            ASSERT_EQ(a.columns[c].measurement_id, b.columns[c].measurement_id) << "packet " << i;
        }
        for (std::size_t p = 0; p < b.pixels.size(); ++p) {
            const auto& x = a.pixels[p];
            const auto& y = b.pixels[p];
            ASSERT_TRUE(near(x.range_mm, y.range_mm, 1) &&
                        near(x.reflectivity, y.reflectivity, 1) && near(x.signal, y.signal, 1) &&
                        near(x.nir, y.nir, 1))
                << "packet " << i << " pixel " << p;
        }
    }
}

}  // namespace
}  // namespace mirage::test
