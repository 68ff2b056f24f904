// SPDX-License-Identifier: Apache-2.0
// The waveform data packets of a LAS file with point formats 4, 5, 9 or 10 (docs/file-formats.md
// §6.1): an EVLR header (user LASF_Spec, record 65535) followed by the packets, streamed to
// `<base>.wdp` beside the LAS file as points are written, so the file is valid at any moment with
// its packets external; close() of an internal-waveform writer copies it into the LAS file's EVLR.
// Packet offsets count from the EVLR header's first byte in both places, so they need no change.
#pragma once
#include <sys/types.h>

#include <cstdint>
#include <string>

namespace mirage::las {

class WdpFile {
  public:
    static constexpr std::size_t kEvlrHeaderSize = 60;
    // The .wdp path of a LAS file: its extension (if any) replaced by .wdp.
    static std::string path_for(const std::string& las_path);

    // Creates the file with its EVLR header; IoError naming it on failure.
    explicit WdpFile(const std::string& las_path);
    ~WdpFile();  // closes; never throws
    WdpFile(const WdpFile&) = delete;
    WdpFile& operator=(const WdpFile&) = delete;

    const std::string& path() const { return path_; }
    // Bytes in the file, header included: the offset the next packet gets.
    std::uint64_t end() const { return end_; }
    // Appends packets and updates the header's length; returns 0 or an errno, and on an error
    // leaves end() at the last whole write (the header still covers it).
    int append(const std::uint8_t* data, std::size_t n) noexcept;
    // Copies the whole file to `fd` at `pos` (the LAS file's EVLR); returns 0 or an errno.
    int copy_to(int fd, off_t pos) const noexcept;
    // Closes and deletes the file (after a successful copy).
    void remove() noexcept;

  private:
    std::string path_;
    int fd_ = -1;
    std::uint64_t end_ = 0;
};

}  // namespace mirage::las
