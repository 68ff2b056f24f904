// SPDX-License-Identifier: Apache-2.0
// Draining a reader, shared by the pcap reader tests.
#pragma once
#include <vector>

#include "mirage/pcap/pcap.hpp"

namespace mirage::test {

// Every datagram the reader yields, in order.
inline std::vector<pcap::UdpDatagram> read_all(pcap::Reader& r) {
    std::vector<pcap::UdpDatagram> v;
    pcap::UdpDatagram d;
    while (r.next(d)) v.push_back(d);
    return v;
}

}  // namespace mirage::test
