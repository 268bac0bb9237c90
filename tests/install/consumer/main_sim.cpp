// Uses exoid::sim from the installed package: the model from the installed data directory.
#include "exoid/sim/data_dir.hpp"
#include "exoid/sim/model.hpp"

#include <cstdio>

int main() {
  const exoid::sim::LegModel leg = exoid::sim::loadLeg(exoid::sim::defaultModelPath());
  std::printf("model %s from %s\n", exoid::sim::defaultModelPath().c_str(), exoid::sim::dataDir().c_str());
  return leg.model ? 0 : 1;
}
