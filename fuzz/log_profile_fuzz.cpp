// A lab's log profile (TOML, `exoid identify --profile`): parsed or refused with file:line:column,
// never a crash or a silently odd setting.
#include "fuzz_support.hpp"

#include "exoid/experiments/protocol/log_input.hpp"

#include <cmath>
#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = exoid::fuzz::asFile(data, size, ".toml");
  try {
    const exoid::experiments::LogInput in = exoid::experiments::readLogProfile(path);
    const auto& f = in.csv.format;
    EXOID_FUZZ_CHECK(f.time_scale_s > 0 && std::isfinite(f.time_scale_s));
    EXOID_FUZZ_CHECK(f.angle_scale_rad > 0 && std::isfinite(f.angle_scale_rad));
    if (in.thigh_length_m) EXOID_FUZZ_CHECK(*in.thigh_length_m > 0 && std::isfinite(*in.thigh_length_m));
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
