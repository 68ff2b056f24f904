// SPDX-License-Identifier: Apache-2.0
#pragma once
// Writes generated fuzz seeds into the source tree: <root>/<test folder of the target>/fuzz_seeds/
// <target>/gen_<name>. Hand-written seeds (any other name) are left alone.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mirage/core/time.hpp"
#include "mirage/nav/nav_sample.hpp"

namespace mirage::testing::seeds {

class SeedWriter {
  public:
    explicit SeedWriter(std::filesystem::path root) : root_(std::move(root)) {}
    void put(const std::string& target, const std::string& name,
             std::span<const std::uint8_t> bytes);
    void put(const std::string& target, const std::string& name, std::string_view text);
    // put() with a first byte that picks the harness's mode (fuzz targets documented so).
    void put(const std::string& target, const std::string& name, std::uint8_t mode,
             std::span<const std::uint8_t> bytes);
    std::size_t files() const { return files_; }
    std::uint64_t bytes() const { return bytes_; }

  private:
    std::filesystem::path root_;
    std::vector<std::string> cleaned_;
    std::size_t files_ = 0;
    std::uint64_t bytes_ = 0;
};

std::span<const std::uint8_t> as_bytes(std::string_view text);

// Sample k of a short drive near Zürich, 10 Hz, every field set (GPS week 2300).
nav::NavSample drive_sample(int k, nav::Protocol source);

void write_wire_seeds(SeedWriter& w);  // Velodyne, Ouster
void write_nav_seeds(SeedWriter& w);   // NMEA, NovAtel, NCOM, CAN, slcan, gs_usb, nav logs
void write_file_seeds(SeedWriter& w);  // pcap frames and files, LAS, trajectory CSV

}  // namespace mirage::testing::seeds
