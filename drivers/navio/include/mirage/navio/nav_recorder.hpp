// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Geometry>
#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "mirage/nav/can_frame.hpp"
#include "mirage/nav/nav_sample.hpp"
#include "mirage/navpose/track_update.hpp"

namespace mirage::navio {

// A file written in whole units (text lines, or the chunks a read returned) from one thread,
// through a buffer flushed every 64 KiB or 0.5 s. A write error (disk full, EFBIG, EIO) stops
// the writing and cuts the file back to the end of the last unit written whole, so the file
// never ends mid-line; error() then says what happened. Never throws after the constructor.
class RecordFile {
  public:
    // `what` names the file in messages, e.g. "live: --pose-log 'poses.csv'". Throws IoError
    // when the file cannot be created.
    RecordFile(const std::string& path, std::string what);
    ~RecordFile();
    RecordFile(const RecordFile&) = delete;
    RecordFile& operator=(const RecordFile&) = delete;

    // One unit; the caller includes its line end. Dropped after an error.
    void append(std::string_view unit);
    // Flushes and closes; false (and error() set) if any write failed. Idempotent.
    bool close();
    const std::string& error() const { return error_; }
    std::uint64_t units() const { return units_; }  // units written whole (after close)
    std::uint64_t bytes() const { return committed_; }

  private:
    bool flush();

    std::string what_;
    int fd_ = -1;
    std::string buf_;
    std::uint64_t buf_units_ = 0;
    std::uint64_t units_ = 0;
    std::uint64_t committed_ = 0;  // file size up to the last whole unit
    std::chrono::steady_clock::time_point last_flush_;
    std::string error_;
};

// `mirage live --pose-log FILE`: every sample applied to the pose buffer, one CSV row per track
// update, in arrival order, written by the nav thread. Columns (header row first):
//   gps_time_s   INS time of validity, GPS seconds since 1980-01-06, exact ("1076877708.100000000")
//   kind         position | attitude
//   x_m,y_m,z_m  position rows: the scene-local position applied (grid E, N, up from the anchor)
//   qw,qx,qy,qz  attitude rows: the scene-local attitude applied (body FLU -> local ENU)
//   lat_deg,lon_deg,h_m,h_ref   position rows, as received: WGS84; h_ref "ellipsoid" or "msl"
//                               (an MSL height had --undulation added before mapping)
//   roll_deg,pitch_deg,heading_deg   attitude rows, as applied: NED Euler, heading [0, 360) (a
//                                    heading-only message with the roll/pitch it was given)
// Cells that do not apply to a row's kind are empty. Numbers are the shortest text that reads
// back to the same double.
class PoseLog {
  public:
    explicit PoseLog(const std::string& path);  // throws IoError
    void position(const nav::NavSample& s, const navpose::PositionUpdate& u);
    void attitude(const navpose::AttitudeUpdate& u);
    bool close() { return file_.close(); }
    const std::string& error() const { return file_.error(); }
    std::uint64_t rows() const { return file_.units() > 0 ? file_.units() - 1 : 0; }

  private:
    RecordFile file_;
    std::string line_;
};

// `mirage live --nav-record FILE`: the navigation input as it arrived, replayable later.
//  - byte protocols (NMEA, NovAtel, NCOM): the raw bytes in arrival order, as a serial capture
//    (UDP: the datagrams' payloads back to back; the NCOM/NovAtel decoders resynchronise on
//    them the same way);
//  - CAN protocols: a candump -L log, `(unix.usec) <ifname> <id>#<data>`, one line per frame
//    the bus delivered (data frames, and error frames with CAN_ERR_FLAG as `candump -e` logs
//    them), stamped with the host's CLOCK_REALTIME at reception.
class NavRecorder {
  public:
    // `can_ifname` empty: a raw byte capture; otherwise a candump log with that interface name.
    NavRecorder(const std::string& path, std::string can_ifname);  // throws IoError
    void bytes(std::span<const std::uint8_t> data);
    // `host_mono_ns`: CLOCK_MONOTONIC reception time (CanBus::receive), converted to Unix time.
    void frame(const nav::CanFrame& f, std::int64_t host_mono_ns);
    bool close() { return file_.close(); }
    const std::string& error() const { return file_.error(); }
    bool is_candump() const { return !ifname_.empty(); }
    std::uint64_t units() const { return file_.units(); }  // frames, or chunks of bytes
    std::uint64_t bytes_written() const { return file_.bytes(); }

  private:
    RecordFile file_;
    std::string ifname_;
    std::int64_t realtime_offset_ns_ = 0;  // CLOCK_REALTIME − CLOCK_MONOTONIC at the start
};

// candump interface name for a CanBus spec: socketcan:<if> -> <if>; memory:<name> -> <name>;
// slcan:… -> slcan0 (what slcand names it); gsusb:… -> can0 (the gs_usb kernel driver's name).
// Characters outside [A-Za-z0-9_.-] become '_'; at most 21 characters (candump's limit).
std::string candump_ifname(const std::string& bus_spec);

}  // namespace mirage::navio
