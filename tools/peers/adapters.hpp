// Internal to tools/peers: the prepare functions behind peer_methods().
#pragma once

#include <memory>

#include "continuous.hpp"
#include "peers.hpp"

namespace hedra::peers::detail {

std::unique_ptr<PreparedPair> prepare_ccd_gjk(const PeerPair& pair);
std::unique_ptr<PreparedPair> prepare_ccd_gjk_epa(const PeerPair& pair);
std::unique_ptr<PreparedPair> prepare_ccd_mpr(const PeerPair& pair);
std::unique_ptr<PreparedPair> prepare_fcl_libccd(const PeerPair& pair);
std::unique_ptr<PreparedPair> prepare_fcl_indep(const PeerPair& pair);
std::unique_ptr<PreparedPair> prepare_bullet_f32_gjk_epa(const PeerPair& pair);
std::unique_ptr<PreparedPair> prepare_bullet_f64_gjk_epa(const PeerPair& pair);
std::unique_ptr<PreparedPair> prepare_bullet_f32_signed(const PeerPair& pair);
std::unique_ptr<PreparedPair> prepare_bullet_f64_signed(const PeerPair& pair);

// A prepared pair whose every query answers "unsupported: <why>".
std::unique_ptr<PreparedPair> unsupported(const char* why);

// Times of impact (continuous.hpp).
std::unique_ptr<PreparedSweep> prepare_bullet_f64_gjk_cast(const SweepPair& pair);
std::unique_ptr<PreparedSweep> prepare_bullet_f64_subsimplex(const SweepPair& pair);
std::unique_ptr<PreparedSweep> prepare_bullet_f64_continuous(const SweepPair& pair);
std::unique_ptr<PreparedSweep> prepare_bullet_f32_continuous(const SweepPair& pair);
std::unique_ptr<PreparedSweep> prepare_fcl_naive_trans(const SweepPair& pair);
std::unique_ptr<PreparedSweep> prepare_fcl_ca_trans(const SweepPair& pair);
std::unique_ptr<PreparedSweep> prepare_fcl_ca_linear(const SweepPair& pair);
std::unique_ptr<PreparedSweep> unsupported_sweep(const char* why);

}  // namespace hedra::peers::detail
