// SPDX-License-Identifier: Apache-2.0
#include "mirage/navio/nav_recorder.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>

#include "mirage/core/error.hpp"
#include "mirage/core/time.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/navcan/candump.hpp"

namespace mirage::navio {
namespace {

constexpr std::size_t kFlushBytes = 64 * 1024;
constexpr auto kFlushEvery = std::chrono::milliseconds(500);

double deg(double rad) { return rad * 180.0 / M_PI; }

}  // namespace

RecordFile::RecordFile(const std::string& path, std::string what)
    : what_(std::move(what)), last_flush_(std::chrono::steady_clock::now()) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) throw IoError(fmt::format("{}: cannot create: {}", what_, std::strerror(errno)));
    buf_.reserve(kFlushBytes + 4096);
}

RecordFile::~RecordFile() { close(); }

void RecordFile::append(std::string_view unit) {
    if (fd_ < 0 || !error_.empty()) return;
    buf_.append(unit);
    ++buf_units_;
    if (buf_.size() >= kFlushBytes || std::chrono::steady_clock::now() - last_flush_ > kFlushEvery)
        flush();
}

bool RecordFile::flush() {
    last_flush_ = std::chrono::steady_clock::now();
    if (!error_.empty()) return false;
    std::size_t done = 0;
    while (done < buf_.size()) {
        const ssize_t n = ::write(fd_, buf_.data() + done, buf_.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int e = n < 0 ? errno : ENOSPC;
            // Cut a partly written buffer off: the file ends after the last whole unit.
            const bool cut = done == 0 || ::ftruncate(fd_, static_cast<off_t>(committed_)) == 0;
            error_ = fmt::format("{}: write failed after {} units ({} bytes): {}{}", what_, units_,
                                 committed_, std::strerror(e),
                                 cut ? "" : " (and the partial tail could not be cut off)");
            buf_.clear();
            return false;
        }
        done += static_cast<std::size_t>(n);
    }
    committed_ += buf_.size();
    units_ += buf_units_;
    buf_units_ = 0;
    buf_.clear();
    return true;
}

bool RecordFile::close() {
    if (fd_ < 0) return error_.empty();
    flush();
    if (::close(fd_) != 0 && error_.empty())
        error_ = fmt::format("{}: close failed: {}", what_, std::strerror(errno));
    fd_ = -1;
    return error_.empty();
}

PoseLog::PoseLog(const std::string& path)
    : file_(path, fmt::format("live: --pose-log '{}'", path)) {
    file_.append(
        "gps_time_s,kind,x_m,y_m,z_m,qw,qx,qy,qz,lat_deg,lon_deg,h_m,h_ref,roll_deg,pitch_deg,"
        "heading_deg\n");
}

void PoseLog::position(const nav::NavSample& s, const navpose::PositionUpdate& u) {
    line_.clear();
    fmt::format_to(std::back_inserter(line_), "{},position,{},{},{},,,,,{},{},{},{},,,\n",
                   core::format_decimal_seconds(u.t.time_since_epoch()), u.local.x(), u.local.y(),
                   u.local.z(), s.lat_deg, s.lon_deg, s.height_m,
                   s.has(nav::NavSample::kHeightIsMsl) ? "msl" : "ellipsoid");
    file_.append(line_);
}

void PoseLog::attitude(const navpose::AttitudeUpdate& u) {
    const Eigen::Quaterniond& q = u.attitude;
    line_.clear();
    fmt::format_to(std::back_inserter(line_), "{},attitude,,,,{},{},{},{},,,,,{},{},{}\n",
                   core::format_decimal_seconds(u.t.time_since_epoch()), q.w(), q.x(), q.y(), q.z(),
                   deg(u.ned_rpy.x()), deg(u.ned_rpy.y()), deg(u.ned_rpy.z()));
    file_.append(line_);
}

NavRecorder::NavRecorder(const std::string& path, std::string can_ifname)
    : file_(path, fmt::format("live: --nav-record '{}'", path)),
      ifname_(std::move(can_ifname)),
      realtime_offset_ns_(hostclock::realtime_minus_monotonic()) {}

void NavRecorder::bytes(std::span<const std::uint8_t> data) {
    file_.append(std::string_view(reinterpret_cast<const char*>(data.data()), data.size()));
}

void NavRecorder::frame(const nav::CanFrame& f, std::int64_t host_mono_ns) {
    // Monotonic reception time -> Unix time (candump logs are Unix) with one offset for the whole
    // recording, so stamps keep the arrival order and spacing even if the wall clock is stepped.
    const std::int64_t unix_ns = host_mono_ns + realtime_offset_ns_;
    std::string line = navcan::format_candump_line(unix_ns, ifname_, f);
    line += '\n';
    file_.append(line);
}

std::string candump_ifname(const std::string& bus_spec) {
    const auto colon = bus_spec.find(':');
    const std::string kind = bus_spec.substr(0, colon);
    std::string name;
    if (kind == "slcan")
        name = "slcan0";
    else if (kind == "gsusb")
        name = "can0";
    else
        name = colon == std::string::npos ? bus_spec : bus_spec.substr(colon + 1);
    name = name.substr(0, name.find('?'));
    if (name.empty()) name = "can0";
    for (char& c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '_' || c == '.' || c == '-';
        if (!ok) c = '_';
    }
    if (name.size() > navcan::kCandumpMaxIfname) name.resize(navcan::kCandumpMaxIfname);
    return name;
}

}  // namespace mirage::navio
