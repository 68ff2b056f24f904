// SPDX-License-Identifier: Apache-2.0
// libFuzzer: whole capture files (classic pcap or pcapng, any link type) through pcap::Reader,
// which libpcap feeds from an in-memory file. A file it cannot open must be an IoError (a filter
// for a link type without UDP a ConfigError); once read to the end, the frames counted by status
// cover every datagram returned.
#include <cstddef>
#include <cstdint>
#include <numeric>

#include "fuzz_file.hpp"
#include "mirage/core/error.hpp"
#include "mirage/pcap/pcap.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static mirage::testing::FuzzFile file;
    const std::string& path = file.write(data, size);
    mirage::pcap::ReaderOptions options;
    options.unknown_link_throws = false;
    try {
        mirage::pcap::Reader reader(path, options);
        // Odd sizes also run the port filter (reassembled datagrams are re-framed for it).
        if (size % 2 == 1) reader.set_filter("udp port 2368");
        mirage::pcap::UdpDatagram d;
        std::uint64_t datagrams = 0;
        while (reader.next(d)) {
            if (d.payload.size() > 65535) __builtin_trap();
            ++datagrams;
        }
        const auto& c = reader.counts();
        if (std::accumulate(c.begin(), c.end(), std::uint64_t{0}) < datagrams) __builtin_trap();
    } catch (const mirage::IoError&) {      // not a capture libpcap can open
    } catch (const mirage::ConfigError&) {  // a link type the filter cannot be compiled for
    }
    return 0;
}
