// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <memory>
#include <span>

#include "mirage/core/point.hpp"

namespace mirage::render {

// A chunk of points a sink has encoded on a render worker: the sink's own type, see
// PointSink::new_encoded.
class EncodedPoints {
  public:
    virtual ~EncodedPoints() = default;
    virtual void clear() = 0;  // empty, keeping capacity: reused for later chunks
};

// Receives points in pulse order (deterministic whatever the thread count), one chunk at a time,
// from a single thread at a time.
class PointSink {
  public:
    virtual ~PointSink() = default;
    virtual void write(std::span<const core::PointRecord> points) = 0;
    // Called after each chunk's write: every pulse before `next_pulse` has been delivered. Packet
    // encoders need it because pulses without returns produce no points but still fill packets.
    virtual void pulses_done(std::uint64_t next_pulse) { (void)next_pulse; }
    // The end of the stream: completes what the sink feeds (a LAS file's header, a packetizer's
    // last packet). Called once by whoever drives the sink (render() at the end of its run, also
    // when stopped early), never after a failure: the exception propagates instead.
    virtual void finish() {}

    // Optional encoding on the render workers. A sink that returns a buffer here has each trace
    // batch's points passed to encode() on the worker that made them, while they are in cache
    // and in parallel, and then receives whole chunks, in order, through write_encoded() instead
    // of write(). new_encoded() and encode() are called from several threads at once.
    virtual std::unique_ptr<EncodedPoints> new_encoded() const { return nullptr; }
    virtual void encode(std::span<const core::PointRecord> points, EncodedPoints& out) const {
        (void)points;
        (void)out;
    }
    virtual void write_encoded(EncodedPoints& chunk) { (void)chunk; }

    // A render recording waveforms (RenderOptions::waveform_samples) calls these instead of
    // write() and encode(): `samples` holds the digitised windows the points refer to
    // (PointRecord::wave indexes it). A sink that does not store waveforms ignores them.
    virtual void write_recorded(std::span<const core::PointRecord> points,
                                std::span<const std::uint32_t> samples) {
        (void)samples;
        write(points);
    }
    virtual void encode_recorded(std::span<const core::PointRecord> points,
                                 std::span<const std::uint32_t> samples, EncodedPoints& out) const {
        (void)samples;
        encode(points, out);
    }
};

}  // namespace mirage::render
