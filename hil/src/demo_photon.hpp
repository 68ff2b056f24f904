// SPDX-License-Identifier: Apache-2.0
// The photon-counting part of `mirage demo` (docs/photon-counting.md §8): the ALIRT-like array
// over the camouflaged vehicle at night, the events and the coincidence-processed points at
// several dwells, and views of the vehicle under its net.
#pragma once
#include <filesystem>
#include <memory>
#include <string>

#include "mirage/render/embree_renderer.hpp"
#include "mirage/scene/scene.hpp"

namespace mirage::hil {

struct PhotonDemo {
    std::string scene_spec;  // "demo:<seed>"
    std::string seconds;     // length of the pass
    std::uint64_t seed = 1;
    int threads = 0;
};

void run_photon_demo(const PhotonDemo& d, const std::filesystem::path& dir,
                     const std::shared_ptr<const scene::Scene>& scene, double scene_seconds,
                     std::shared_ptr<const render::EmbreeRenderer>& renderer);

}  // namespace mirage::hil
