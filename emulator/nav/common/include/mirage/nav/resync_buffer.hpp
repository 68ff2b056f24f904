// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace mirage::nav {

// What a byte means to a framer while it hunts for the start of a frame.
enum class ByteKind : std::uint8_t {
    Sync,     // a frame may start here
    Filler,   // skipped silently (NMEA's line ends between sentences)
    Garbage,  // skipped and counted
};

// What a framer makes of the bytes from a sync byte on.
struct FrameLength {
    enum class Kind : std::uint8_t {
        Complete,  // a whole frame of `bytes` bytes starts at the sync
        NeedMore,  // the candidate runs past the bytes buffered so far
        Skip,      // no frame here: drop `bytes` (≥ 1) bytes, counted as garbage if `garbage`
    };
    Kind kind = Kind::NeedMore;
    std::size_t bytes = 0;
    bool garbage = false;

    static constexpr FrameLength complete(std::size_t n) { return {Kind::Complete, n, false}; }
    static constexpr FrameLength need_more() { return {Kind::NeedMore, 0, false}; }
    // `garbage` false: the framer has counted why itself (e.g. truncated).
    static constexpr FrameLength skip(std::size_t n, bool garbage) {
        return {Kind::Skip, n, garbage};
    }
};

// The buffer-and-resynchronise part of the byte-stream decoders (NMEA, NovAtel, NCOM): bytes
// arrive in any split, frames come out whole and in order, whatever is not a frame is dropped
// and counted. The protocol supplies what a sync byte is, a frame's length and its checks.
class ResyncBuffer {
  public:
    // `max_frame`: the longest frame; a candidate still incomplete with that many bytes
    // buffered is no frame (its sync byte counts as garbage), so the buffer never holds more
    // than the bytes of one feed plus one frame.
    explicit ResyncBuffer(std::size_t max_frame) : max_frame_(max_frame) {}

    void append(std::span<const std::uint8_t> bytes) {
        buf_.insert(buf_.end(), bytes.begin(), bytes.end());
    }

    // Hands out every complete frame buffered, in stream order:
    //  1. bytes before a sync (classify(b) != Sync) are dropped, Garbage ones counted;
    //  2. at a sync, length(rest) says whether a whole frame starts there;
    //  3. on_frame(frame) checks and decodes it and returns how many bytes to consume:
    //     frame.size() when taken, fewer (≥ 1) to look for a frame inside a rejected one.
    // `garbage` is the decoder's counter. Never reads outside the buffered bytes.
    template <class Classify, class Length, class OnFrame>
    void drain(std::uint64_t& garbage, Classify classify, Length length, OnFrame on_frame) {
        while (size() > 0) {
            const std::span<const std::uint8_t> rest(buf_.data() + pos_, size());
            const ByteKind kind = classify(rest[0]);
            if (kind != ByteKind::Sync) {
                if (kind == ByteKind::Garbage) ++garbage;
                consume(1);
                continue;
            }
            const FrameLength f = length(rest);
            if (f.kind == FrameLength::Kind::NeedMore) {
                if (rest.size() < max_frame_) break;
                ++garbage;  // longer than any frame: this sync starts none
                consume(1);
            } else if (f.kind == FrameLength::Kind::Skip) {
                const std::size_t n = std::clamp<std::size_t>(f.bytes, 1, rest.size());
                if (f.garbage) garbage += n;
                consume(n);
            } else {
                const std::size_t n = std::min(f.bytes, rest.size());
                const std::size_t used = on_frame(rest.first(n));
                consume(std::clamp<std::size_t>(used, 1, n));
            }
        }
        compact();
    }

    // Drops what is buffered (end of stream, reset).
    void clear() {
        offset_ += size();
        buf_.clear();
        pos_ = 0;
    }
    std::size_t size() const { return buf_.size() - pos_; }
    // Stream offset of the first byte not consumed yet (during on_frame: the frame's first).
    std::uint64_t offset() const { return offset_; }

  private:
    // Compact once this much has been consumed (amortised O(1) per byte).
    static constexpr std::size_t kCompactThreshold = 8192;

    void consume(std::size_t n) {
        pos_ += n;
        offset_ += n;
    }
    void compact() {
        if (pos_ == buf_.size()) {
            buf_.clear();
            pos_ = 0;
        } else if (pos_ >= kCompactThreshold) {
            buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(pos_));
            pos_ = 0;
        }
    }

    std::vector<std::uint8_t> buf_;
    std::size_t pos_ = 0;
    std::uint64_t offset_ = 0;
    std::size_t max_frame_;
};

}  // namespace mirage::nav
