// SPDX-License-Identifier: Apache-2.0
// BatchSender over loopback: runs of equal datagrams leave as UDP GSO messages and arrive as the
// same separate datagrams, in order; where the route refuses GSO (MTU below the segment size, in
// a private network namespace) the run is re-sent singly and nothing is lost.
#include "mirage/replay/batch_sender.hpp"

#include <gtest/gtest.h>
#include <net/if.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <thread>

#include "mirage/udp/udp_receiver.hpp"

namespace {

using namespace mirage;

std::vector<std::uint8_t> stamped(std::size_t size, std::uint32_t id) {
    std::vector<std::uint8_t> p(size);
    for (std::size_t i = 0; i < size; ++i) p[i] = static_cast<std::uint8_t>(id * 131 + i);
    std::memcpy(p.data(), &id, sizeof id);
    return p;
}

std::vector<std::vector<std::uint8_t>> collect(udp::UdpReceiver& rx, std::size_t expected) {
    std::vector<std::vector<std::uint8_t>> v;
    udp::ReceivedDatagram d;
    while (v.size() < expected && rx.receive(d, core::Nanos{2'000'000'000})) v.push_back(d.payload);
    return v;
}

struct Plan {
    std::vector<std::vector<std::uint8_t>> a, b;  // expected at receivers A and B, in order
    std::vector<replay::Outgoing> out;
};

// 30 × 1206 B to A, 3 × 512 B to A, 10 × 1206 B to B, 1 × 1206 B to A: four runs.
Plan make_plan(std::uint16_t port_a, std::uint16_t port_b) {
    Plan p;
    std::uint32_t id = 0;
    for (int i = 0; i < 30; ++i) p.a.push_back(stamped(1206, id++));
    for (int i = 0; i < 3; ++i) p.a.push_back(stamped(512, id++));
    for (int i = 0; i < 10; ++i) p.b.push_back(stamped(1206, id++));
    p.a.push_back(stamped(1206, id++));
    for (std::size_t i = 0; i < 33; ++i) p.out.push_back({p.a[i], port_a});
    for (const auto& x : p.b) p.out.push_back({x, port_b});
    p.out.push_back({p.a[33], port_a});
    return p;
}

void send_and_check(bool gso) {
    udp::UdpReceiver rx_a(udp::ReceiverConfig{}), rx_b(udp::ReceiverConfig{});
    const Plan plan = make_plan(rx_a.port(), rx_b.port());
    std::vector<std::vector<std::uint8_t>> got_a, got_b;
    std::thread ta([&] { got_a = collect(rx_a, plan.a.size()); });
    std::thread tb([&] { got_b = collect(rx_b, plan.b.size()); });
    replay::BatchSender sender("127.0.0.1", 4 << 20, gso);
    EXPECT_EQ(sender.send(plan.out), plan.out.size());
    ta.join();
    tb.join();
    EXPECT_EQ(sender.failed(), 0u);
    EXPECT_EQ(sender.sent(), plan.out.size());
    // Four runs (30, 3, 10, 1): three go as GSO messages, the single one plainly; one call.
    EXPECT_EQ(sender.gso_messages(), gso ? 3u : 0u);
    EXPECT_EQ(sender.syscalls(), 1u);
    ASSERT_EQ(got_a.size(), plan.a.size());
    ASSERT_EQ(got_b.size(), plan.b.size());
    for (std::size_t i = 0; i < plan.a.size(); ++i) EXPECT_EQ(got_a[i], plan.a[i]) << "A #" << i;
    for (std::size_t i = 0; i < plan.b.size(); ++i) EXPECT_EQ(got_b[i], plan.b[i]) << "B #" << i;
}

TEST(BatchSender, runs_of_equal_datagrams_leave_as_gso_messages_and_arrive_separately_in_order) {
    send_and_check(true);
}

TEST(BatchSender, without_gso_the_same_datagrams_arrive_the_same) { send_and_check(false); }

// Child of the fork: exit 0 = passed, 77 = cannot make the namespace, other = failure code.
int gso_refused_child() {
    if (::unshare(CLONE_NEWNET) != 0) return 77;
    const int s = ::socket(AF_INET, SOCK_DGRAM, 0);
    ifreq ifr{};
    std::strncpy(ifr.ifr_name, "lo", IFNAMSIZ - 1);
    ifr.ifr_mtu = 1500;  // below the 3000-byte segments: the kernel refuses GSO with EINVAL
    if (::ioctl(s, SIOCSIFMTU, &ifr) != 0) return 77;
    if (::ioctl(s, SIOCGIFFLAGS, &ifr) != 0) return 77;
    ifr.ifr_flags = static_cast<short>(ifr.ifr_flags | IFF_UP);
    if (::ioctl(s, SIOCSIFFLAGS, &ifr) != 0) return 77;
    ::close(s);
    udp::UdpReceiver rx(udp::ReceiverConfig{});
    std::vector<std::vector<std::uint8_t>> sent;
    std::vector<replay::Outgoing> out;
    for (std::uint32_t i = 0; i < 3; ++i) sent.push_back(stamped(3000, i));
    for (const auto& p : sent) out.push_back({p, rx.port()});
    replay::BatchSender sender("127.0.0.1");
    if (sender.send(out) != 3) return 10;
    if (sender.gso_messages() != 0) return 11;
    if (sender.failed() != 0) return 12;
    if (sender.syscalls() != 2) return 13;  // the refused GSO call, then the three singly
    const auto got = collect(rx, 3);
    if (got != sent) return 14;  // fragmented by IP and reassembled, in order
    // The size stays refused: the next run of it goes singly at once.
    if (sender.send(out) != 3 || sender.syscalls() != 3) return 15;
    if (collect(rx, 3) != sent) return 16;
    return 0;
}

TEST(BatchSender, gso_refused_by_a_smaller_route_mtu_falls_back_to_single_datagrams) {
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) ::_exit(gso_refused_child());
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    if (WEXITSTATUS(status) == 77) GTEST_SKIP() << "no private network namespace (not root?)";
    EXPECT_EQ(WEXITSTATUS(status), 0) << "failure code in gso_refused_child()";
}

}  // namespace
