// SPDX-License-Identifier: Apache-2.0
#include <fmt/format.h>
#include <pcap/pcap.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>

#include "frame_parser.hpp"
#include "ip_reassembler.hpp"
#include "mirage/core/error.hpp"
#include "mirage/pcap/pcap.hpp"
#include "udp_framer.hpp"

namespace mirage::pcap {

struct Reader::Impl {
    pcap_t* handle = nullptr;
    int dlt = 0;
    bool link_ok = true;
    bool done = false;
    std::string path;
    std::string error;
    std::int64_t error_offset = -1;
    std::int64_t record_offset = -1;
    detail::IpReassembler reassembler;
    // Filter on the file's frames, and on re-framed reassembled datagrams (Ethernet).
    bool filtering = false;
    bpf_program raw_filter{};
    bpf_program eth_filter{};
    std::uint64_t filtered = 0;
    std::vector<std::uint8_t> frame;  // re-framing buffer
    // The file's stdio buffer. libpcap reads each record with fread, and stdio's default
    // (st_blksize, 4 KiB) made that a read() system call per three VLP-16 records: about 30 %
    // of top-speed replay's sender time. Freed after pcap_close (in ~Impl's body).
    static constexpr std::size_t kReadBuffer = 1 << 20;
    std::unique_ptr<char[]> read_buffer;

    ~Impl() {
        if (filtering) {
            pcap_freecode(&raw_filter);
            pcap_freecode(&eth_filter);
        }
        if (handle) pcap_close(handle);
    }
    // Byte offset of the next record. ftell costs an lseek system call per record (the profile
    // of top-speed replay showed it), so classic pcap files with 16-byte record headers are
    // counted instead: header + caplen, unless libpcap may have cut the record to the
    // snapshot length (then the file read more than caplen and ftell is asked once).
    bool classic16 = false;
    std::int64_t next_at = -1;
    std::int64_t tell() const {
        if (next_at >= 0) return next_at;
        FILE* f = pcap_file(handle);
        return f ? static_cast<std::int64_t>(std::ftell(f)) : -1;
    }
    void advance(std::int64_t at, const pcap_pkthdr& hdr) {
        const bool whole = at >= 0 && static_cast<int>(hdr.caplen) < pcap_snapshot(handle);
        next_at = classic16 && whole ? at + 16 + static_cast<std::int64_t>(hdr.caplen) : -1;
    }
};

namespace {
// Classic pcap magics with 16-byte record headers (µs and ns, either byte order), read from
// the file's first 4 bytes; the modified-pcap (Kuznetzov) format and pcapng are not.
bool classic_16_byte_records(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return false;
    unsigned char b[4] = {};
    const bool got = std::fread(b, 1, 4, f) == 4;
    std::fclose(f);
    if (!got) return false;
    const std::uint32_t le = std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 |
                             std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
    return le == 0xA1B2C3D4u || le == 0xD4C3B2A1u || le == 0xA1B23C4Du || le == 0x4D3CB2A1u;
}
}  // namespace

const char* to_string(FrameStatus s) {
    switch (s) {
        case FrameStatus::Ok:
            return "ok";
        case FrameStatus::Truncated:
            return "truncated";
        case FrameStatus::NotIpv4:
            return "not-ip";
        case FrameStatus::NotUdp:
            return "not-udp";
        case FrameStatus::BadHeader:
            return "bad-header";
        case FrameStatus::Fragment:
            return "fragment";
    }
    return "?";
}

Reader::Reader(const std::string& path) : Reader(path, ReaderOptions{}) {}

Reader::Reader(const std::string& path, const ReaderOptions& options) : impl_(new Impl) {
    impl_->path = path;
    char errbuf[PCAP_ERRBUF_SIZE] = {};
    // Nanosecond precision: libpcap scales µs files up, so ts.tv_usec always holds ns.
    impl_->read_buffer = std::make_unique<char[]>(Impl::kReadBuffer);
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) {
        const int err = errno;
        delete impl_;
        throw IoError(fmt::format("pcap reader '{}': {}", path, std::strerror(err)));
    }
    std::setvbuf(f, impl_->read_buffer.get(), _IOFBF, Impl::kReadBuffer);
    impl_->handle = pcap_fopen_offline_with_tstamp_precision(f, PCAP_TSTAMP_PRECISION_NANO, errbuf);
    if (impl_->handle == nullptr) {
        std::fclose(f);  // not taken over on failure
        delete impl_;
        throw IoError(fmt::format("pcap reader '{}': {}", path, errbuf));
    }
    impl_->dlt = pcap_datalink(impl_->handle);
    impl_->classic16 = classic_16_byte_records(path);
    impl_->link_ok = detail::supported_dlt(impl_->dlt);
    if (!impl_->link_ok && options.unknown_link_throws) {
        const char* name = pcap_datalink_val_to_name(impl_->dlt);
        const int dlt = impl_->dlt;
        delete impl_;
        throw IoError(fmt::format(
            "pcap reader '{}': link type {} ({}) not supported (Ethernet, Linux SLL/SLL2, "
            "BSD loopback or raw IP only)",
            path, dlt, name ? name : "unknown"));
    }
}

Reader::~Reader() { delete impl_; }

const std::string& Reader::error() const { return impl_->error; }
std::int64_t Reader::error_offset() const { return impl_->error_offset; }
std::int64_t Reader::record_offset() const { return impl_->record_offset; }
std::uint64_t Reader::filtered() const { return impl_->filtered; }
int Reader::link_type() const { return impl_->dlt; }
bool Reader::link_supported() const { return impl_->link_ok; }
const std::string& Reader::path() const { return impl_->path; }

void Reader::set_filter(const std::string& expression) {
    auto& m = *impl_;
    if (m.filtering) {
        pcap_freecode(&m.raw_filter);
        pcap_freecode(&m.eth_filter);
        m.filtering = false;
    }
    if (expression.empty()) return;
    if (pcap_compile(m.handle, &m.raw_filter, expression.c_str(), 1, PCAP_NETMASK_UNKNOWN) != 0)
        throw ConfigError(fmt::format("pcap reader '{}': filter '{}': {}", m.path, expression,
                                      pcap_geterr(m.handle)));
    pcap_t* eth = pcap_open_dead(DLT_EN10MB, 65535);
    const int rc =
        eth ? pcap_compile(eth, &m.eth_filter, expression.c_str(), 1, PCAP_NETMASK_UNKNOWN) : -1;
    const std::string why = eth ? pcap_geterr(eth) : "out of memory";
    if (eth) pcap_close(eth);
    if (rc != 0) {
        pcap_freecode(&m.raw_filter);
        throw ConfigError(
            fmt::format("pcap reader '{}': filter '{}': {}", m.path, expression, why));
    }
    m.filtering = true;
}

bool Reader::next(UdpDatagram& out) {
    constexpr std::int64_t kMaxSeconds =
        std::numeric_limits<std::int64_t>::max() / 1'000'000'000 - 1;
    auto count = [this](FrameStatus s, std::uint64_t n = 1) {
        counts_[static_cast<std::size_t>(s)] += n;
    };
    auto& m = *impl_;
    auto& r = m.reassembler;
    while (!m.done) {
        pcap_pkthdr* hdr = nullptr;
        const u_char* data = nullptr;
        const std::int64_t at = m.tell();
        const int rc = pcap_next_ex(m.handle, &hdr, &data);
        if (rc == 0) continue;  // live-capture timeout; not produced by files
        if (rc == 1) m.advance(at, *hdr);
        if (rc != 1) {
            // PCAP_ERROR_BREAK is the clean end; PCAP_ERROR a damaged or cut last record.
            if (rc == PCAP_ERROR) {
                m.error_offset = at;
                m.error = fmt::format("record at byte {}: {}", at, pcap_geterr(m.handle));
                count(FrameStatus::Truncated);
            }
            m.done = true;
            r.drain();
            count(FrameStatus::Fragment, r.take_abandoned());
            return false;
        }
        // pcapng stamps are 64-bit: one past 2262 (or before 1970) has no int64 ns and is
        // counted as a damaged record instead of overflowing (fuzz_pcap_reader).
        if (hdr->ts.tv_sec < 0 || hdr->ts.tv_sec > kMaxSeconds || hdr->ts.tv_usec < 0 ||
            hdr->ts.tv_usec >= 1'000'000'000) {
            count(FrameStatus::BadHeader);
            continue;
        }
        const std::int64_t time_ns =
            static_cast<std::int64_t>(hdr->ts.tv_sec) * 1'000'000'000 + hdr->ts.tv_usec;
        if (r.pending() != 0) {
            r.expire(time_ns);
            count(FrameStatus::Fragment, r.take_abandoned());
        }
        if (!m.link_ok) {
            count(FrameStatus::NotIpv4);
            continue;
        }

        detail::Ipv4Packet ip;
        const std::span<const std::uint8_t> frame(data, hdr->caplen);
        FrameStatus status = detail::parse_ipv4_frame(m.dlt, frame, hdr->len, ip);
        const bool fragment = status == FrameStatus::Ok && ip.is_fragment();
        // Fragments are filtered once whole; everything else as captured.
        if (m.filtering && !fragment && pcap_offline_filter(&m.raw_filter, hdr, data) == 0) {
            ++m.filtered;
            continue;
        }
        if (status != FrameStatus::Ok) {
            count(status);
            continue;
        }
        std::uint64_t frames = 1;
        std::vector<std::uint8_t> whole;
        std::span<const std::uint8_t> ip_payload = ip.payload;
        if (fragment) {
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
        if (status == FrameStatus::Ok && fragment && m.filtering) {
            // Re-frame the whole datagram as one Ethernet/IP/UDP frame for the filter.
            bool pass = false;
            auto judge = [&](std::span<const std::uint8_t> f) {
                pcap_pkthdr h{};
                h.caplen = h.len = static_cast<bpf_u_int32>(f.size());
                pass = pcap_offline_filter(&m.eth_filter, &h, f.data()) != 0;
            };
            Endpoint src{ip.src, out.src.port}, dst{ip.dst, out.dst.port};
            if (ip.v6) {
                src.ip6 = ip.src6;
                dst.ip6 = ip.dst6;
                detail::frame_udp6(FrameOptions{}, src, dst, out.payload, m.frame);
                judge(m.frame);
            } else {
                detail::frame_udp(FrameOptions{}, src, dst, static_cast<std::uint16_t>(ip.id),
                                  out.payload, 65535 + 28, m.frame, judge);
            }
            if (!pass) {
                m.filtered += frames;
                continue;
            }
        }
        count(status, frames);
        if (status != FrameStatus::Ok) continue;
        m.record_offset = at;
        out.time_ns = time_ns;
        out.src.v6 = out.dst.v6 = ip.v6;
        if (ip.v6) {
            out.src.ip = out.dst.ip = {0, 0, 0, 0};
            out.src.ip6 = ip.src6;
            out.dst.ip6 = ip.dst6;
        } else {
            out.src.ip = ip.src;
            out.dst.ip = ip.dst;
            out.src.ip6 = out.dst.ip6 = {};
        }
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
