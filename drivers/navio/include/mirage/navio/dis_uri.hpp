// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>

#include "mirage/dis/entity_track.hpp"

namespace mirage::navio {

// The DIS source's options out of its `--nav` transport (docs/dis.md §6):
// udp://[bind]:port[?exercise=N][&entity=site.app.entity][&timeout=S]. Returns them and sets
// `udp_uri` to the socket's URI without them. Throws ConfigError naming the URI and the option.
dis::TrackConfig parse_dis_transport(const std::string& transport, std::string& udp_uri);

}  // namespace mirage::navio
