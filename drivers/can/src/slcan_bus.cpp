// SPDX-License-Identifier: Apache-2.0
// slcan (Lawicel ASCII) CAN bus over a ByteStream (docs/nav-protocols.md §9), framing by navcan.
#include "mirage/can/slcan_bus.hpp"

#include <fmt/format.h>

#include <deque>
#include <mutex>
#include <string_view>
#include <vector>

#include "bus_counting.hpp"
#include "mirage/bytestream/byte_stream.hpp"
#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/navcan/slcan.hpp"

namespace mirage::can {
namespace {

using bytestream::ByteStream;
using bytestream::ReadStatus;

std::span<const std::uint8_t> as_bytes(std::string_view s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

bool all_digits(std::string_view s) {
    for (char c : s)
        if (c < '0' || c > '9') return false;
    return !s.empty();
}

int decimal(std::string_view s) {
    int v = 0;
    for (char c : s) v = v * 10 + (c - '0');
    return v;
}

nav::CanFrame error_frame(std::uint32_t classes) {
    nav::CanFrame f;
    f.error = true;
    f.id = classes;
    f.len = 8;
    return f;
}

// Linux slcan state line: `s` + a|w|p|b + 3-digit rx + 3-digit tx error counts ("sb256256").
bool parse_state_line(std::string_view line, nav::CanFrame& out) {
    if (line.size() != 8 || line[0] != 's' || !all_digits(line.substr(2))) return false;
    const int rx = decimal(line.substr(2, 3)), tx = decimal(line.substr(5, 3));
    const auto rx8 = static_cast<std::uint8_t>(std::min(rx, 255));
    const auto tx8 = static_cast<std::uint8_t>(std::min(tx, 255));
    switch (line[1]) {
        case 'b':
            out = error_frame(err::kBusOff | err::kCounters);
            break;
        case 'p':
            out = error_frame(err::kController | err::kCounters);
            out.data[1] = static_cast<std::uint8_t>((rx >= 128 ? err::kCtrlRxPassive : 0) |
                                                    (tx >= 128 ? err::kCtrlTxPassive : 0));
            break;
        case 'w':
            out = error_frame(err::kController | err::kCounters);
            out.data[1] = static_cast<std::uint8_t>((rx >= 96 ? err::kCtrlRxWarning : 0) |
                                                    (tx >= 96 ? err::kCtrlTxWarning : 0));
            break;
        case 'a':
            out = error_frame(err::kController | err::kCounters);
            out.data[1] = err::kCtrlActive;
            break;
        default:
            return false;
    }
    out.data[6] = tx8;
    out.data[7] = rx8;
    return true;
}

// Linux slcan error line: `e` + count digit + that many codes (a ack, b/B bit0/bit1, c crc,
// f form, s stuff, o/O rx/tx overrun).
bool parse_error_line(std::string_view line, nav::CanFrame& out) {
    if (line.size() < 3 || line[0] != 'e' || line[1] < '1' || line[1] > '9') return false;
    const auto count = static_cast<std::size_t>(line[1] - '0');
    if (line.size() != 2 + count) return false;
    out = error_frame(0);
    for (char c : line.substr(2)) {
        switch (c) {
            case 'a':
                out.id |= err::kNoAck;
                break;
            case 'b':
                out.id |= err::kProtocol | err::kBusError;
                out.data[2] |= err::kProtBit0;
                break;
            case 'B':
                out.id |= err::kProtocol | err::kBusError;
                out.data[2] |= err::kProtBit1;
                break;
            case 'c':
                out.id |= err::kProtocol | err::kBusError;
                break;  // CRC: location bits only
            case 'f':
                out.id |= err::kProtocol | err::kBusError;
                out.data[2] |= err::kProtForm;
                break;
            case 's':
                out.id |= err::kProtocol | err::kBusError;
                out.data[2] |= err::kProtStuff;
                break;
            case 'o':
                out.id |= err::kController;
                out.data[1] |= err::kCtrlRxOverflow;
                break;
            case 'O':
                out.id |= err::kController;
                out.data[1] |= err::kCtrlTxOverflow;
                break;
            default:
                return false;
        }
    }
    return true;
}

class SlcanBus final : public CanBus {
  public:
    SlcanBus(std::unique_ptr<ByteStream> stream, std::uint32_t bitrate, bool listen_only,
             std::string device)
        : stream_(std::move(stream)), device_(std::move(device)) {
        open_sequence_ = navcan::slcan_open_sequence(bitrate, listen_only);
        if (open_sequence_.empty())
            throw ConfigError(fmt::format(
                "slcan '{}': bitrate {} has no slcan code (10k 20k 50k 100k 125k 250k 500k "
                "800k 1M)",
                device_, bitrate));
        if (!stream_->write(as_bytes(open_sequence_)))
            throw IoError(fmt::format("slcan '{}': cannot write the open sequence", device_));
        reopens_seen_ = stream_->counters().reopens;
    }

    bool send(const nav::CanFrame& frame) override {
        const std::string line =
            frame.error || frame.len > 8 ? std::string() : navcan::slcan_encode(frame);
        bool ok = !line.empty();
        if (ok) {
            std::lock_guard lock(tx_mutex_);
            ok = stream_->write(as_bytes(line));
        }
        ++(ok ? counters_.tx_frames : counters_.tx_failed);
        return ok;
    }

    RxStatus receive(nav::CanFrame& out, std::int64_t& host_ns,
                     std::chrono::nanoseconds timeout) override {
        std::lock_guard lock(rx_mutex_);
        const std::int64_t deadline =
            hostclock::monotonic_ns() + std::max<std::int64_t>(0, timeout.count());
        for (bool first = true;; first = false) {
            if (!pending_.empty()) {
                out = pending_.front().frame;
                host_ns = pending_.front().t_ns;
                pending_.pop_front();
                return counters_.count_rx(out);
            }
            // A zero timeout still polls the line once.
            const std::int64_t left =
                std::max<std::int64_t>(0, deadline - hostclock::monotonic_ns());
            if (left == 0 && !first) return RxStatus::Timeout;
            std::size_t n = 0;
            std::int64_t t_ns = 0;
            const ReadStatus st = stream_->read(buffer_, n, t_ns, std::chrono::nanoseconds(left));
            resend_open_sequence_after_reopen();
            if (st == ReadStatus::Timeout) return RxStatus::Timeout;
            if (st == ReadStatus::Closed) {
                line_.clear();
                passthrough_ = false;
                parser_.reset();
                return RxStatus::Closed;
            }
            feed(std::span<const std::uint8_t>(buffer_.data(), n), t_ns);
        }
    }

    BusCounters counters() const override {
        BusCounters c = counters_.snapshot();
        c.malformed = malformed_bytes_;
        return c;
    }
    std::string name() const override { return "slcan:" + device_; }

  private:
    struct Pending {
        nav::CanFrame frame;
        std::int64_t t_ns;
    };

    // The adapter lost power or was re-plugged: it starts closed, so open it again.
    void resend_open_sequence_after_reopen() {
        const auto reopens = stream_->counters().reopens;
        if (reopens == reopens_seen_) return;
        reopens_seen_ = reopens;
        line_.clear();
        passthrough_ = false;
        parser_.reset();
        std::lock_guard lock(tx_mutex_);
        stream_->write(as_bytes(open_sequence_));
    }

    // Splits lines so Linux-slcan state/error lines (which navcan's parser does not know) are
    // handled here; everything else goes to the parser whole, terminator included.
    void feed(std::span<const std::uint8_t> bytes, std::int64_t t_ns) {
        const auto on_event = [&](const navcan::SlcanEvent& ev) {
            if (ev.kind == navcan::SlcanEvent::Kind::Frame) pending_.push_back({ev.frame, t_ns});
            if (ev.kind == navcan::SlcanEvent::Kind::Error) ++counters_.nacks;
        };
        for (const std::uint8_t b : bytes) {
            const char c = static_cast<char>(b);
            if (passthrough_) {
                parser_.feed(std::span<const std::uint8_t>(&b, 1), on_event);
                if (c == navcan::kSlcanOk || c == navcan::kSlcanError) passthrough_ = false;
                continue;
            }
            if (c == navcan::kSlcanOk) {
                nav::CanFrame ef;
                if (parse_state_line(line_, ef) || parse_error_line(line_, ef)) {
                    pending_.push_back({ef, t_ns});
                } else {
                    line_.push_back(c);
                    parser_.feed(std::string_view(line_), on_event);
                }
                line_.clear();
            } else if (c == navcan::kSlcanError) {
                line_.push_back(c);
                parser_.feed(std::string_view(line_), on_event);
                line_.clear();
            } else {
                line_.push_back(c);
                if (line_.size() > navcan::kSlcanMaxLine) {
                    parser_.feed(std::string_view(line_), on_event);
                    line_.clear();
                    passthrough_ = true;
                }
            }
        }
        malformed_bytes_ = parser_.counters().garbage_bytes;
    }

    std::unique_ptr<ByteStream> stream_;
    std::string device_;
    std::string open_sequence_;
    std::mutex tx_mutex_;
    std::mutex rx_mutex_;
    // Receive side, guarded by rx_mutex_.
    navcan::SlcanParser parser_;
    std::string line_;
    bool passthrough_ = false;
    std::deque<Pending> pending_;
    std::vector<std::uint8_t> buffer_ = std::vector<std::uint8_t>(4096);
    std::uint64_t reopens_seen_ = 0;
    std::atomic<std::uint64_t> malformed_bytes_{0};
    detail::AtomicBusCounters counters_;
};

}  // namespace

std::unique_ptr<CanBus> open_slcan(std::unique_ptr<ByteStream> stream, std::uint32_t bitrate,
                                   bool listen_only) {
    std::string device = stream->name();
    if (device.starts_with("serial:")) device.erase(0, 7);
    return std::make_unique<SlcanBus>(std::move(stream), bitrate, listen_only, std::move(device));
}

std::unique_ptr<CanBus> open_slcan(const SlcanOptions& options) {
    if (!navcan::slcan_bitrate_code(options.bitrate))
        throw ConfigError(fmt::format(
            "slcan '{}': bitrate {} has no slcan code (10k 20k 50k 100k 125k 250k 500k 800k 1M)",
            options.device, options.bitrate));
    auto stream = bytestream::open_byte_stream(
        fmt::format("serial:{}?baud={}", options.device, options.baud));
    return open_slcan(std::move(stream), options.bitrate, options.listen_only);
}

}  // namespace mirage::can
