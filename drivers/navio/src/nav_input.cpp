// SPDX-License-Identifier: Apache-2.0
#include "mirage/navio/nav_input.hpp"

#include <array>
#include <chrono>
#include <cstdio>

#include "mirage/bytestream/byte_stream.hpp"
#include "mirage/can/can_bus.hpp"
#include "mirage/core/error.hpp"
#include "mirage/navio/nav_recorder.hpp"

namespace mirage::navio {
namespace {

constexpr std::int64_t kOffsetBlockNs = 10'000'000'000;  // lower envelope over 10-20 s
constexpr auto kPoll = std::chrono::milliseconds(50);

void tally(navpose::AddStatus st, bool& applied, bool& rejected) {
    if (st == navpose::AddStatus::Accepted)
        applied = true;
    else if (st != navpose::AddStatus::Duplicate)
        rejected = true;
}

}  // namespace

NavInput::NavInput(const navproto::NavUri& uri, navpose::NavFrame frame, navpose::PoseBuffer& poses,
                   double undulation_m)
    : NavInput(uri, frame, poses, NavInputOptions{undulation_m, "host", nullptr, nullptr}) {}

NavInput::NavInput(const navproto::NavUri& uri, navpose::NavFrame frame, navpose::PoseBuffer& poses,
                   const NavInputOptions& options)
    : uri_(uri),
      frame_(frame),
      poses_(poses),
      undulation_m_(options.undulation_m),
      pose_log_(options.pose_log),
      record_(options.record),
      decoder_(navproto::make_nav_decoder(uri.protocol, options.nmea_date)) {
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
    if (thread_.joinable()) thread_.join();
}

void NavInput::run() {
    std::array<std::uint8_t, 65536> buf{};
    while (!stop_) {
        std::int64_t host_ns = 0;
        const auto fn = [&](const nav::NavSample& s) { on_sample(s, host_ns); };
        if (bus_) {
            nav::CanFrame f;
            switch (bus_->receive(f, host_ns, kPoll)) {
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
            switch (stream_->read(buf, n, host_ns, kPoll)) {
                case bytestream::ReadStatus::Data: {
                    const std::span<const std::uint8_t> bytes(buf.data(), n);
                    if (record_) record_->bytes(bytes);
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
        const nav::DecodeCounters dc = decoder_->counters();
        std::lock_guard lk(mu_);
        decode_counters_ = dc;
        counters_.decode_rejected = dc.rejected();
    }
}

void NavInput::on_sample(const nav::NavSample& s, std::int64_t host_ns) {
    using F = nav::NavSample;
    {
        std::lock_guard lk(mu_);
        ++counters_.samples;
        if (!s.has(F::kTime)) {
            ++counters_.no_time;
            return;
        }
    }
    bool applied = false, rejected = false;
    if (s.has(F::kPosition)) {
        last_lat_ = s.lat_deg;
        last_lon_ = s.lon_deg;
        have_latlon_ = true;
        const double h = s.height_m + (s.has(F::kHeightIsMsl) ? undulation_m_ : 0.0);
        const Eigen::Vector3d local = frame_.local_from_geodetic(s.lat_deg, s.lon_deg, h);
        std::optional<Eigen::Vector3d> v;
        if (s.has(F::kVelocity))
            v = frame_.local_velocity(s.velocity_ned_mps, s.lat_deg, s.lon_deg);
        const navpose::AddStatus st = poses_.add_position(s.t, local, v);
        if (st == navpose::AddStatus::Accepted && pose_log_) pose_log_->position(s, local);
        tally(st, applied, rejected);
    }
    if (s.has(F::kAttitude)) {
        if (!have_latlon_) {
            const Eigen::Vector3d g = frame_.geodetic_from_local(Eigen::Vector3d::Zero());
            last_lat_ = g.x();
            last_lon_ = g.y();
        }
        const Eigen::Quaterniond q =
            frame_.local_attitude(s.roll_rad, s.pitch_rad, s.heading_rad, last_lat_, last_lon_);
        const navpose::AddStatus st = poses_.add_attitude(s.t, q);
        if (st == navpose::AddStatus::Accepted && pose_log_) pose_log_->attitude(s, q);
        tally(st, applied, rejected);
    }
    std::lock_guard lk(mu_);
    if (rejected) ++counters_.pose_rejected;
    if (!applied) return;
    ++counters_.applied;
    arrivals_.push_back(host_ns);
    if (arrivals_.size() > 100'000) arrivals_.pop_front();
    const std::int64_t off = host_ns - s.t.time_since_epoch().count();
    if (!offset_) {
        offset_ = off;
        offset_block_min_ = off;
        prev_block_min_ = off;
        offset_block_start_ = host_ns;
    }
    if (host_ns - offset_block_start_ > kOffsetBlockNs) {
        prev_block_min_ = offset_block_min_;
        offset_block_min_ = off;
        offset_block_start_ = host_ns;
    }
    offset_block_min_ = std::min(offset_block_min_, off);
    offset_ = std::min(prev_block_min_, offset_block_min_);
}

std::optional<std::int64_t> NavInput::offset_ns() const {
    std::lock_guard lk(mu_);
    return offset_;
}

NavInputCounters NavInput::counters() const {
    std::lock_guard lk(mu_);
    return counters_;
}

nav::DecodeCounters NavInput::decode_counters() const {
    std::lock_guard lk(mu_);
    return decode_counters_;
}

std::uint16_t NavInput::udp_port() const {
    return stream_ && datagrams_ ? stream_->local_port() : 0;
}

std::optional<can::BusCounters> NavInput::bus_counters() const {
    if (!bus_) return std::nullopt;
    return bus_->counters();
}

std::deque<std::int64_t> NavInput::take_arrivals() {
    std::lock_guard lk(mu_);
    std::deque<std::int64_t> out;
    out.swap(arrivals_);
    return out;
}

}  // namespace mirage::navio
