// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

namespace mirage::replay {

// One datagram on the replay schedule. time_ns: capture time relative to the replay's start
// (before any speed scaling).
struct Packet {
    std::int64_t time_ns = 0;
    std::uint16_t dst_port = 0;
    std::vector<std::uint8_t> payload;
};

// Seeded network faults for robustness tests of downstream processors. Applied in this order:
//   drop       with probability `drop` a drop event starts at a packet and removes it and the
//              next drop_burst − 1 packets (bursts: a lost switch buffer, not single losses);
//   reorder    with probability `reorder` a packet is swapped with the one after it (the two
//              payloads exchange places; the schedule times stay where they were);
//   duplicate  with probability `duplicate` a packet is sent twice (the copy right after it);
//   jitter     every packet is delayed by a uniform random 0..jitter_ns (never early; packets
//              are still sent in order, so a delayed packet also delays the ones behind it).
// The same seed and input give the same output.
struct ImpairmentConfig {
    double drop = 0.0;
    std::uint32_t drop_burst = 1;
    double duplicate = 0.0;
    double reorder = 0.0;
    std::int64_t jitter_ns = 0;
    std::uint64_t seed = 1;
    bool active() const { return drop > 0 || duplicate > 0 || reorder > 0 || jitter_ns > 0; }
};

struct ImpairmentCounters {
    std::uint64_t in = 0, out = 0, dropped = 0, drop_events = 0, duplicated = 0, reordered = 0;
};

class Impairer {
  public:
    // Throws ConfigError for rates outside [0, 1], a zero burst or negative jitter.
    explicit Impairer(const ImpairmentConfig& config);

    // Takes one packet; appends the packets now ready (0, 1 or 2 or 3) to `out`.
    void push(Packet&& p, std::vector<Packet>& out);
    // End of input: appends a packet held back for reordering.
    void finish(std::vector<Packet>& out);
    const ImpairmentCounters& counters() const { return counters_; }

  private:
    bool chance(double p);
    void emit(Packet&& p, std::vector<Packet>& out);

    ImpairmentConfig config_;
    std::mt19937_64 rng_;
    std::uint32_t burst_left_ = 0;
    std::optional<Packet> held_;
    ImpairmentCounters counters_;
};

}  // namespace mirage::replay
