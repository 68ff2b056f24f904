// SPDX-License-Identifier: Apache-2.0
// `mirage replay`: sends the UDP payloads of a capture with its timing (see
// mirage/replay/replayer.hpp), with optional seeded impairments. Exit 1 on a read error or
// failed sends, 2 when nothing was sent.
#include <fmt/format.h>

#include <cstdio>

#include "commands.hpp"
#include "keep_awake_option.hpp"
#include "mirage/core/error.hpp"
#include "mirage/replay/options.hpp"
#include "mirage/replay/replayer.hpp"
#include "stop_signal.hpp"

namespace mirage::hil {

void register_replay(CLI::App& app) {
    struct Opts {
        replay::ReplayConfig cfg;
        std::vector<std::string> port_map;
        std::string from, until;
        bool top = false;
        double jitter_us = 0;
        double spin_us = static_cast<double>(replay::ReplayConfig{}.spin_ns) / 1000.0;
        bool quiet = false, keep_awake = false;
    };
    auto o = std::make_shared<Opts>();
    auto* cmd = app.add_subcommand(
        "replay",
        "Send the UDP payloads of a pcap/pcapng capture to a host with the capture's timing");
    cmd->add_option("capture", o->cfg.path, "Capture file (classic pcap or pcapng)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--to", o->cfg.host, "Destination IPv4 host (every datagram goes there)")
        ->required();
    cmd->add_option("--port-map", o->port_map,
                    "CAPTURE_PORT=SEND_PORT, repeatable (other ports are kept)");
    cmd->add_option("--speed", o->cfg.speed, "Time scale: 2 = twice as fast; 0 = top speed")
        ->capture_default_str();
    cmd->add_flag("--top-speed", o->top, "As fast as possible (batched sendmmsg), like --speed 0");
    cmd->add_option("--loop", o->cfg.loops, "Passes over the file (0: until interrupted)")
        ->capture_default_str();
    cmd->add_option("--from", o->from, "Start T seconds after the first datagram (e.g. 1.5)");
    cmd->add_option("--until", o->until, "Stop T seconds after the first datagram");
    cmd->add_option("--filter", o->cfg.filter,
                    "libpcap filter expression (pcap-filter(7)), e.g. 'udp dst port 2368', "
                    "'src host 192.168.1.201 and not port 8308'; fragments are matched as the "
                    "whole datagram");
    cmd->add_option("--seed", o->cfg.impair.seed, "Seed of the impairments")->capture_default_str();
    cmd->add_option("--drop", o->cfg.impair.drop,
                    "Probability that a drop burst starts at a packet");
    cmd->add_option("--drop-burst", o->cfg.impair.drop_burst, "Packets lost per drop event")
        ->capture_default_str();
    cmd->add_option("--duplicate", o->cfg.impair.duplicate, "Probability a packet is sent twice");
    cmd->add_option("--reorder", o->cfg.impair.reorder,
                    "Probability a packet swaps places with the next one");
    cmd->add_option("--jitter-us", o->jitter_us, "Extra delay per packet, uniform in 0..S us");
    cmd->add_option("--spin-us", o->spin_us,
                    "Sleep until this long before each send time, then spin (timer wake-ups "
                    "are late by tens of us, more in VMs; more spin = more CPU, less jitter)")
        ->capture_default_str();
    cmd->add_flag("-q,--quiet", o->quiet, "No progress line");
    add_keep_awake_flag(*cmd, o->keep_awake);
    cmd->callback([o] {
        auto cfg = o->cfg;
        cfg.port_map = replay::parse_port_map(o->port_map);
        if (o->top) cfg.speed = 0.0;
        if (!o->from.empty()) cfg.from_ns = replay::parse_seconds_ns(o->from, "replay --from");
        if (!o->until.empty()) cfg.until_ns = replay::parse_seconds_ns(o->until, "replay --until");
        if (o->jitter_us < 0) throw ConfigError("replay --jitter-us: expected >= 0");
        cfg.impair.jitter_ns = static_cast<std::int64_t>(o->jitter_us * 1000.0);
        if (!(o->spin_us >= 0) || o->spin_us > 1e6)
            throw ConfigError("replay --spin-us: expected 0 to 1000000");
        cfg.spin_ns = static_cast<std::int64_t>(o->spin_us * 1000.0);
        const auto& stop = install_stop_signal();
        const auto awake = keep_cpus_awake(o->keep_awake && cfg.speed > 0, "replay");
        if (std::string why;
            awake && !hostclock::pin_current_thread(hostclock::sending_cpu_of(awake.get()), why))
            std::fprintf(stderr, "mirage replay: not pinned to %s; sending unpinned\n",
                         why.c_str());
        const bool quiet = o->quiet;
        const auto s = replay::replay(cfg, &stop, [quiet](const replay::ReplaySummary& p) {
            if (!quiet)
                std::fputs(fmt::format("replay: {} packets sent\n", p.packets).c_str(), stderr);
        });
        fmt::print("{}", replay::format_summary(s));
        std::fflush(stdout);
        if (!s.error.empty() || s.failed > 0) throw CLI::RuntimeError(1);
        if (s.packets == 0 && !s.stopped) throw CLI::RuntimeError(2);
    });
}

}  // namespace mirage::hil
