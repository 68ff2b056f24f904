// SPDX-License-Identifier: Apache-2.0
#include "mirage/novatel/decoder.hpp"

#include "le_bytes.hpp"
#include "mirage/novatel/convert.hpp"
#include "mirage/novatel/crc32.hpp"
#include "mirage/novatel/frame.hpp"
#include "mirage/novatel/messages.hpp"

namespace mirage::novatel {
using namespace detail;

namespace {

bool is_sync_at(std::span<const std::uint8_t> b, std::size_t i) {
    return i + 3 <= b.size() && b[i] == kSync0 && b[i + 1] == kSync1 &&
           (b[i + 2] == kSyncLong || b[i + 2] == kSyncShort);
}

// A sync sequence after the first byte of a rejected frame: the frame was cut short.
bool contains_later_sync(std::span<const std::uint8_t> frame) {
    for (std::size_t i = 1; i + 3 <= frame.size(); ++i)
        if (is_sync_at(frame, i)) return true;
    return false;
}

// Compact the buffer once this much has been consumed (amortised O(1) per byte).
constexpr std::size_t kCompactThreshold = 8192;

}  // namespace

void NovatelDecoder::feed(std::span<const std::uint8_t> bytes, const nav::SampleFn& on_sample) {
    buf_.insert(buf_.end(), bytes.begin(), bytes.end());
    process(false, on_sample);
}

void NovatelDecoder::process(bool flushing, const nav::SampleFn& on_sample) {
    // An incomplete candidate: wait for bytes, or (flushing) give it up as truncated.
    const auto incomplete = [&]() {
        if (!flushing) return false;
        ++counters_.truncated;
        ++pos_;
        return true;
    };
    for (;;) {
        const std::span<const std::uint8_t> rest(buf_.data() + pos_, buf_.size() - pos_);
        if (rest.empty()) break;
        if (rest[0] != kSync0) {
            ++counters_.garbage_bytes;
            ++pos_;
            continue;
        }
        if (rest.size() < 3) {
            if (incomplete()) continue;
            break;
        }
        if (rest[1] != kSync1 || (rest[2] != kSyncLong && rest[2] != kSyncShort)) {
            ++counters_.garbage_bytes;
            ++pos_;
            continue;
        }
        const bool long_header = rest[2] == kSyncLong;
        std::size_t total = 0;
        if (long_header) {
            if (rest.size() < 10) {
                if (incomplete()) continue;
                break;
            }
            const std::size_t hlen = rest[3];
            if (hlen < kLongHeaderSize) {  // not a header: a false sync
                ++counters_.garbage_bytes;
                ++pos_;
                continue;
            }
            const std::size_t body = get_u16(rest.data() + 8);
            if (body > kMaxBodyLength) {  // checked before waiting for the body
                ++counters_.truncated;
                ++pos_;
                continue;
            }
            total = hlen + body + kCrcSize;
        } else {
            if (rest.size() < 4) {
                if (incomplete()) continue;
                break;
            }
            total = kShortHeaderSize + rest[3] + kCrcSize;
        }
        if (rest.size() < total) {
            if (incomplete()) continue;
            break;
        }
        const auto frame = rest.first(total);
        const std::uint32_t stored = get_u32(frame.data() + total - kCrcSize);
        if (crc32(frame.first(total - kCrcSize)) != stored) {
            if (contains_later_sync(frame))
                ++counters_.truncated;
            else
                ++counters_.bad_checksum;
            ++pos_;
            continue;
        }
        handle_frame(frame, long_header, on_sample);
        pos_ += total;
    }
    if (pos_ == buf_.size()) {
        buf_.clear();
        pos_ = 0;
    } else if (pos_ >= kCompactThreshold) {
        buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(pos_));
        pos_ = 0;
    }
}

void NovatelDecoder::handle_frame(std::span<const std::uint8_t> frame, bool long_header,
                                  const nav::SampleFn& on_sample) {
    std::optional<nav::NavSample> sample;
    if (long_header) {
        const auto h = parse_long_header(frame);
        if (!h) {
            ++counters_.invalid_field;
            return;
        }
        // Only binary logs (format bits 00) that are not command responses.
        const bool binary_log = (h->message_type & 0xE0U) == 0;
        const auto body = frame.subspan(h->header_length, h->body_length);
        if (binary_log && h->message_id == kBestPosId) {
            const auto m = unpack_bestpos(body);
            if (m) sample = to_sample(*h, *m);
        } else if (binary_log && h->message_id == kInsPvaXId) {
            const auto m = unpack_inspvax(body);
            if (m) sample = to_sample(*h, *m);
        } else if (binary_log && h->message_id == kInsPvaId) {
            const auto m = unpack_inspvas(body);
            if (m) sample = to_sample(*m);
        } else {
            ++counters_.unsupported;
            return;
        }
    } else {
        const auto h = parse_short_header(frame);
        if (!h || h->message_id != kInsPvaSId) {
            ++counters_.unsupported;
            return;
        }
        const auto m = unpack_inspvas(frame.subspan(kShortHeaderSize, h->body_length));
        if (m) sample = to_sample(*m);
    }
    if (!sample) {
        ++counters_.invalid_field;
        return;
    }
    ++counters_.messages_ok;
    emit(*sample, on_sample);
}

void NovatelDecoder::emit(const nav::NavSample& s, const nav::SampleFn& on_sample) {
    ++counters_.samples;
    if (on_sample) on_sample(s);
}

void NovatelDecoder::finish(const nav::SampleFn& on_sample) {
    process(true, on_sample);
    buf_.clear();
    pos_ = 0;
}

void NovatelDecoder::reset() {
    buf_.clear();
    pos_ = 0;
    counters_ = {};
}

}  // namespace mirage::novatel
