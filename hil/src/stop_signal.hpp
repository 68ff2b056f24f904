// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>

namespace mirage::hil {

// SIGINT/SIGTERM set this flag (the first time) so a streaming command can stop cleanly and
// close its files; a second signal exits at once.
const std::atomic<bool>& install_stop_signal();

}  // namespace mirage::hil
