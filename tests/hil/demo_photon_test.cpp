// SPDX-License-Identifier: Apache-2.0
// `mirage demo`'s photon-counting pass (docs/photon-counting.md §8): the ALIRT-like array over
// the camouflaged vehicle writes its events, the coincidence points at 60 / 240 / 480 pulses per
// cell and their views; with more pulses per cell more of the vehicle under the net comes out.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <map>

#include "cli_run.hpp"
#include "mirage/las/las_reader.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

TEST(DemoPhoton, the_vehicle_under_the_net_comes_out_as_the_pulses_per_cell_grow) {
    TempDir tmp;
    const auto r = run_mirage("demo --out-dir " + tmp.path().string() +
                              " --car-seconds 0.05 --flight-seconds 0.05 --waveform-seconds 0 "
                              "--photon-seconds 0.6 --threads 2");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // "  60 pulses per cell: 4004 points: vehicle 87, net 1218, ground 2691, other 8 (..." (no
    // std::regex: GCC 12 under ASan warns inside <regex>, and warnings are errors there).
    std::map<int, std::array<long, 4>> seen;  // dwell -> points, vehicle, net, ground
    std::size_t at = 0;
    while ((at = r.output.find(" pulses per cell: ", at)) != std::string::npos) {
        const std::size_t line = r.output.rfind('\n', at) + 1;
        int dwell = 0;
        long pts = 0, vehicle = 0, net = 0, ground = 0;
        if (std::sscanf(r.output.c_str() + line,
                        " %d pulses per cell: %ld points: vehicle %ld, net %ld, ground %ld", &dwell,
                        &pts, &vehicle, &net, &ground) == 5)
            seen[dwell] = {pts, vehicle, net, ground};
        at += 1;
    }
    ASSERT_EQ(seen.size(), 3u) << r.output;
    std::printf("vehicle points at 60 / 240 / 480 pulses per cell: %ld / %ld / %ld\n", seen[60][1],
                seen[240][1], seen[480][1]);
    EXPECT_LT(seen[60][1], seen[240][1]);
    EXPECT_LT(seen[240][1], seen[480][1]);
    EXPECT_GT(seen[480][2], 100);  // the net
    EXPECT_GT(seen[480][3], 500);  // the ground around it
    for (const char* tag : {"events", "60", "240", "480"})
        for (const char* view : {"top", "side"})
            EXPECT_GT(std::filesystem::file_size(
                          tmp.file(std::string("demo_photon_") + tag + "_" + view + ".png")),
                      100u)
                << tag << " " << view;
    const auto events = las::LasFile::read(tmp.file("demo_photon_events.las"));
    EXPECT_TRUE(events.validate().empty());
    ASSERT_GT(events.points().size(), 10000u);
    std::size_t signal = 0;
    for (const auto& p : events.points()) signal += p.event == 1;
    EXPECT_GT(signal, events.points().size() / 2);  // a night collection: mostly signal
    const auto points = las::LasFile::read(tmp.file("demo_photon_points_480.las"));
    EXPECT_EQ(points.points().size(), std::size_t(seen[480][0]));
}

}  // namespace
}  // namespace mirage::test
