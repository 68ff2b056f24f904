// SPDX-License-Identifier: Apache-2.0
// Faults a controller injects into one sensor (docs/control.md §5): the control thread stores
// them, the sensor's threads load them per packet without a lock. Drops and range noise draw
// counter-based numbers keyed by (seed, sensor), so a run's faults repeat exactly.
#pragma once
#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include "mirage/wire/packet.hpp"

namespace mirage::control {

struct FaultSettings {
    std::uint16_t drop_rate = 0;   // chance a drop burst starts at a packet, in 1/10000
    std::uint16_t drop_burst = 1;  // packets per burst
    std::int16_t range_bias_mm = 0;
    std::uint16_t range_noise_mm = 0;  // σ of extra Gaussian range noise
    bool freeze_nav = false;
    bool stale_nav = false;
    bool stop = false;
    bool operator==(const FaultSettings&) const = default;
};

// One sensor's faults, written by one thread and read by others as one consistent set: all
// fields packed into one 64-bit word (rate 14 bits, burst 10, bias 16, noise 14, 3 flags), so a
// reader never sees half of a request's changes. Fields beyond their ranges (docs/control.md §2)
// are clamped.
class FaultCell {
  public:
    void store(const FaultSettings& f);
    FaultSettings load() const;

  private:
    std::atomic<std::uint64_t> word_{std::uint64_t{1} << 14};  // burst 1
};

// Decides which packets a burst drops, in packet order (one sensor's send path).
class PacketDropper {
  public:
    PacketDropper(std::uint64_t seed, std::uint32_t sensor) : seed_(seed), sensor_(sensor) {}
    bool drop(const FaultSettings& f);
    std::uint64_t dropped() const { return dropped_; }

  private:
    std::uint64_t seed_;
    std::uint32_t sensor_;
    std::uint64_t packet_ = 0;
    std::uint32_t burst_left_ = 0;
    std::uint64_t dropped_ = 0;
};

// A packetizer in front of another: range bias and noise on each return, and no returns at all
// while navigation is faulted stale (the slots still go out empty, as with real stale
// navigation). Passes points through untouched when the cell holds no such fault.
class FaultPacketizer final : public wire::Packetizer {
  public:
    FaultPacketizer(wire::Packetizer& inner, const FaultCell& cell, std::uint64_t seed,
                    std::uint32_t sensor)
        : inner_(inner), cell_(cell), seed_(seed), sensor_(sensor) {}
    void add(std::span<const core::PointRecord> points) override;
    void advance_to(std::uint64_t next_pulse) override { inner_.advance_to(next_pulse); }
    void emit_side_packets_until(core::GpsTime t) override { inner_.emit_side_packets_until(t); }
    void finish() override { inner_.finish(); }
    // Readable from any thread while the sensor runs (the control plane's counters).
    std::uint64_t points() const { return points_.load(std::memory_order_relaxed); }
    std::uint64_t stale_points() const { return stale_points_.load(std::memory_order_relaxed); }
    std::uint64_t stale_periods() const { return stale_periods_.load(std::memory_order_relaxed); }

  private:
    wire::Packetizer& inner_;
    const FaultCell& cell_;
    std::uint64_t seed_;
    std::uint32_t sensor_;
    std::vector<core::PointRecord> buf_;
    bool stale_ = false;
    std::atomic<std::uint64_t> points_{0}, stale_points_{0}, stale_periods_{0};
};

}  // namespace mirage::control
