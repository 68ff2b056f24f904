// SPDX-License-Identifier: Apache-2.0
// The first event of a gated Geiger-mode pixel that reports its first detection only, straight
// from its signal (docs/photon-counting.md §2): no EventRate is built, the same event results.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

#include "mirage/physics/geiger.hpp"

namespace mirage::physics {

// Bins k0 + j (j < n) of a gate expecting scale·w[j] signal primary events (an arrival's
// photo-electrons over its pulse's shares; EventRate::add_run's arguments), and the shares'
// running sums shares[j] = w[0] + … + w[j], added in that order (the table's own).
struct SignalRun {
    std::int64_t k0;
    double scale;
    const double* w;
    const double* shares;
    std::size_t n;
};

enum class FirstEventResult : std::uint8_t { None, Event, Undecided };

// The pixel's first event for the level Λ = −ln u of its first primary event and the uniform
// that decides signal or noise, before its jitter: for runs in increasing bins, each after the
// previous one's last bin with signal, the event (or none) that an EventRate built by add_run
// from the same runs and geiger_events with max_events 1 give (their reported time less its
// jitter), to the bit, without a chain of additions: Λ at each bin's end is the sum before
// the run plus scale·shares[j] plus the noise, so the bins below the level are counted in one
// loop that vectorises. Undecided where the runs overlap, a run starts before the gate opens,
// or rounding puts the event's bin off the bin whose sum crossed the level: the caller builds
// the rate then.
FirstEventResult gated_first_event(std::span<const SignalRun> runs, std::size_t bins,
                                   double noise_per_bin, double bin_ns, double level,
                                   double u_signal, GeigerEvent& out);

}  // namespace mirage::physics
