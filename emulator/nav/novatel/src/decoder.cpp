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

// The longest frame: a long header (length in one byte), the largest body accepted, the CRC.
constexpr std::size_t kMaxFrame = 255 + kMaxBodyLength + kCrcSize;

}  // namespace

NovatelDecoder::NovatelDecoder() : buf_(kMaxFrame) {}

void NovatelDecoder::feed(std::span<const std::uint8_t> bytes, const nav::SampleFn& on_sample) {
    buf_.append(bytes);
    process(false, on_sample);
}

// The frame's length from its header, checked in order: sync, header length, body length.
nav::FrameLength NovatelDecoder::frame_length(std::span<const std::uint8_t> rest, bool flushing) {
    using nav::FrameLength;
    // An incomplete candidate: wait for bytes, or (flushing) give it up as truncated.
    const auto incomplete = [&] {
        if (!flushing) return FrameLength::need_more();
        ++counters_.truncated;
        return FrameLength::skip(1, false);
    };
    if (rest.size() < 3) return incomplete();
    if (rest[1] != kSync1 || (rest[2] != kSyncLong && rest[2] != kSyncShort))
        return FrameLength::skip(1, true);
    if (rest[2] == kSyncShort) {
        if (rest.size() < 4) return incomplete();
        const std::size_t total = kShortHeaderSize + rest[3] + kCrcSize;
        return rest.size() < total ? incomplete() : FrameLength::complete(total);
    }
    if (rest.size() < 10) return incomplete();
    const std::size_t hlen = rest[3];
    if (hlen < kLongHeaderSize) return FrameLength::skip(1, true);  // not a header: a false sync
    const std::size_t body = get_u16(rest.data() + 8);
    if (body > kMaxBodyLength) {  // checked before waiting for the body
        ++counters_.truncated;
        return FrameLength::skip(1, false);
    }
    const std::size_t total = hlen + body + kCrcSize;
    return rest.size() < total ? incomplete() : FrameLength::complete(total);
}

void NovatelDecoder::process(bool flushing, const nav::SampleFn& on_sample) {
    buf_.drain(
        counters_.garbage_bytes,
        [](std::uint8_t b) { return b == kSync0 ? nav::ByteKind::Sync : nav::ByteKind::Garbage; },
        [&](std::span<const std::uint8_t> rest) { return frame_length(rest, flushing); },
        [&](std::span<const std::uint8_t> frame) -> std::size_t {
            const std::size_t total = frame.size();
            const std::uint32_t stored = get_u32(frame.data() + total - kCrcSize);
            if (crc32(frame.first(total - kCrcSize)) != stored) {
                if (contains_later_sync(frame))
                    ++counters_.truncated;
                else
                    ++counters_.bad_checksum;
                return 1;  // a real frame may hide behind a false sync
            }
            handle_frame(frame, frame[2] == kSyncLong, on_sample);
            return total;
        });
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
}

void NovatelDecoder::reset() {
    buf_.clear();
    counters_ = {};
}

}  // namespace mirage::novatel
