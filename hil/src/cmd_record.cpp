// SPDX-License-Identifier: Apache-2.0
// `mirage record`: arriving UDP datagrams with kernel receive timestamps into a nanosecond pcap
// (see mirage/replay/recorder.hpp). Exit 1 on a write error (the file keeps its whole records).
#include <fmt/format.h>

#include <cstdio>

#include "commands.hpp"
#include "mirage/replay/options.hpp"
#include "mirage/replay/recorder.hpp"
#include "stop_signal.hpp"

namespace mirage::hil {

void register_record(CLI::App& app) {
    struct Opts {
        replay::RecordConfig cfg;
        std::string listen;
        std::string duration;
        bool quiet = false;
    };
    auto o = std::make_shared<Opts>();
    auto* cmd = app.add_subcommand(
        "record", "Write arriving UDP datagrams with kernel timestamps into a pcap file");
    cmd->add_option("--listen", o->listen, "Ports to listen on, e.g. :2368,:8308")->required();
    cmd->add_option("--bind-host", o->cfg.bind_host, "Local IPv4 address to bind")
        ->capture_default_str();
    cmd->add_option("--out", o->cfg.out, "Output pcap (nanosecond timestamps)")->required();
    cmd->add_option("--duration", o->duration, "Stop after S seconds (default: SIGINT/SIGTERM)");
    cmd->add_flag("-q,--quiet", o->quiet, "No status line");
    cmd->callback([o] {
        auto cfg = o->cfg;
        cfg.ports = replay::parse_listen_ports(o->listen);
        if (!o->duration.empty())
            cfg.duration_ns = replay::parse_seconds_ns(o->duration, "record --duration");
        const auto& stop = install_stop_signal();
        replay::Recorder rec(cfg);
        std::string bound;
        for (auto p : rec.ports()) bound += fmt::format("{}:{} ", cfg.bind_host, p);
        std::fputs(fmt::format("record: listening on {}-> {}\n", bound, cfg.out).c_str(), stderr);
        const bool quiet = o->quiet;
        const auto r = rec.run(stop, [quiet](const replay::RecordStatus& s) {
            if (quiet) return;
            std::string line = "record:";
            const double secs = static_cast<double>(s.interval_ns) * 1e-9;
            for (std::size_t i = 0; i < s.ports.size(); ++i)
                line += fmt::format(" :{} {:.0f} pkt/s ({} total)", s.ports[i],
                                    static_cast<double>(s.packets_last[i]) / secs, s.packets[i]);
            std::fputs((line + "\n").c_str(), stderr);
        });
        std::uint64_t total = 0;
        for (auto n : r.totals.packets) total += n;
        fmt::print("record: {} datagrams received, {} written to {} ({} bytes){}\n", total,
                   r.written, cfg.out, r.file_bytes,
                   r.truncated ? fmt::format(", {} truncated", r.truncated) : "");
        if (r.out_of_order > 0)
            fmt::print(
                "record: {} datagrams were read over 50 ms after their receive time and "
                "follow later ones in the file\n",
                r.out_of_order);
        if (!r.error.empty()) {
            fmt::print(stderr, "record: ERROR {} (file cut to its last whole record)\n", r.error);
            throw CLI::RuntimeError(1);
        }
    });
}

}  // namespace mirage::hil
