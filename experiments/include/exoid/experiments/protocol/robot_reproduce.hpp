#pragma once
// `exoid reproduce --model M` for a chain: the paper's protocol on any serial chain, composed of
// the chain commands. A designed excitation (excite), its simulated record (the one-fit record and
// the segmental strategy's last stage), a validation record of another motion, one record per
// segmental stage with the joints above locked; every method on the one fit and stage by stage;
// report.md with every base parameter's error against the simulation's truth.
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/sim/motor_rig.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace exoid::experiments {

struct ChainReproduceArgs {
  std::string out = "results/reproduce";
  bool plots = true;
  /// Model path, duration, dt, sensors (noise, quantisation, torque noise); trajectory and seed set per record.
  sim::ChainSimConfig sim;
  std::uint64_t seed = 1;  ///< every record's seed and the design's derive from it
  int design_restarts = 8;  ///< the design's restarts (exoid excite --restarts), >= 1
  bool keep_edits = false;  ///< refuse to rewrite a previous run's outputs changed by hand
  std::vector<ident::Method> methods{ident::Method::kLs, ident::Method::kRls, ident::Method::kPso,
                                     ident::Method::kRlsPso, ident::Method::kLad, ident::Method::kIvBand,
                                     ident::Method::kIdimIv};
};

/// Runs the protocol into args.out (prepared first, as exoid reproduce's folder) and returns 0.
/// Throws std::invalid_argument for a bad model or settings.
int reproduceChain(const ChainReproduceArgs& args);

}  // namespace exoid::experiments
