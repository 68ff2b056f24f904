// SPDX-License-Identifier: Apache-2.0
// Trajectory CSV reader and writer (format: trajectory.hpp, load_trajectory_csv).
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <string_view>

#include "mirage/core/error.hpp"
#include "mirage/core/trajectory.hpp"

namespace mirage::core {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

using Group = std::array<const char*, 4>;  // up to 4 column names, nullptr-terminated
constexpr std::array<Group, 2> kTimeGroups{{{"time"}, {"utc"}}};
constexpr std::array<Group, 3> kPositionGroups{
    {{"x", "y", "z"}, {"e", "n", "u"}, {"lat", "lon", "h"}}};
constexpr std::array<Group, 2> kAttitudeGroups{
    {{"roll", "pitch", "yaw"}, {"qw", "qx", "qy", "qz"}}};

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

std::vector<std::string_view> split_fields(std::string_view line) {
    std::vector<std::string_view> out;
    for (;;) {
        const std::size_t comma = line.find(',');
        out.push_back(trim(line.substr(0, comma)));
        if (comma == std::string_view::npos) return out;
        line.remove_prefix(comma + 1);
    }
}

std::string group_list(const auto& groups) {
    std::string s;
    for (const Group& g : groups) {
        if (!s.empty()) s += " or ";
        for (std::size_t k = 0; k < g.size() && g[k] != nullptr; ++k) {
            if (k > 0) s += ',';
            s += g[k];
        }
    }
    return s;
}

class CsvReader {
  public:
    CsvReader(const std::string& path, const Georef& georef) : path_(path), georef_(georef) {}

    std::vector<StampedPose> read(std::istream& in) {
        std::string raw;
        std::size_t line_no = 0;
        bool have_header = false;
        while (std::getline(in, raw)) {
            ++line_no;
            std::string_view line = trim(raw);  // also drops a CR of CRLF files
            if (line.empty() || line.front() == '#') continue;
            if (!have_header) {
                read_header(line, line_no);
                have_header = true;
            } else {
                read_row(line, line_no);
            }
        }
        if (in.bad()) throw IoError("trajectory '" + path_ + "': read error");
        if (!have_header) throw ConfigError("trajectory '" + path_ + "': no header row");
        if (samples_.empty()) {
            throw ConfigError("trajectory '" + path_ + "': line " + std::to_string(line_no) +
                              ": no data rows after the header (need at least 1 sample)");
        }
        convert_geodetic();
        return std::move(samples_);
    }

  private:
    [[noreturn]] void fail(std::size_t line, std::string_view column,
                           const std::string& why) const {
        throw ConfigError("trajectory '" + path_ + "': line " + std::to_string(line) +
                          ", column '" + std::string(column) + "': " + why);
    }

    // Index of the group (within `groups`) whose columns are all present; checks that exactly
    // one group is used and complete.
    template <std::size_t N>
    std::size_t pick_group(const std::array<Group, N>& groups, std::size_t line) {
        std::optional<std::size_t> chosen;
        for (std::size_t g = 0; g < N; ++g) {
            for (std::size_t k = 0; k < groups[g].size() && groups[g][k] != nullptr; ++k) {
                if (!columns_.count(groups[g][k])) continue;
                if (chosen && *chosen != g) {
                    fail(line, groups[g][k],
                         "conflicts with '" + std::string(groups[*chosen][0]) + "' (use one of " +
                             group_list(groups) + ")");
                }
                chosen = g;
            }
        }
        if (!chosen) fail(line, groups[0][0], "missing (need " + group_list(groups) + ")");
        for (std::size_t k = 0; k < groups[*chosen].size() && groups[*chosen][k] != nullptr; ++k) {
            if (!columns_.count(groups[*chosen][k])) fail(line, groups[*chosen][k], "missing");
        }
        return *chosen;
    }

    void read_header(std::string_view line, std::size_t line_no) {
        header_line_ = line_no;
        const auto names = split_fields(line);
        for (std::size_t i = 0; i < names.size(); ++i) {
            std::string name(names[i]);
            for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            bool known = false;
            const auto scan = [&](const auto& groups) {
                for (const Group& g : groups)
                    for (const char* n : g)
                        if (n != nullptr && name == n) known = true;
            };
            scan(kTimeGroups);
            scan(kPositionGroups);
            scan(kAttitudeGroups);
            if (!known) {
                fail(line_no, name,
                     "unknown column (expected " + group_list(kTimeGroups) + "; " +
                         group_list(kPositionGroups) + "; " + group_list(kAttitudeGroups) + ")");
            }
            if (!columns_.emplace(name, i).second) fail(line_no, name, "duplicate column");
        }
        field_count_ = names.size();
        time_group_ = pick_group(kTimeGroups, line_no);
        position_group_ = pick_group(kPositionGroups, line_no);
        attitude_group_ = pick_group(kAttitudeGroups, line_no);
        if (position_group_ == 2 && !georef_.has_crs()) {
            fail(line_no, "lat", "geodetic positions need a scene georeference (EPSG code)");
        }
    }

    double number(const std::vector<std::string_view>& f, std::size_t line, const char* col) const {
        std::string_view s = f[columns_.at(col)];
        if (s.empty()) fail(line, col, "empty value");
        if (s.front() == '+') s.remove_prefix(1);
        double v = 0.0;
        const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (ec == std::errc::result_out_of_range)
            fail(line, col, "'" + std::string(s) + "' out of range");
        if (ec != std::errc() || ptr != s.data() + s.size()) {
            fail(line, col, "'" + std::string(f[columns_.at(col)]) + "' is not a number");
        }
        if (!std::isfinite(v)) fail(line, col, "'" + std::string(s) + "' is not finite");
        return v;
    }

    GpsTime time(const std::vector<std::string_view>& f, std::size_t line) const {
        if (time_group_ == 0) {
            const std::string_view s = f[columns_.at("time")];
            auto ns = parse_decimal_seconds(s);
            if (!ns) {
                fail(line, "time",
                     "'" + std::string(s) +
                         "' is not decimal GPS seconds (digits[.digits], at most 9 decimals)");
            }
            return GpsTime{*ns};
        }
        try {
            return parse_time(std::string(f[columns_.at("utc")]));
        } catch (const ConfigError& e) {
            fail(line, "utc", e.what());
        }
    }

    void read_row(std::string_view line, std::size_t line_no) {
        const auto f = split_fields(line);
        if (f.size() != field_count_) {
            throw ConfigError("trajectory '" + path_ + "': line " + std::to_string(line_no) +
                              ": expected " + std::to_string(field_count_) +
                              " fields as in the header (line " + std::to_string(header_line_) +
                              "), found " + std::to_string(f.size()));
        }
        StampedPose s;
        s.t = time(f, line_no);
        if (!samples_.empty() && s.t <= samples_.back().t) {
            fail(line_no, kTimeGroups[time_group_][0],
                 "time " + format_decimal_seconds(s.t.time_since_epoch()) +
                     " s is not after the previous sample's (line " + std::to_string(last_line_) +
                     ", " + format_decimal_seconds(samples_.back().t.time_since_epoch()) + " s)");
        }

        const Group& pg = kPositionGroups[position_group_];
        const Eigen::Vector3d p{number(f, line_no, pg[0]), number(f, line_no, pg[1]),
                                number(f, line_no, pg[2])};
        if (position_group_ == 0) {
            s.pose.position = p;
        } else if (position_group_ == 1) {
            s.pose.position = georef_.local_from_world(p);
        } else {
            if (std::abs(p.x()) > 90.0) fail(line_no, "lat", "outside [-90, 90] degrees");
            if (std::abs(p.y()) > 360.0) fail(line_no, "lon", "outside [-360, 360] degrees");
            geodetic_.push_back(p);  // converted in one PROJ batch at the end
        }

        if (attitude_group_ == 0) {
            s.pose.attitude = quaternion_from_rpy(number(f, line_no, "roll") * kDegToRad,
                                                  number(f, line_no, "pitch") * kDegToRad,
                                                  number(f, line_no, "yaw") * kDegToRad);
        } else {
            Eigen::Quaterniond q{number(f, line_no, "qw"), number(f, line_no, "qx"),
                                 number(f, line_no, "qy"), number(f, line_no, "qz")};
            if (q.squaredNorm() < 1e-24) fail(line_no, "qw", "quaternion has zero norm");
            s.pose.attitude = q;
        }
        samples_.push_back(s);
        last_line_ = line_no;
    }

    void convert_geodetic() {
        if (position_group_ != 2) return;
        std::vector<Eigen::Vector3d> local;
        try {
            local = georef_.local_from_geodetic(geodetic_);
        } catch (const ConfigError& e) {
            throw ConfigError("trajectory '" + path_ + "': " + e.what());
        }
        for (std::size_t i = 0; i < samples_.size(); ++i) samples_[i].pose.position = local[i];
    }

    const std::string& path_;
    const Georef& georef_;
    std::map<std::string, std::size_t, std::less<>> columns_;
    std::size_t field_count_ = 0, header_line_ = 0, last_line_ = 0;
    std::size_t time_group_ = 0, position_group_ = 0, attitude_group_ = 0;
    std::vector<StampedPose> samples_;
    std::vector<Eigen::Vector3d> geodetic_;
};

void append_double(std::string& out, double v) {
    char buf[32];
    // Shortest representation that reads back to the same double.
    const auto res = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, res.ptr);
}

}  // namespace

Trajectory load_trajectory_csv(const std::string& path, const Georef& georef,
                               Interpolation interp) {
    std::ifstream in(path);
    if (!in) throw IoError("trajectory '" + path + "': cannot open: " + std::strerror(errno));
    return Trajectory(CsvReader(path, georef).read(in), interp);
}

Trajectory parse_trajectory_csv(const std::string& text, const std::string& name,
                                const Georef& georef, Interpolation interp) {
    std::istringstream in(text);
    return Trajectory(CsvReader(name, georef).read(in), interp);
}

void save_trajectory_csv(const std::string& path, const Trajectory& trajectory) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError("trajectory '" + path + "': cannot create: " + std::strerror(errno));
    std::string text = "time,x,y,z,qw,qx,qy,qz\n";
    for (const StampedPose& s : trajectory.samples()) {
        text += format_decimal_seconds(s.t.time_since_epoch());
        for (double v :
             {s.pose.position.x(), s.pose.position.y(), s.pose.position.z(), s.pose.attitude.w(),
              s.pose.attitude.x(), s.pose.attitude.y(), s.pose.attitude.z()}) {
            text += ',';
            append_double(text, v);
        }
        text += '\n';
    }
    out << text;
    out.close();
    if (!out) throw IoError("trajectory '" + path + "': write failed");
}

}  // namespace mirage::core
