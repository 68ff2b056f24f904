// SPDX-License-Identifier: Apache-2.0
#include "wdp_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "las_layout.hpp"
#include "mirage/core/error.hpp"
#include "mirage/core/output_file.hpp"

namespace mirage::las {
namespace {

using namespace layout;

int pwrite_all(int fd, const std::uint8_t* p, std::size_t n, off_t pos) noexcept {
    while (n > 0) {
        const ssize_t w = ::pwrite(fd, p, n, pos);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return w < 0 ? errno : EIO;
        p += w;
        n -= static_cast<std::size_t>(w);
        pos += w;
    }
    return 0;
}

// The EVLR header (LAS 1.4 §2.7) of a waveform data packet record of `length` bytes.
std::array<std::uint8_t, WdpFile::kEvlrHeaderSize> evlr_header(std::uint64_t length) {
    std::array<std::uint8_t, WdpFile::kEvlrHeaderSize> h{};
    std::memcpy(h.data() + 2, "LASF_Spec", 9);
    put_u16(h.data() + 18, kWaveformPacketsRecordId);
    put_u64(h.data() + 20, length);
    std::memcpy(h.data() + 28, "Waveform data packets", 21);
    return h;
}

}  // namespace

std::string WdpFile::path_for(const std::string& las_path) {
    const auto slash = las_path.find_last_of('/');
    const auto dot = las_path.find_last_of('.');
    const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
    return (has_ext ? las_path.substr(0, dot) : las_path) + ".wdp";
}

WdpFile::WdpFile(const std::string& las_path) : path_(path_for(las_path)) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0)
        throw IoError("las writer '" + path_ + "': cannot create: " + std::strerror(errno));
    const auto h = evlr_header(0);
    if (const int err = pwrite_all(fd_, h.data(), h.size(), 0); err != 0) {
        ::close(fd_);
        core::remove_failed_output(path_);
        throw IoError("las writer '" + path_ + "': cannot write: " + std::strerror(err));
    }
    end_ = kEvlrHeaderSize;
}

WdpFile::~WdpFile() {
    if (fd_ >= 0) ::close(fd_);
}

int WdpFile::append(const std::uint8_t* data, std::size_t n) noexcept {
    if (n == 0) return 0;
    if (const int err = pwrite_all(fd_, data, n, static_cast<off_t>(end_)); err != 0) {
        const int cut = ::ftruncate(fd_, static_cast<off_t>(end_));  // drop a partial packet
        (void)cut;
        return err;
    }
    end_ += n;
    const auto h = evlr_header(end_ - kEvlrHeaderSize);
    return pwrite_all(fd_, h.data(), h.size(), 0);
}

int WdpFile::copy_to(int fd, off_t pos) const noexcept {
    std::array<std::uint8_t, 1 << 16> buf;
    for (std::uint64_t at = 0; at < end_;) {
        const ssize_t r = ::pread(fd_, buf.data(), buf.size(), static_cast<off_t>(at));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return r < 0 ? errno : EIO;
        if (const int err = pwrite_all(fd, buf.data(), static_cast<std::size_t>(r),
                                       pos + static_cast<off_t>(at));
            err != 0)
            return err;
        at += static_cast<std::uint64_t>(r);
    }
    return 0;
}

void WdpFile::remove() noexcept {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    core::remove_failed_output(path_);
}

}  // namespace mirage::las
