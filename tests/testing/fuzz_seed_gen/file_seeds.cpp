// SPDX-License-Identifier: Apache-2.0
// Seeds of the capture and file targets: frames of every link type (Mirage's UDP framer for
// Ethernet/IPv4 and its fragments, hand-built headers for the rest), pcap files from pcap::Writer
// plus a cooked-link and a pcapng file, LAS files from LasWriter, trajectory CSV from
// save_trajectory_csv.
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_pcap_frame.hpp"
#include "las_test_points.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/las/las_writer.hpp"
#include "mirage/pcap/writer.hpp"
#include "raw_pcap.hpp"
#include "seed_writer.hpp"
#include "udp_framer.hpp"

namespace mirage::testing::seeds {
namespace {

using test::Bytes;

Bytes slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A scratch file that is removed again.
struct Scratch {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("mirage-seed-" + std::to_string(::getpid()));
    ~Scratch() { std::filesystem::remove(path); }
};

// Ethernet/IPv4/UDP frames of one datagram as Mirage frames it (fragments above mtu − 28).
std::vector<Bytes> udp_frames(std::size_t payload_size, std::size_t mtu, std::uint16_t ip_id) {
    const pcap::Endpoint src{{192, 168, 1, 201}, 2368}, dst{{192, 168, 1, 77}, 2368};
    std::vector<Bytes> out;
    Bytes buf;
    pcap::detail::frame_udp(
        {}, src, dst, ip_id, test::pattern(payload_size), mtu, buf,
        [&](std::span<const std::uint8_t> f) { out.emplace_back(f.begin(), f.end()); });
    return out;
}

Bytes ipv6_udp(const Bytes& payload, std::uint8_t next_header = 17, const Bytes& ext = {}) {
    const Bytes u = test::udp(7502, 7502, payload);
    Bytes h(40, 0);
    h[0] = 0x60;
    test::put16(h, 4, static_cast<unsigned>(ext.size() + u.size()));
    h[6] = next_header;
    h[7] = 64;
    h[8] = 0xfe, h[9] = 0x80, h[23] = 1;    // fe80::1
    h[24] = 0xfe, h[25] = 0x80, h[39] = 2;  // fe80::2
    test::append(h, ext);
    test::append(h, u);
    return h;
}

// Raw IPv6 packets (fe80::1 -> fe80::2) carrying one UDP datagram in fragments of `piece` bytes
// (RFC 8200 §4.5), last piece first.
std::vector<Bytes> ipv6_fragments(const Bytes& payload, std::size_t piece) {
    const Bytes whole = test::udp(7502, 7502, payload);
    std::vector<Bytes> out;
    for (std::size_t begin = 0; begin < whole.size(); begin += piece) {
        const std::size_t end = std::min(whole.size(), begin + piece);
        const auto fo = static_cast<unsigned>(begin | (end < whole.size() ? 1u : 0u));
        Bytes h(40, 0);
        h[0] = 0x60;
        test::put16(h, 4, static_cast<unsigned>(8 + end - begin));
        h[6] = 44;
        h[7] = 64;
        h[8] = 0xfe, h[9] = 0x80, h[23] = 1;
        h[24] = 0xfe, h[25] = 0x80, h[39] = 2;
        test::append(h, {17, 0, static_cast<std::uint8_t>(fo >> 8), static_cast<std::uint8_t>(fo),
                         0, 0, 0, 5});
        test::append(h, Bytes(whole.begin() + static_cast<std::ptrdiff_t>(begin),
                              whole.begin() + static_cast<std::ptrdiff_t>(end)));
        out.insert(out.begin(), h);
    }
    return out;
}

// Byte 0 indexes pcap::test::kFuzzLinkTypes: 0 Ethernet, 1 SLL, 2 SLL2, 3 loopback, 4 raw,
// 5 IPv4, 6 IPv6.
void pcap_frames(SeedWriter& w) {
    const std::string t = "fuzz_pcap_frame";
    const Bytes ip4 = test::ipv4(17, test::udp(2368, 2368, test::pattern(40)));
    Bytes b;
    for (const auto& f : udp_frames(100, 1500, 1)) pcap::test::append_frame(b, f, 1);
    w.put(t, "ethernet_udp", 0, b);
    b.clear();
    const auto frags = udp_frames(1200, 576, 2);
    for (auto it = frags.rbegin(); it != frags.rend(); ++it) pcap::test::append_frame(b, *it, 0);
    w.put(t, "ethernet_fragments_reversed", 0, b);
    b.clear();
    pcap::test::append_frame(b, frags[0], 0);
    pcap::test::append_frame(b, frags[1], 70);  // 35 s later: the first one expired
    pcap::test::append_frame(b, frags[2], 0x80 | 1);
    w.put(t, "ethernet_fragments_expired_cut", 0, b);
    b.clear();
    Bytes tagged = {0x00, 0x05, 0x08, 0x00};  // 802.1Q VLAN 5, then IPv4
    test::append(tagged, ip4);
    pcap::test::append_frame(b, test::ethernet(0x8100, tagged), 1);
    const Bytes frag_ext = {17, 0, 0, 0, 0, 0, 0, 9};  // atomic fragment header
    pcap::test::append_frame(b, test::ethernet(0x86dd, ipv6_udp(test::pattern(24), 44, frag_ext)),
                             1);
    pcap::test::append_frame(b, test::ethernet(0x86dd, ipv6_udp(test::pattern(32))), 1);
    w.put(t, "ethernet_vlan_ipv6", 0, b);
    b.clear();
    Bytes sll = {0, 0, 0, 1, 0, 6, 0x60, 0x76, 0x88, 0, 0, 1, 0, 0, 0x08, 0x00};
    test::append(sll, ip4);
    pcap::test::append_frame(b, sll, 1);
    w.put(t, "sll", 1, b);
    b.clear();
    Bytes sll2 = {0x86, 0xdd, 0, 0, 0, 0, 0, 2, 0, 1, 0, 6, 0x60, 0x76, 0x88, 0, 0, 1, 0, 0};
    test::append(sll2, ipv6_udp(test::pattern(16)));
    pcap::test::append_frame(b, sll2, 1);
    w.put(t, "sll2_ipv6", 2, b);
    b.clear();
    Bytes loop = {2, 0, 0, 0};
    test::append(loop, ip4);
    pcap::test::append_frame(b, loop, 1);
    w.put(t, "loopback", 3, b);
    b.clear();
    pcap::test::append_frame(b, ip4, 1);
    pcap::test::append_frame(b, ipv6_udp(test::pattern(8)), 1);
    w.put(t, "raw", 4, b);
    b.clear();
    for (const auto& f : ipv6_fragments(test::pattern(600), 256)) pcap::test::append_frame(b, f, 1);
    w.put(t, "ipv6_fragments", 6, b);
}

// A minimal pcapng: section header, Ethernet interface, one enhanced packet block.
Bytes pcapng_file(const Bytes& frame) {
    Bytes b;
    auto u32 = [&](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    };
    u32(0x0A0D0D0A), u32(28), u32(0x1A2B3C4D), u32(0x00000001), u32(0xFFFFFFFF), u32(0xFFFFFFFF);
    u32(28);
    u32(1), u32(20), u32(0x00000001), u32(65535), u32(20);  // link type 1, snaplen
    const auto padded = static_cast<std::uint32_t>((frame.size() + 3) / 4 * 4);
    u32(6), u32(32 + padded), u32(0), u32(0x0005F5E1), u32(0x00000000);
    u32(static_cast<std::uint32_t>(frame.size())), u32(static_cast<std::uint32_t>(frame.size()));
    test::append(b, frame);
    b.resize(b.size() + (padded - frame.size()), 0);
    u32(32 + padded);
    return b;
}

void pcap_files(SeedWriter& w) {
    const std::string t = "fuzz_pcap_reader";
    const Scratch s;
    for (const bool ns : {true, false}) {
        {
            pcap::Writer pw(s.path.string(), ns);
            const pcap::Endpoint src{{192, 168, 1, 201}, 2368}, dst{{192, 168, 1, 77}, 2368};
            for (int k = 0; k < 3; ++k)
                pw.write(1'700'000'000'000'000'000 + k * 1'000'000, src, dst, test::pattern(80));
            if (ns)
                pw.write(1'700'000'000'010'000'000, src, dst, test::pattern(2000));  // 2 fragments
            pw.close();
        }
        w.put(t, ns ? "writer_ns.pcap" : "writer_us.pcap", slurp(s.path));
    }
    Bytes sll = {0, 0, 0, 1, 0, 6, 0x60, 0x76, 0x88, 0, 0, 1, 0, 0, 0x08, 0x00};
    test::append(sll, test::ipv4(17, test::udp(2368, 2368, test::pattern(40))));
    test::write_raw_pcap(s.path.string(), 113, {{1'700'000'000'000'000'000, sll, 0}});
    w.put(t, "sll.pcap", slurp(s.path));
    w.put(t, "ethernet.pcapng", pcapng_file(udp_frames(60, 1500, 3)[0]));
}

void las_files(SeedWriter& w) {
    const Scratch s;
    const auto georef = core::Georef::projected(32632, {500000, 5000000, 0});
    for (const std::uint8_t format :
         {std::uint8_t{1}, std::uint8_t{3}, std::uint8_t{6}, std::uint8_t{7}}) {
        las::LasWriterOptions o;
        o.point_format = format;
        {
            // Formats 6/7 with the WKT VLR of a georeference, 1/3 without.
            las::LasWriter lw(s.path.string(), format >= 6 ? georef : core::Georef{}, o);
            lw.write(test::make_points(6, format, 5, 31, 50.0));
            lw.close();
        }
        w.put("fuzz_las", "format" + std::to_string(format) + ".las", slurp(s.path));
    }
    // Full-waveform formats: packets of 8 samples in the EVLR (a packet per two returns), echo
    // fields in extra bytes.
    for (const std::uint8_t format :
         {std::uint8_t{4}, std::uint8_t{5}, std::uint8_t{9}, std::uint8_t{10}}) {
        las::LasWriterOptions o;
        o.point_format = format;
        o.waveform.samples = 8;
        o.waveform.bits = format == 4 ? 8 : 16;
        o.echo_fields = true;
        auto pts = test::make_points(6, format, 5, 31, 50.0);
        std::vector<std::uint32_t> samples(24);
        for (std::size_t k = 0; k < samples.size(); ++k) samples[k] = std::uint32_t(100 + 37 * k);
        for (std::size_t k = 0; k < pts.size(); ++k) {
            pts[k].wave = std::uint32_t(8 * (k / 2));
            pts[k].wave_location_ps = float(1000 * (k % 2 + 2));
            pts[k].beam_dz = -1;
        }
        {
            las::LasWriter lw(s.path.string(), format >= 6 ? georef : core::Georef{}, o);
            lw.write_recorded(pts, samples);
            lw.close();
        }
        w.put("fuzz_las", "format" + std::to_string(format) + ".las", slurp(s.path));
    }
}

void trajectory_csv(SeedWriter& w) {
    const Scratch s;
    std::vector<core::StampedPose> poses(4);
    for (std::size_t k = 0; k < poses.size(); ++k) {
        poses[k].t =
            core::GpsTime(core::Nanos(1'400'000'000'000'000'000 + 250'000'000 * std::int64_t(k)));
        poses[k].pose.position = {1.5 * double(k), -0.25 * double(k), 0.1};
        poses[k].pose.attitude =
            Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * double(k), Eigen::Vector3d::UnitZ()));
    }
    core::save_trajectory_csv(s.path.string(), core::Trajectory(poses));
    const Bytes text = slurp(s.path);
    w.put("fuzz_trajectory_csv", "saved_xyz_quat.csv", 0, text);
    w.put("fuzz_trajectory_csv", "saved_xyz_quat_cubic.csv", 4, text);
}

}  // namespace

void write_file_seeds(SeedWriter& w) {
    pcap_frames(w);
    pcap_files(w);
    las_files(w);
    trajectory_csv(w);
}

}  // namespace mirage::testing::seeds
