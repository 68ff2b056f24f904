// SPDX-License-Identifier: Apache-2.0
// `--nav dis:udp://…?exercise=&entity=&timeout=` (docs/dis.md §6): options out of the URI, the
// socket's URI without them, and every mistake refused naming the option.
#include "mirage/navio/dis_uri.hpp"

#include <gtest/gtest.h>

#include <string>

#include "mirage/core/error.hpp"

namespace mirage::navio {
namespace {

TEST(DisUri, options_come_out_and_the_socket_keeps_its_address) {
    std::string udp;
    const dis::TrackConfig c =
        parse_dis_transport("udp://127.0.0.1:3000?exercise=3&entity=1.2.65535&timeout=5", udp);
    EXPECT_EQ(udp, "udp://127.0.0.1:3000");
    ASSERT_TRUE(c.filter.exercise);
    EXPECT_EQ(*c.filter.exercise, 3);
    ASSERT_TRUE(c.filter.entity);
    EXPECT_EQ(*c.filter.entity, (dis::EntityId{1, 2, 65535}));
    EXPECT_EQ(c.timeout, std::chrono::seconds(5));
}

TEST(DisUri, without_options_every_exercise_and_the_first_entity) {
    std::string udp;
    const dis::TrackConfig c = parse_dis_transport("udp://:3000", udp);
    EXPECT_EQ(udp, "udp://:3000");
    EXPECT_FALSE(c.filter.exercise);
    EXPECT_FALSE(c.filter.entity);
    EXPECT_EQ(c.timeout, std::chrono::seconds(12));
}

TEST(DisUri, mistakes_are_refused_naming_the_option) {
    const std::pair<const char*, const char*> bad[] = {
        {"udp://:3000?exercise=256", "exercise"},
        {"udp://:3000?entity=1.2", "entity"},
        {"udp://:3000?entity=1.2.3.4", "entity"},
        {"udp://:3000?entity=1.2.65536", "entity"},
        {"udp://:3000?entity=1..3", "entity"},
        {"udp://:3000?timeout=0", "timeout"},
        {"udp://:3000?heartbeat=5", "heartbeat"},
        {"tcp://host:3000", "UDP"},
        {"/dev/ttyUSB0", "UDP"},
    };
    for (const auto& [uri, word] : bad) {
        std::string udp;
        try {
            (void)parse_dis_transport(uri, udp);
            ADD_FAILURE() << uri << " was accepted";
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace mirage::navio
