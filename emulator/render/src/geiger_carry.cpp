// SPDX-License-Identifier: Apache-2.0
// A free-running Geiger-mode array's dead time across pulses (docs/photon-counting.md §2.1):
// frame by frame, each pixel's window opens where its previous window's last detection left it
// dead; render()'s chunks hand the last frame's state on through a CarryChain.
#include <algorithm>

#include "shading.hpp"

namespace mirage::render {

// Where pixel-pulse `pulse`'s window opens armed (ns into it; ≤ 0: at its start): what its
// pixel's previous frame carried, or armed when that frame was not drawn on this scratch.
double PulseShader::carried(std::uint64_t pulse, const GeigerBatch& b) const {
    if (!geiger_->free_running) return 0.0;
    const std::uint32_t pixels = sensor_.array.pixels();
    const std::uint64_t p = pulse % pixels;
    if (p >= b.carry.size() || b.carry_frame[p] != pulse / pixels) return 0.0;
    return std::max(0.0, b.carry[p]);
}

// After the frame's pixel-pulses [i0, end) of a batch starting at pulse `first`: each pixel is
// dead until its own draw's re-arming or, when crosstalk drew the frame (b.armed), its last kept
// event's dead time, whichever is later; the next window opens one period on.
void PulseShader::carry_on(std::uint64_t first, std::uint32_t i0, std::uint32_t end, bool crosstalk,
                           GeigerBatch& b) const {
    const std::uint32_t pixels = sensor_.array.pixels();
    b.carry.resize(pixels, 0.0);
    b.carry_frame.resize(pixels, ~std::uint64_t(0));
    for (std::uint32_t i = i0; i < end; ++i) {
        const std::uint64_t pulse = first + i;
        const auto p = static_cast<std::size_t>(pulse % pixels);
        double until = b.own_end[i - i0];
        if (crosstalk) until = std::max(until, b.armed[i - i0]);
        b.carry[p] = until - geiger_->period_ns;
        b.carry_frame[p] = pulse / pixels + 1;
    }
}

// The carry is taken when the chunk's first frame is drawn (take_carry), so its first batch's
// rays are traced while the chunk before is still drawing.
void PulseShader::begin_chunk(std::uint64_t first, ShadeScratch& scratch) const {
    if (!chain_) return;
    const std::uint32_t pixels = sensor_.array.pixels();
    GeigerBatch& b = scratch.geiger;
    const std::uint64_t frame = first / pixels;
    b.carry.assign(pixels, 0.0);
    b.carry_frame.assign(pixels, frame);
    b.take_frame = frame;
}

void PulseShader::take_carry(GeigerBatch& b) const {
    if (!chain_ || b.take_frame == 0) return;
    if (!chain_->take(b.take_frame, b.carry))
        b.carry.assign(sensor_.array.pixels(), 0.0);  // aborted: the run is ending
    b.take_frame = 0;
}

void PulseShader::end_chunk(std::uint64_t next, ShadeScratch& scratch) const {
    if (!chain_) return;
    const std::uint32_t pixels = sensor_.array.pixels();
    GeigerBatch& b = scratch.geiger;
    take_carry(b);  // (a chunk that drew nothing passes its carry on)
    const std::uint64_t frame = next / pixels;
    std::vector<double> carry(pixels, 0.0);
    for (std::size_t p = 0; p < std::min<std::size_t>(pixels, b.carry.size()); ++p)
        if (b.carry_frame[p] == frame) carry[p] = b.carry[p];
    chain_->put(frame, std::move(carry));
}

void PulseShader::abort_chunks() const {
    if (chain_) chain_->abort();
}

}  // namespace mirage::render
