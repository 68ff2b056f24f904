// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <span>

#include "mirage/render/pipeline.hpp"
#include "mirage/wire/packet.hpp"

namespace mirage::output {

// Pipeline points into a packetizer; pulses without returns still advance it, and finish() sends
// the last packet.
class PacketizerSink : public render::PointSink {
  public:
    explicit PacketizerSink(wire::Packetizer& p) : p_(p) {}
    void write(std::span<const core::PointRecord> points) override { p_.add(points); }
    void pulses_done(std::uint64_t next_pulse) override { p_.advance_to(next_pulse); }
    void finish() override { p_.finish(); }

  private:
    wire::Packetizer& p_;
};

}  // namespace mirage::output
