// SPDX-License-Identifier: Apache-2.0
#include "mirage/pcap/writer.hpp"

#include <fmt/format.h>
#include <pcap/pcap.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "mirage/core/error.hpp"
#include "udp_framer.hpp"

namespace mirage::pcap {

struct Writer::Impl {
    pcap_t* dead = nullptr;
    pcap_dumper_t* dumper = nullptr;
    bool nanosecond = true;
    FrameOptions options;
    std::uint16_t next_id = 1;
    std::vector<std::uint8_t> frame;
    int first_errno = 0;  // errno of the first failed stdio write (its flag alone has no cause)
};

Writer::Writer(const std::string& path, bool nanosecond, FrameOptions options)
    : impl_(new Impl), path_(path) {
    impl_->nanosecond = nanosecond;
    impl_->options = options;
    impl_->dead = pcap_open_dead_with_tstamp_precision(
        DLT_EN10MB, 262144, nanosecond ? PCAP_TSTAMP_PRECISION_NANO : PCAP_TSTAMP_PRECISION_MICRO);
    if (impl_->dead != nullptr) impl_->dumper = pcap_dump_open(impl_->dead, path.c_str());
    if (impl_->dumper == nullptr) {
        const std::string why = impl_->dead ? pcap_geterr(impl_->dead) : "out of memory";
        if (impl_->dead) pcap_close(impl_->dead);
        delete impl_;
        throw IoError(fmt::format("pcap writer '{}': cannot create: {}", path, why));
    }
}

Writer::~Writer() {
    try {
        close();
    } catch (const std::exception& e) {
        std::fputs(fmt::format("{}\n", e.what()).c_str(), stderr);
    }
    delete impl_;
}

bool Writer::write(std::int64_t time_ns, const Endpoint& src, const Endpoint& dst,
                   std::span<const std::uint8_t> payload) {
    if (impl_->dumper == nullptr || payload.size() > kMaxPayload || time_ns < 0) {
        ++rejected_;
        return false;
    }
    pcap_pkthdr hdr{};
    hdr.ts.tv_sec = static_cast<time_t>(time_ns / 1'000'000'000);
    const std::int64_t sub = time_ns % 1'000'000'000;
    // The dead handle's precision tells libpcap what tv_usec holds (ns or µs).
    hdr.ts.tv_usec = static_cast<suseconds_t>(impl_->nanosecond ? sub : sub / 1000);
    // Linux's IP id counter; the fragments of one datagram share it.
    const std::uint16_t id = impl_->next_id++;
    detail::frame_udp(impl_->options, src, dst, id, payload, kMtu, impl_->frame,
                      [&](std::span<const std::uint8_t> f) {
                          hdr.caplen = hdr.len = static_cast<bpf_u_int32>(f.size());
                          pcap_dump(reinterpret_cast<u_char*>(impl_->dumper), &hdr, f.data());
                          ++frames_;
                      });
    if (impl_->first_errno == 0 && std::ferror(pcap_dump_file(impl_->dumper)))
        impl_->first_errno = errno ? errno : EIO;
    ++datagrams_;
    return true;
}

void Writer::flush() {
    if (impl_->dumper == nullptr) return;
    FILE* file = pcap_dump_file(impl_->dumper);
    errno = 0;
    // ferror also catches a failure of an earlier implicit flush by stdio.
    if (pcap_dump_flush(impl_->dumper) != 0 || std::ferror(file)) {
        if (impl_->first_errno == 0) impl_->first_errno = errno ? errno : EIO;
        throw IoError(fmt::format("pcap writer '{}': write failed: {}", path_,
                                  std::strerror(impl_->first_errno)));
    }
}

void Writer::close() {
    if (impl_->dumper == nullptr) return;
    std::string error;
    try {
        flush();
    } catch (const IoError& e) {
        error = e.what();
    }
    pcap_dump_close(impl_->dumper);
    pcap_close(impl_->dead);
    impl_->dumper = nullptr;
    impl_->dead = nullptr;
    if (!error.empty()) throw IoError(error);
}

}  // namespace mirage::pcap
