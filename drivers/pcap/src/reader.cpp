// SPDX-License-Identifier: Apache-2.0
#include <fmt/format.h>
#include <pcap/pcap.h>

#include "frame_parser.hpp"
#include "ip_reassembler.hpp"
#include "mirage/core/error.hpp"
#include "mirage/pcap/pcap.hpp"

namespace mirage::pcap {

struct Reader::Impl {
    pcap_t* handle = nullptr;
    int dlt = 0;
    bool done = false;
    std::string error;
    detail::IpReassembler reassembler;
};

namespace {

bool supported_dlt(int dlt) {
    switch (dlt) {
        case DLT_EN10MB:
        case DLT_LINUX_SLL:
        case DLT_LINUX_SLL2:
        case DLT_NULL:
        case DLT_RAW:
        case DLT_IPV4:
            return true;
        default:
            return false;
    }
}

}  // namespace

Reader::Reader(const std::string& path) : impl_(new Impl) {
    char errbuf[PCAP_ERRBUF_SIZE] = {};
    // Nanosecond precision: libpcap scales µs files up, so ts.tv_usec always holds ns.
    impl_->handle =
        pcap_open_offline_with_tstamp_precision(path.c_str(), PCAP_TSTAMP_PRECISION_NANO, errbuf);
    if (impl_->handle == nullptr) {
        delete impl_;
        throw IoError(fmt::format("pcap reader '{}': {}", path, errbuf));
    }
    impl_->dlt = pcap_datalink(impl_->handle);
    if (!supported_dlt(impl_->dlt)) {
        const char* name = pcap_datalink_val_to_name(impl_->dlt);
        const int dlt = impl_->dlt;
        pcap_close(impl_->handle);
        delete impl_;
        throw IoError(fmt::format(
            "pcap reader '{}': link type {} ({}) not supported (Ethernet, Linux SLL/SLL2, "
            "BSD loopback or raw IPv4 only)",
            path, dlt, name ? name : "unknown"));
    }
}

Reader::~Reader() {
    pcap_close(impl_->handle);
    delete impl_;
}

const std::string& Reader::error() const { return impl_->error; }

bool Reader::next(UdpDatagram& out) {
    auto count = [this](FrameStatus s, std::uint64_t n = 1) {
        counts_[static_cast<std::size_t>(s)] += n;
    };
    auto& r = impl_->reassembler;
    while (!impl_->done) {
        pcap_pkthdr* hdr = nullptr;
        const u_char* data = nullptr;
        const int rc = pcap_next_ex(impl_->handle, &hdr, &data);
        if (rc == 0) continue;  // live-capture timeout; not produced by files
        if (rc != 1) {
            // PCAP_ERROR_BREAK is the clean end; PCAP_ERROR a damaged or cut last record.
            if (rc == PCAP_ERROR) {
                impl_->error = pcap_geterr(impl_->handle);
                count(FrameStatus::Truncated);
            }
            impl_->done = true;
            r.drain();
            count(FrameStatus::Fragment, r.take_abandoned());
            return false;
        }
        const std::int64_t time_ns =
            static_cast<std::int64_t>(hdr->ts.tv_sec) * 1'000'000'000 + hdr->ts.tv_usec;
        if (r.pending() != 0) {
            r.expire(time_ns);
            count(FrameStatus::Fragment, r.take_abandoned());
        }

        detail::Ipv4Packet ip;
        const std::span<const std::uint8_t> frame(data, hdr->caplen);
        FrameStatus status = detail::parse_ipv4_frame(impl_->dlt, frame, hdr->len, ip);
        if (status != FrameStatus::Ok) {
            count(status);
            continue;
        }
        std::uint64_t frames = 1;
        std::vector<std::uint8_t> whole;
        std::span<const std::uint8_t> ip_payload = ip.payload;
        if (ip.is_fragment()) {
            const auto res = r.add(ip, time_ns, whole, frames);
            count(FrameStatus::Fragment, r.take_abandoned());  // evicted to make room
            if (res == detail::IpReassembler::Result::Pending) continue;
            if (res == detail::IpReassembler::Result::Bad) {
                count(FrameStatus::BadHeader);
                continue;
            }
            ip_payload = whole;
        }
        status = detail::parse_udp(ip_payload, out);
        count(status, frames);
        if (status != FrameStatus::Ok) continue;
        out.time_ns = time_ns;
        out.src.ip = ip.src;
        out.dst.ip = ip.dst;
        return true;
    }
    return false;
}

std::vector<UdpDatagram> read_udp(const std::string& path, std::uint16_t dst_port) {
    Reader reader(path);
    std::vector<UdpDatagram> result;
    UdpDatagram d;
    while (reader.next(d))
        if (dst_port == 0 || d.dst.port == dst_port) result.push_back(std::move(d));
    return result;
}

}  // namespace mirage::pcap
