// SPDX-License-Identifier: Apache-2.0
#include "stream_report.hpp"

#include <algorithm>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <sstream>

#include "report_figure.hpp"

namespace mirage::hil {
namespace {

std::string yes_no(bool b) { return b ? "yes" : "no"; }

void md_encoder(std::ostream& o, const Report& r) {
    o << "## Encoder throughput (synthetic returns for every pulse, no-op packet sink)\n\n";
    o << "| model / mode | pulses | data packets | position/IMU | MB | encode s | packets/s | "
         "device packets/s | headroom × | as emulate builds it: packets/s | headroom × |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& e : r.encoder)
        o << fmt::format(
            "| {} | {} | {} | {} | {:.1f} | {:.3f} | {:.0f} | {:.1f} | {:.1f} | {:.0f} | {:.2f} "
            "|\n",
            e.label, e.pulses, e.packets, e.aux_packets, fig(static_cast<double>(e.bytes) / 1e6),
            fig(e.seconds), fig(e.packets_per_s), fig(e.device_packets_per_s), fig(e.headroom()),
            fig(e.emulate_packets_per_s), fig(e.emulate_headroom()));
    o << "\nThe encoder alone uses a fixed position fix (Velodyne) and the static pose (Ouster "
         "IMU); \"as emulate builds it\" goes through wire::make_wire, whose Velodyne position "
         "packets take the fix from the trajectory through Georef::geodetic_from_local (once per "
         "UTC second).\n";
}

std::string sender_description(const StreamsResult& s) {
    const std::string awake =
        s.keep_awake_threads == 0
            ? std::string()
            : fmt::format(
                  "; pinned to a CPU that a SCHED_IDLE spinner keeps out of idle "
                  "(--keep-awake{})",
                  s.keep_awake_warning.empty() ? "" : ": " + s.keep_awake_warning);
    return fmt::format(
        "{} {}{}",
        s.shared ? "one shared deadline-ordered sending thread (--sender shared)"
                 : "each stream paced and sent by its writer thread (--sender per-stream)",
        s.fifo_priority > 0 && s.fifo ? fmt::format("SCHED_FIFO {}{}", s.fifo_priority,
                                                    s.shared ? " (writer threads SCHED_OTHER)" : "")
        : s.fifo_priority > 0         ? fmt::format("SCHED_OTHER (FIFO refused: {})", s.fifo_error)
                                      : std::string("SCHED_OTHER"),
        awake);
}

// "Three streams", or "The 5 sensors of rig 'car.yaml'".
std::string streams_title(const StreamsResult& s) {
    if (s.rig.empty()) return "Three streams";
    return fmt::format("The {} sensors of rig '{}'", s.rows.size(), s.rig);
}

double share(double part_s, double wall_s) { return wall_s > 0 ? 100 * part_s / wall_s : 0.0; }

void md_streams_intro(std::ostream& o, const Report& r) {
    const auto& s = r.streams;
    o << fmt::format(
        "\n## {} at once in real time ({} s, trajectory {}, {} render worker "
        "thread(s) per stream, {} pulses per chunk, renderers up to {:.0f} ms ahead, {})\n\n",
        streams_title(s), r.seconds, s.trajectory, s.render_threads, s.chunk_pulses,
        fig(s.render_lead_ms), sender_description(s));
    o << fmt::format(
        "CPU used (getrusage user+sys / wall): {:.1f} % of one core ({:.2f} s CPU in {:.2f} s "
        "wall, {} cores).\n\n",
        fig(s.cpu_percent()), fig(s.cpu_s), fig(s.wall_s), r.machine.cores);
    if (s.shared)
        o << fmt::format(
            "Shared sending thread: {:.1f} % of one core (sleep to {} µs before the earliest "
            "deadline, spin, send); {} early wake-ups by a submit; {} submits held back by the "
            "{:.0f} ms horizon, {} by a full queue. Its timed sleeps ended {:.0f} µs (p50) / "
            "{:.0f} µs (p99) after the instant asked for: a wake-up later than the spin margin "
            "makes the packet late by the difference.\n\n",
            fig(share(s.sender_cpu_s, s.wall_s)), s.spin_margin_us, s.sender_wakeups,
            s.horizon_waits, fig(s.horizon_ms), s.full_waits, fig(s.wake_late_p50_us),
            fig(s.wake_late_p99_us));
}

void md_stream_table(std::ostream& o, const StreamsResult& s) {
    o << "| stream | device pkt/s | received pkt/s | rate error % | data sent | data received | "
         "expected | aux sent/recv | failed sends | pacer late >100 µs | pacer p99 µs | pacer "
         "worst µs | send call p50/p99 µs | handed >1 ms late | worst hand-over ms | real time "
         "|\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
    for (const auto& t : s.rows)
        o << fmt::format(
            "| {} | {:.2f} | {:.2f} | {:+.3f} | {} | {} | {:.0f} | {}/{} | {} | {} | {:.0f} | "
            "{:.0f} | {:.0f}/{:.0f} | {} | {:+.2f} | {} |\n",
            t.label, fig(t.device_packets_per_s), fig(t.rx_packets_per_s), fig(100 * t.rate_error),
            t.data_sent, t.data_received, fig(t.expected_data), t.aux_sent, t.aux_received,
            t.failed_sends, t.pacer_late, fig(t.pacer_p99_us), fig(t.pacer_worst_us),
            fig(t.send_p50_us), fig(t.send_p99_us), t.handed_late_1ms, fig(t.handed_worst_ms),
            yes_no(t.real_time));
    for (const auto& t : s.rows)
        if (t.handed_late_1ms > 0)
            o << fmt::format(
                "\n{}: the {} late hand-overs fell between {:.3f} s and {:.3f} s of the "
                "schedule.\n",
                t.label, t.handed_late_1ms, fig(t.late_first_s), fig(t.late_last_s));
}

void md_lateness_and_cpu(std::ostream& o, const StreamsResult& s) {
    o << "\nPacing error seen by the loopback receiver (SO_TIMESTAMPNS kernel time − scheduled "
         "time, every packet incl. position / IMU):\n\n"
         "| stream | packets | p50 µs | p99 µs | max µs | min µs | drift µs | lost | unmatched |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& t : s.rows)
        o << fmt::format("| {} | {} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:+.1f} | {} | {} |\n",
                         t.label, t.wire.count, us(t.wire.p50), us(t.wire.p99), us(t.wire.max),
                         us(t.wire.min), us(t.wire.drift), t.lost, t.unmatched);
    o << "\nWhere the CPU goes, per stream (thread CPU time over the wall time, % of one core): "
         "render = rays + Embree + physics on the worker(s); output = the writer thread inside the "
         "sink: encoding, position / IMU fixes, and with --sender per-stream also the Pacer's "
         "last-50-µs spin and the sends (with --sender shared: the copy into the shared "
         "sender's queue).\n\n"
         "| stream | pulses | points | render % | output % |\n|---|---:|---:|---:|---:|\n";
    for (const auto& t : s.rows)
        o << fmt::format("| {} | {} | {} | {:.1f} | {:.1f} |\n", t.label, t.pulses, t.points,
                         fig(share(t.cpu_render_s, s.wall_s)),
                         fig(share(t.cpu_output_s, s.wall_s)));
    for (const auto& t : s.rows)
        if (!t.error.empty()) o << fmt::format("\nError in {}: {}\n", t.label, t.error);
}

std::string floor_figures(const Floor& f) {
    return fmt::format(
        "instants delayed by more than 50 µs {:.3f} %, delay exceeded by 1 % of instants {:.0f} "
        "µs, longest gap {:.0f} µs",
        100 * f.share_50us, f.p99_us, f.worst_us);
}

// Issue 22 item 3: receiver lateness p99 ≤ the floor's p99 + 20 µs; share of packets later than
// 50 µs ≤ 1.5 × the floor's share of instants delayed by more than 50 µs. With --keep-awake the
// floor was measured with the spinners on and off; the targets take the stricter of each figure.
void md_floor(std::ostream& o, const Report& r) {
    Floor f = r.floor;
    if (f.seconds <= 0) return;
    o << "\n## Against the machine's floor\n\n";
    if (r.floor_plain.seconds > 0) {
        const Floor& p = r.floor_plain;
        o << fmt::format(
            "Floor: a thread spinning on the clock on the sender's CPU, {:.1f} s with it kept "
            "awake (a quarter just before the streams, a quarter just after): {}; and {:.1f} s "
            "without (a quarter before those, a quarter after): {}. The targets take the "
            "stricter of each figure.\n\n",
            f.seconds, floor_figures(f), p.seconds, floor_figures(p));
        f.p99_us = std::min(f.p99_us, p.p99_us);
        f.share_50us = std::min(f.share_50us, p.share_50us);
    } else {
        o << fmt::format(
            "Floor: a thread spinning on the clock for {:.1f} s (half just before the streams, "
            "half just after): {}.\n\n",
            f.seconds, floor_figures(f));
    }
    o << "| stream | receiver p99 µs | floor p99 + 20 µs | met | packets > 50 µs late % | 1.5 × "
         "floor % | met |\n|---|---:|---:|---|---:|---:|---|\n";
    for (const auto& t : r.streams.rows)
        o << fmt::format("| {} | {:.1f} | {:.1f} | {} | {:.3f} | {:.3f} | {} |\n", t.label,
                         us(t.wire.p99), f.p99_us + 20, yes_no(us(t.wire.p99) <= f.p99_us + 20),
                         100 * t.wire_late_50us_share, 150 * f.share_50us,
                         yes_no(t.wire_late_50us_share <= 1.5 * f.share_50us));
}

void md_probes(std::ostream& o, const Report& r) {
    if (r.probes.empty()) {
        o << "\n## Pacing probe\n\nNot run (--probe-seconds 0).\n";
        return;
    }
    o << "\n## Pacing probe (mirage::udp::run_pacing_probe, 1206-byte datagrams over loopback, "
         "10 000 packets per second)\n\n"
         "| run | packets recv/sched | p50 µs | p99 µs | max µs | > 50 µs | drift µs | pacer "
         "wake p99 µs |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& p : r.probes) {
        if (!p.ran) {
            o << fmt::format("| {} | {} | | | | | | |\n", p.label, p.note);
            continue;
        }
        const auto& w = p.report.wire;
        o << fmt::format("| {} | {}/{} | {:.0f} | {:.0f} | {:.1f} | {} | {:+.1f} | {:.0f} |\n",
                         p.label, p.report.received, p.report.scheduled,
                         us(w.percentile(0.5).count()), us(w.percentile(0.99).count()),
                         us(w.worst().count()), w.late(), us(p.report.drift.count()),
                         us(p.report.pacer.percentile(0.99).count()));
    }
}

void md_targets(std::ostream& o, const Report& r) {
    const auto& s = r.streams;
    bool all_rt = !s.rows.empty(), rates_ok = true;
    std::int64_t worst_p99 = 0, worst_drift = 0;
    std::uint64_t late_total = 0, lost_total = 0, sent_total = 0;
    for (const auto& t : s.rows) {
        all_rt = all_rt && t.real_time;
        rates_ok = rates_ok && std::abs(t.rate_error) <= 0.005;
        late_total += t.handed_late_1ms;
        lost_total += t.data_sent - std::min(t.data_sent, t.data_received);
        sent_total += t.data_sent;
        worst_p99 = std::max(worst_p99, t.wire.p99);
        worst_drift = std::max(worst_drift, std::abs(t.wire.drift));
    }
    o << (s.rig.empty() ? "\n## Targets (issue 3)\n\n" : "\n## Targets (issue 22, item 2)\n\n");
    o << fmt::format(
        "- {} at once in real time on {} cores: {} (CPU {:.1f} % of one core; "
        "{} of {} data packets lost; {} packets handed to the sender more than 1 ms after their "
        "send time; rates within 0.5 %: {}).\n",
        streams_title(s), r.machine.cores, all_rt ? "met" : "NOT met", fig(s.cpu_percent()),
        lost_total, sent_total, late_total, yes_no(rates_ok));
    o << fmt::format(
        "- Pacing p99 ≤ 50 µs (receiver, worst stream, {} sender): {} ({:.1f} µs; machine load "
        "average at start {}).\n",
        s.shared ? "shared" : "per-stream", worst_p99 <= 50'000 ? "met" : "NOT met", us(worst_p99),
        r.machine.load);
    o << fmt::format("- No drift (|drift| ≤ 10 µs over the run, worst stream): {} ({:.1f} µs).\n",
                     worst_drift <= 10'000 ? "met" : "NOT met", us(worst_drift));
}

nlohmann::ordered_json encoder_json(const EncoderRow& e) {
    return {{"name", e.label},
            {"pulses", e.pulses},
            {"packets", e.packets},
            {"bytes", e.bytes},
            {"aux_packets", e.aux_packets},
            {"encode_seconds", e.seconds},
            {"packets_per_s", e.packets_per_s},
            {"device_packets_per_s", e.device_packets_per_s},
            {"headroom", e.headroom()},
            {"emulate_packets_per_s", e.emulate_packets_per_s},
            {"emulate_headroom", e.emulate_headroom()}};
}

nlohmann::ordered_json streams_run_json(const StreamsResult& s) {
    return {{"wall_seconds", s.wall_s},
            {"cpu_seconds", s.cpu_s},
            {"cpu_percent", s.cpu_percent()},
            {"render_threads", s.render_threads},
            {"chunk_pulses", s.chunk_pulses},
            {"render_lead_ms", s.render_lead_ms},
            {"trajectory", s.trajectory},
            {"rig", s.rig},
            {"sender", s.shared ? "shared" : "per-stream"},
            {"fifo", s.fifo},
            {"spin_margin_us", s.spin_margin_us},
            {"sender_cpu_seconds", s.sender_cpu_s},
            {"sender_wakeups", s.sender_wakeups},
            {"horizon_waits", s.horizon_waits},
            {"full_waits", s.full_waits},
            {"sender_wake_late_p50_us", s.wake_late_p50_us},
            {"sender_wake_late_p99_us", s.wake_late_p99_us},
            {"keep_awake_threads", s.keep_awake_threads}};
}

nlohmann::ordered_json stream_json(const StreamRow& t) {
    return {{"name", t.label},
            {"device_packets_per_s", t.device_packets_per_s},
            {"expected_data_packets", t.expected_data},
            {"sent_data_packets", t.data_sent},
            {"received_data_packets", t.data_received},
            {"received_packets_per_s", t.rx_packets_per_s},
            {"late_over_50us_share", t.wire_late_50us_share},
            {"rate_error", t.rate_error},
            {"sent_aux_packets", t.aux_sent},
            {"received_aux_packets", t.aux_received},
            {"failed_sends", t.failed_sends},
            {"lost", t.lost},
            {"unmatched", t.unmatched},
            {"pacer_late", t.pacer_late},
            {"pacer_p99_us", t.pacer_p99_us},
            {"pacer_worst_us", t.pacer_worst_us},
            {"send_p50_us", t.send_p50_us},
            {"send_p99_us", t.send_p99_us},
            {"handed_late_1ms", t.handed_late_1ms},
            {"handed_worst_ms", t.handed_worst_ms},
            {"handed_ahead_p50_ms", t.handed_ahead_p50_ms},
            {"late_first_s", t.late_first_s},
            {"late_last_s", t.late_last_s},
            {"lateness_p50_us", us(t.wire.p50)},
            {"lateness_p99_us", us(t.wire.p99)},
            {"lateness_max_us", us(t.wire.max)},
            {"lateness_min_us", us(t.wire.min)},
            {"drift_us", us(t.wire.drift)},
            {"pulses", t.pulses},
            {"points", t.points},
            {"cpu_render_seconds", t.cpu_render_s},
            {"cpu_output_seconds", t.cpu_output_s},
            {"real_time", t.real_time},
            {"error", t.error}};
}

nlohmann::ordered_json probe_json(const ProbeRow& p) {
    const auto& w = p.report.wire;
    return {{"name", p.label},
            {"ran", p.ran},
            {"note", p.note},
            {"scheduled", p.report.scheduled},
            {"received", p.report.received},
            {"p50_us", us(w.percentile(0.5).count())},
            {"p99_us", us(w.percentile(0.99).count())},
            {"max_us", us(w.worst().count())},
            {"over_50us", w.late()},
            {"drift_us", us(p.report.drift.count())}};
}

}  // namespace

std::string stream_markdown(const Report& r) {
    std::ostringstream o;
    o << "# mirage stream-bench\n\n";
    o << fmt::format(
        "Machine: {}, {} cores, {}; load average at start {}. Run: --seconds {}{}.\n\n",
        r.machine.cpu, r.machine.cores, r.machine.kernel, r.machine.load, r.seconds,
        r.quick ? " --quick" : "");
    if (!r.encoder.empty()) md_encoder(o, r);
    md_streams_intro(o, r);
    md_stream_table(o, r.streams);
    md_lateness_and_cpu(o, r.streams);
    md_floor(o, r);
    md_probes(o, r);
    md_targets(o, r);
    return o.str();
}

// nlohmann-json serialises a NaN or infinite number as null (serializer::dump_float).
std::string stream_json(const Report& r) {
    nlohmann::ordered_json j = {{"machine",
                                 {{"cpu", r.machine.cpu},
                                  {"cores", r.machine.cores},
                                  {"kernel", r.machine.kernel},
                                  {"load_average", r.machine.load}}},
                                {"seconds", std::strtod(r.seconds.c_str(), nullptr)},
                                {"quick", r.quick},
                                {"scene_seconds", r.scene_seconds},
                                {"floor",
                                 {{"seconds", r.floor.seconds},
                                  {"delayed_share_over_50us", r.floor.share_50us},
                                  {"p99_us", r.floor.p99_us},
                                  {"worst_us", r.floor.worst_us}}},
                                {"floor_without_keep_awake",
                                 {{"seconds", r.floor_plain.seconds},
                                  {"delayed_share_over_50us", r.floor_plain.share_50us},
                                  {"p99_us", r.floor_plain.p99_us},
                                  {"worst_us", r.floor_plain.worst_us}}},
                                {"encoder", nlohmann::ordered_json::array()},
                                {"streams_run", streams_run_json(r.streams)},
                                {"streams", nlohmann::ordered_json::array()},
                                {"pacing_probe", nlohmann::ordered_json::array()}};
    for (const auto& e : r.encoder) j["encoder"].push_back(encoder_json(e));
    for (const auto& t : r.streams.rows) j["streams"].push_back(stream_json(t));
    for (const auto& p : r.probes) j["pacing_probe"].push_back(probe_json(p));
    return j.dump(2) + "\n";
}

}  // namespace mirage::hil
