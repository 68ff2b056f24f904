// SPDX-License-Identifier: Apache-2.0
#include "mirage/velodyne/packetizer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/core/rounding.hpp"
#include "mirage/sensor/spinning.hpp"
#include "mirage/velodyne/sensor_clock.hpp"

namespace mirage::velodyne {
namespace {

std::string prefix(const ModelDescriptor& m) { return "velodyne " + std::string(m.name) + ": "; }

PacketizerOptions from_sensor(const ModelDescriptor& model, ReturnMode mode,
                              const sensor::SensorModel& s, core::GpsTime start,
                              PacketizerOptions opt) {
    const auto* sp = dynamic_cast<const sensor::SpinningPattern*>(s.scan.get());
    if (sp == nullptr)
        throw ConfigError(prefix(model) + "sensor '" + s.name + "' has no spinning scan pattern");
    const auto& cfg = sp->config();
    const auto fail = [&](const std::string& what) {
        throw ConfigError(prefix(model) + "sensor '" + s.name + "' does not match the " +
                          std::string(model.product) + " wire format: " + what);
    };
    if (static_cast<int>(cfg.lasers.size()) != model.lasers)
        fail(std::to_string(cfg.lasers.size()) + " lasers, expected " +
             std::to_string(model.lasers));
    if (std::abs(cfg.sequence_period_ns - static_cast<double>(model.sequence_period_ns)) > 0.5)
        fail("firing sequence period " + std::to_string(cfg.sequence_period_ns) + " ns, expected " +
             std::to_string(model.sequence_period_ns));
    for (std::size_t l = 0; l < cfg.lasers.size(); ++l) {
        const auto& a = cfg.lasers[l];
        const auto& b = model.laser[l];
        if (std::llround(a.firing_offset_ns) != b.firing_offset_ns ||
            std::abs(a.elevation_deg - b.elevation_deg) > 1e-9 ||
            std::abs(a.azimuth_offset_deg - b.azimuth_offset_deg) > 1e-9)
            fail("laser " + std::to_string(l) + " differs in timing or angles");
    }
    opt.mode = mode;
    opt.rpm = sp->rpm();
    opt.start = start;
    opt.max_range_m = s.receiver.max_range_m;
    return opt;
}

}  // namespace

Packetizer::Packetizer(const ModelDescriptor& model, PacketizerOptions options, wire::PacketFn sink)
    : model_(model), opt_(std::move(options)), sink_(std::move(sink)) {
    if (!(opt_.rpm >= model_.rpm_min && opt_.rpm <= model_.rpm_max)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "rpm %g outside %g–%g", opt_.rpm, model_.rpm_min,
                      model_.rpm_max);
        throw ConfigError(prefix(model_) + buf);
    }
    step_deg_ = model_.azimuth_step_deg(opt_.rpm);
    seqs_per_packet_ = model_.sequences_per_packet(opt_.mode);
    pulses_per_packet_ =
        static_cast<std::uint64_t>(seqs_per_packet_) * static_cast<std::uint64_t>(model_.lasers);
    slots_.assign(pulses_per_packet_, SlotState{});
}

Packetizer::Packetizer(const ModelDescriptor& model, ReturnMode mode,
                       const sensor::SensorModel& sensor, core::GpsTime start, wire::PacketFn sink,
                       PacketizerOptions options)
    : Packetizer(model, from_sensor(model, mode, sensor, start, std::move(options)),
                 std::move(sink)) {}

core::GpsTime Packetizer::sequence_time(std::uint64_t sequence) const {
    return opt_.start +
           core::Nanos(static_cast<std::int64_t>(sequence) * model_.sequence_period_ns);
}

std::uint16_t Packetizer::sequence_azimuth(std::uint64_t sequence) const {
    // Rotor azimuth of the sequence's first firing, as SpinningPattern: wrap(s·step).
    double az = std::fmod(static_cast<double>(sequence) * step_deg_, 360.0);
    if (az < 0) az += 360.0;
    return static_cast<std::uint16_t>(std::llround(az * 100.0) % kAzimuthCounts);
}

core::GpsTime Packetizer::packet_send_time(std::uint64_t packet) const {
    const std::uint64_t last_seq = (packet + 1) * static_cast<std::uint64_t>(seqs_per_packet_) - 1;
    return sequence_time(last_seq) + core::Nanos(model_.last_firing_offset_ns());
}

std::uint8_t Packetizer::reflectivity_of(std::uint16_t intensity) {
    // Calibrated intensity 0..65535 → reflectivity byte 0..255.
    return static_cast<std::uint8_t>((static_cast<std::uint32_t>(intensity) + 128u) / 257u);
}

void Packetizer::add(std::span<const core::PointRecord> points) {
    if (finished_) return;
    const auto lasers = static_cast<std::uint64_t>(model_.lasers);
    for (const core::PointRecord& p : points) {
        ++stats_.returns_in;
        const std::uint64_t seq = p.pulse / lasers;
        const std::uint64_t packet = seq / static_cast<std::uint64_t>(seqs_per_packet_);
        if (packet < packet_) continue;  // out of order (contract: never happens)
        if (packet > packet_) emit_through(packet);
        if (p.channel >= lasers) {
            ++stats_.returns_bad_channel;
            continue;
        }
        const double raw =
            core::round_half_away(static_cast<double>(p.range_m) / model_.distance_lsb_m);
        if (!(static_cast<double>(p.range_m) <= opt_.max_range_m) || !(raw >= 1.0) ||
            raw > 65535.0) {
            ++stats_.returns_out_of_range;
            continue;
        }
        const auto q = seq % static_cast<std::uint64_t>(seqs_per_packet_);
        SlotState& s = slots_[q * lasers + p.channel];
        const Ret r{p.range_m, p.n_laser, std::max<std::uint8_t>(p.return_number, 1),
                    reflectivity_of(p.intensity)};
        if (r.n > s.strongest.n) {
            s.second = s.strongest;
            s.strongest = r;
        } else if (r.n > s.second.n) {
            s.second = r;
        }
        if (!s.last.valid() || r.number > s.last.number ||
            (r.number == s.last.number && r.range_m > s.last.range_m))
            s.last = r;
    }
}

void Packetizer::advance_to(std::uint64_t next_pulse) {
    if (finished_) return;
    emit_through(next_pulse / pulses_per_packet_);
}

void Packetizer::emit_side_packets_until(core::GpsTime t) {
    if (finished_) return;
    emit_positions_until(std::min(t, packet_send_time(packet_)));
}

void Packetizer::finish() {
    // The packet being filled is partial (its pulses were not all delivered): dropped.
    finished_ = true;
}

void Packetizer::emit_through(std::uint64_t packet_exclusive) {
    while (packet_ < packet_exclusive) {
        emit_packet();
        ++packet_;
        std::fill(slots_.begin(), slots_.end(), SlotState{});
    }
}

core::GpsTime Packetizer::stamp(core::GpsTime t) const {
    return opt_.clock_step ? t + core::Nanos(opt_.clock_step->load(std::memory_order_relaxed)) : t;
}

void Packetizer::emit_positions_until(core::GpsTime t) {
    if (!opt_.position_packets || model_.position_layout == PositionLayout::None ||
        model_.position_period_ns <= 0)
        return;
    for (;;) {
        const core::GpsTime pt =
            opt_.start +
            core::Nanos(static_cast<std::int64_t>(position_next_) * model_.position_period_ns);
        if (pt > t) return;
        const GeoFix fix = opt_.position ? opt_.position(pt) : opt_.fixed_position;
        encode_position(model_.position_layout, stamp(pt), fix, opt_.position_options, pos_buf_);
        ++position_next_;
        ++stats_.position_packets;
        if (sink_) sink_(wire::PacketView{wire::Stream::Position, pt, pos_buf_});
    }
}

void Packetizer::emit_packet() {
    const auto S = static_cast<std::uint64_t>(seqs_per_packet_);
    const std::uint64_t s0 = packet_ * S;
    RawDataPacket raw;
    for (int b = 0; b < kBlocksPerPacket; ++b) {
        RawBlock& rb = raw.block[static_cast<std::size_t>(b)];
        rb.flag = model_.block_flag(b);
        rb.azimuth =
            sequence_azimuth(s0 + static_cast<std::uint64_t>(model_.block_sequence(opt_.mode, b)));
    }
    const bool dual = opt_.mode == ReturnMode::Dual;
    const auto put = [&](int q, int l, int r, const Ret& v) {
        if (!v.valid()) return;
        const BlockSlot bs = model_.locate(opt_.mode, q, l, r);
        RawChannel& ch = raw.block[static_cast<std::size_t>(bs.block)]
                             .channel[static_cast<std::size_t>(bs.slot)];
        ch.distance = static_cast<std::uint16_t>(
            core::round_half_away(static_cast<double>(v.range_m) / model_.distance_lsb_m));
        ch.reflectivity = v.reflectivity;
    };
    for (int q = 0; q < seqs_per_packet_; ++q)
        for (int l = 0; l < model_.lasers; ++l) {
            const SlotState& s = slots_[static_cast<std::size_t>(q * model_.lasers + l)];
            if (!dual) {
                put(q, l, 0, opt_.mode == ReturnMode::Last ? s.last : s.strongest);
                continue;
            }
            // §1.5: even block = last; odd = strongest, or the second strongest when the
            // strongest is the last; identical blocks when there is a single return.
            const Ret& other = s.strongest.number != s.last.number ? s.strongest
                               : s.second.valid()                  ? s.second
                                                                   : s.strongest;
            put(q, l, 0, s.last);
            put(q, l, 1, other);
        }
    const core::GpsTime t0 = stamp(sequence_time(s0));
    raw.timestamp_us = micros_past_hour(t0);
    if (model_.hdl64_status) {
        // §1.10: a 16-byte status cycle, one byte per packet: 9 hardware status bytes
        // (H M S D N Y G T V) then 7 calibration bytes (not emulated: zero).
        const UtcFields u = utc_fields(t0);
        const std::uint64_t pos = packet_ % 16;
        static constexpr char kTypes[9] = {'H', 'M', 'S', 'D', 'N', 'Y', 'G', 'T', 'V'};
        const int values[9] = {u.hour,
                               u.minute,
                               u.second,
                               u.day,
                               u.month,
                               u.year % 100,
                               opt_.hdl64_gps_status,
                               opt_.hdl64_temperature_c,
                               0x29};
        if (pos < 9) {
            raw.factory1 = static_cast<std::uint8_t>(kTypes[pos]);
            raw.factory2 = static_cast<std::uint8_t>(values[pos]);
        }
    } else {
        raw.factory1 = static_cast<std::uint8_t>(opt_.mode);
        raw.factory2 = opt_.product_id.value_or(model_.product_id);
    }
    encode_data(raw, buf_);
    const core::GpsTime send = packet_send_time(packet_);
    emit_positions_until(send);
    ++stats_.data_packets;
    if (sink_) sink_(wire::PacketView{wire::Stream::Data, send, buf_});
}

}  // namespace mirage::velodyne
