// A rig's controller description (JSON, `exoid identify --controller`, IDIM-IV): read into a
// valid controller or refused naming the file and field.
#include "fuzz_support.hpp"

#include "exoid/experiments/protocol/controller_io.hpp"

#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = exoid::fuzz::asFile(data, size, ".json");
  try {
    const exoid::ident::ControllerModel c = exoid::experiments::readControllerJson(path);
    c.validate();  // what was read must be a controller IDIM-IV can simulate
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
