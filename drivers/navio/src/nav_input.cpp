// SPDX-License-Identifier: Apache-2.0
#include "mirage/navio/nav_input.hpp"

#include <array>
#include <chrono>
#include <cstdio>

#include "mirage/bytestream/byte_stream.hpp"
#include "mirage/can/can_bus.hpp"
#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/navio/dis_uri.hpp"
#include "mirage/navio/nav_recorder.hpp"

namespace mirage::navio {
namespace {

constexpr auto kPoll = std::chrono::milliseconds(50);
constexpr std::ptrdiff_t kMaxApplied = 100'000;

}  // namespace

NavInput::NavInput(const navproto::NavUri& uri, navpose::NavFrame frame, navpose::PoseBuffer& poses,
                   const NavInputOptions& options)
    : uri_(uri),
      poses_(poses),
      mapper_(frame, options.mapper),
      pose_log_(options.pose_log),
      record_(options.record) {
    if (uri.protocol == navproto::NavProtocol::Dis) {  // its options ride on the UDP URI
        std::string udp;
        decoder_ = navproto::make_dis_decoder(parse_dis_transport(uri.transport, udp));
        stream_ = bytestream::open_byte_stream(udp);
        datagrams_ = true;
        return;
    }
    decoder_ = navproto::make_nav_decoder(uri.protocol, options.nmea_date);
    if (navproto::is_can(uri.protocol)) {
        bus_ = can::open_can_bus(uri.transport);
    } else {
        stream_ = bytestream::open_byte_stream(uri.transport);
        datagrams_ = uri.transport.rfind("udp://", 0) == 0;
    }
}

NavInput::~NavInput() { stop(); }

void NavInput::start() {
    if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
}

void NavInput::stop() {
    stop_ = true;
    if (!thread_.joinable()) return;
    thread_.join();
    const std::string detail = decoder_->detail();  // the last word, the reader gone
    std::lock_guard lk(mu_);
    if (!detail.empty()) counters_.detail = detail;
}

void NavInput::run() {
    std::array<std::uint8_t, 65536> buf{};
    const auto poll = std::min<core::Nanos>(kPoll, decoder_->tick_period().value_or(kPoll));
    std::int64_t next_detail_ns = 0;
    const bool host_stamped = decoder_->tick_period().has_value();
    while (!stop_) {
        std::int64_t host_ns = 0;
        const auto fn = [&](const nav::NavSample& s) { on_sample(s, host_ns); };
        if (bus_) {
            nav::CanFrame f;
            switch (bus_->receive(f, host_ns, poll)) {
                case can::RxStatus::Frame:
                    if (record_) record_->frame(f, host_ns);
                    decoder_->feed_frame(f, fn);
                    break;
                case can::RxStatus::ErrorFrame: {
                    if (record_) record_->frame(f, host_ns);
                    std::lock_guard lk(mu_);
                    ++counters_.error_frames;
                    break;
                }
                case can::RxStatus::Closed: {
                    {
                        std::lock_guard lk(mu_);
                        ++counters_.transport_closed;
                    }
                    std::this_thread::sleep_for(std::chrono::milliseconds(100));
                    break;
                }
                case can::RxStatus::Timeout:
                    break;
            }
        } else {
            std::size_t n = 0;
            switch (stream_->read(buf, n, host_ns, poll)) {
                case bytestream::ReadStatus::Data: {
                    const std::span<const std::uint8_t> bytes(buf.data(), n);
                    if (record_) record_->bytes(bytes);
                    // A source that stamps samples with the host clock when it handles them (DIS)
                    // is paired with that moment, not the kernel's arrival time: the offset's
                    // lower envelope must not see the handling delay as a clock difference.
                    if (host_stamped) host_ns = hostclock::monotonic_ns();
                    if (datagrams_)
                        decoder_->feed_datagram(bytes, fn);
                    else
                        decoder_->feed_bytes(bytes, fn);
                    break;
                }
                case bytestream::ReadStatus::Closed: {
                    std::lock_guard lk(mu_);
                    ++counters_.transport_closed;
                    break;
                }
                case bytestream::ReadStatus::Timeout:
                    break;
            }
        }
        host_ns = hostclock::monotonic_ns();
        decoder_->tick(fn);
        const nav::DecodeCounters dc = decoder_->counters();
        std::string detail;
        if (host_ns >= next_detail_ns || stop_) {  // a string: once a second is enough
            detail = decoder_->detail();
            next_detail_ns = host_ns + 1'000'000'000;
        }
        std::lock_guard lk(mu_);
        counters_.decode = dc;
        if (!detail.empty()) counters_.detail = std::move(detail);
    }
}

// The sample numbered in decode order (the mapper counts every one), mapped, and its accepted
// track updates listed as applied before they reach the pose buffer.
void NavInput::on_sample(const nav::NavSample& s, std::int64_t host_ns) {
    const navpose::MessageTag tag{mapper_.counters().samples, host_ns};
    const navpose::TrackUpdates u = mapper_.map(s, tag);
    {
        std::lock_guard lk(mu_);
        counters_.track = mapper_.counters();
        if (!u.position && !u.attitude) return;
        if (std::ssize(applied_) >= kMaxApplied)  // nobody takes them: keep the newer half
            applied_.erase(applied_.begin(), applied_.begin() + kMaxApplied / 2);
        applied_.push_back({tag, u.position.has_value(), u.attitude.has_value()});
    }
    if (u.position) {
        poses_.add(*u.position);
        if (pose_log_) pose_log_->position(s, *u.position);
    }
    if (u.attitude) {
        poses_.add(*u.attitude);
        if (pose_log_) pose_log_->attitude(*u.attitude);
    }
    track_offset(s, host_ns);
}

void NavInput::track_offset(const nav::NavSample& s, std::int64_t host_ns) {
    std::lock_guard lk(mu_);
    offset_.add(host_ns - s.t.time_since_epoch().count(), host_ns);
}

std::optional<std::int64_t> NavInput::offset_ns() const {
    std::lock_guard lk(mu_);
    return offset_.value();
}

NavInputCounters NavInput::counters() const {
    std::lock_guard lk(mu_);
    return counters_;
}

std::uint16_t NavInput::udp_port() const {
    return stream_ && datagrams_ ? stream_->local_port() : 0;
}

std::optional<can::BusCounters> NavInput::bus_counters() const {
    if (!bus_) return std::nullopt;
    return bus_->counters();
}

std::vector<AppliedMessage> NavInput::take_applied() {
    std::lock_guard lk(mu_);
    std::vector<AppliedMessage> out;
    out.swap(applied_);
    return out;
}

}  // namespace mirage::navio
