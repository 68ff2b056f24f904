// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

#include "mirage/nav/decode_counters.hpp"
#include "mirage/nav/nav_sample.hpp"
#include "mirage/nav/resync_buffer.hpp"

namespace mirage::novatel {

// Incremental NovAtel OEM7 binary decoder: feed() takes any split of the byte stream. Order of
// checks per frame: sync (AA 44 12 / AA 44 13), header length, body length ≤ kMaxBodyLength
// (before waiting for the body), CRC-32, message id, body size, field values.
//  - bytes skipped while hunting for a sync count as garbage_bytes;
//  - a frame whose CRC fails counts bad_checksum, or truncated when a sync sequence appears
//    inside it (the next frame arrived before this one ended); an announced body longer than
//    kMaxBodyLength counts truncated. Decoding then resumes one byte after the rejected sync, so
//    a real frame hidden behind a false sync is still found (its skipped bytes count as garbage);
//  - valid CRC but an id other than BESTPOS/INSPVA/INSPVAS/INSPVAX (or an ASCII/response
//    format) counts unsupported.
// Never throws, never reads outside its buffer.
class NovatelDecoder {
  public:
    NovatelDecoder();
    void feed(std::span<const std::uint8_t> bytes, const nav::SampleFn& on_sample);
    // End of stream: a frame still waiting for bytes counts truncated, and the bytes after its
    // sync are scanned without waiting (a false sync near the end must not hide real frames).
    void finish(const nav::SampleFn& on_sample = nullptr);
    void reset();

    const nav::DecodeCounters& counters() const { return counters_; }

  private:
    // Decodes what is buffered; `flushing`: no more bytes will come.
    void process(bool flushing, const nav::SampleFn& on_sample);
    nav::FrameLength frame_length(std::span<const std::uint8_t> rest, bool flushing);
    void handle_frame(std::span<const std::uint8_t> frame, bool long_header,
                      const nav::SampleFn& on_sample);
    void emit(const nav::NavSample& s, const nav::SampleFn& on_sample);

    nav::ResyncBuffer buf_;
    nav::DecodeCounters counters_;
};

}  // namespace mirage::novatel
