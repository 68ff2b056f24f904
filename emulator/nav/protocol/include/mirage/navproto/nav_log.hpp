// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mirage/core/trajectory.hpp"
#include "mirage/nav/decode_counters.hpp"
#include "mirage/nav/nav_sample.hpp"
#include "mirage/navcan/candump.hpp"
#include "mirage/navpose/nav_frame.hpp"
#include "mirage/navpose/nav_mapper.hpp"
#include "mirage/navproto/protocol.hpp"

namespace mirage::navproto {

// One message of a byte log (NMEA sentence, NovAtel frame, NCOM packet) with the time it carries.
// Bytes that yield no timed sample (HDT, unsupported logs, garbage) travel with the message they
// precede, or the last one; untimed messages take the time of the timed message before them.
struct NavLogMessage {
    std::size_t offset = 0, size = 0;  // into NavLog::bytes
    core::GpsTime t{};
    bool timed = false;  // t is the message's own time (else inherited)
};

struct NavLogStats {
    std::uint64_t bytes = 0;
    std::uint64_t messages = 0;         // byte logs: chunks; CAN: frames
    std::uint64_t samples = 0;          // NavSamples decoded
    std::uint64_t untimed_samples = 0;  // samples without a full time (HDT, VTG)
    nav::DecodeCounters decode;         // the protocol decoder's counters
    navcan::CandumpReadStats candump;   // CAN logs: malformed lines
    bool nmea_date_assumed = false;     // NMEA without RMC/ZDA: the date was not in the log
    std::uint64_t rejected() const { return decode.rejected() + candump.rejected(); }
};

struct NavLogOptions {
    // NMEA: the UTC date when the log has no RMC/ZDA ("YYYY-MM-DD"; empty: the host's date,
    // flagged in nmea_date_assumed). A date found in the log always wins: its first timed
    // sentence's date is applied from the first byte, so sentences before it are not lost.
    std::string nmea_date;
};

// A recorded navigation log, decoded: what `mirage live --nav-record` writes (raw bytes for
// NMEA / NovAtel / NCOM, candump -L for the CAN protocols), or a unit's own log such as the
// OxTS RT NMEA log rst39.log of gpsd's test suite.
struct NavLog {
    std::string path;
    NavProtocol protocol = NavProtocol::Nmea;
    std::vector<std::uint8_t> bytes;            // byte protocols: the whole file
    std::vector<NavLogMessage> messages;        // byte protocols: in file order
    std::vector<navcan::CandumpRecord> frames;  // CAN protocols: valid lines, in file order
    std::vector<nav::NavSample> samples;        // every sample decoded, in decode order
    NavLogStats stats;
};

// Reads and decodes a log. Malformed lines/frames are counted (stats), never thrown. Throws
// IoError "nav log '<path>': cannot read ..." when the file cannot be read.
NavLog read_nav_log(const std::string& path, NavProtocol protocol,
                    const NavLogOptions& options = {});

struct NavTrackOptions {
    navpose::NavMapperConfig mapper;  // undulation, --max-jump-m: the rules live input uses
    core::Interpolation interpolation = core::Interpolation::Linear;
};

// The log's samples through the one mapper and its rejection rules (navpose::NavMapper), as
// `mirage live` would have applied them: the accepted track updates, in log order, tagged with
// the sample's index in NavLog::samples, and the mapper's counters.
struct NavTracks {
    std::vector<navpose::PositionUpdate> positions;
    std::vector<navpose::AttitudeUpdate> attitudes;
    navpose::NavCounters counters;
};
NavTracks nav_log_tracks(const NavLog& log, const navpose::NavFrame& frame,
                         const navpose::NavMapperConfig& config = {});

struct NavTrackStats {
    std::uint64_t positions = 0, attitudes = 0, poses = 0;
    navpose::NavCounters counters;  // what the rules refused, named as live names them
};

// The accepted tracks merged into one trajectory sampled on the union of their times (time =
// the INS GPS time): positions linear between fixes (before the first / after the last fix:
// extrapolated up to 1 s with that fix's reported velocity, else held), attitudes slerped
// between attitude samples (held outside). Throws ConfigError "nav log '<path>': no usable
// pose (...)" without positions or attitudes.
core::Trajectory nav_log_trajectory(const NavLog& log, const navpose::NavFrame& frame,
                                    const NavTrackOptions& options = {},
                                    NavTrackStats* stats = nullptr);

// `--nav-origin lat,lon,h`: a tangent-plane frame (throws ConfigError naming the option).
navpose::NavFrame parse_nav_origin(const std::string& spec);

// One line: "nav log 'f': 158 lines/frames, 157 samples, rejected: 2 bad checksum, ...".
std::string nav_log_summary(const NavLog& log);

}  // namespace mirage::navproto
