// SPDX-License-Identifier: Apache-2.0
// A dead-reckoned DIS state as the protocol-neutral navigation sample (docs/dis.md §4), so the
// one mapper into the scene frame takes DIS like any INS message.
#pragma once
#include "mirage/core/time.hpp"
#include "mirage/dis/dead_reckoning.hpp"
#include "mirage/nav/nav_sample.hpp"

namespace mirage::dis {

// WGS84 latitude, longitude and ellipsoidal height of the ECEF location; the FRD body's NED
// Euler angles there (heading in [0, 2π)); the velocity in NED. Fields: time, position,
// attitude, velocity; source Dis, quality Simulated.
nav::NavSample to_sample(const Kinematics& k, core::GpsTime t);

// The other way, for a sender (`mirage fake-ins --protocol dis`): a sample's position, attitude
// and velocity as the state of entity `id`, its time as an absolute timestamp (UTC past the
// hour); dead-reckoned by RPB (7: velocity in body axes, turning at the sample's body rates)
// when it has rates, which carries a vehicle on a steady turn exactly, else by FPW (2).
EntityState from_sample(const nav::NavSample& s, const EntityId& id, std::uint8_t exercise);

}  // namespace mirage::dis
