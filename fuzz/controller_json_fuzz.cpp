// A rig's controller description (JSON, `exoid identify --controller`, IDIM-IV): read into a
// valid controller or refused naming the file and field.
#include "fuzz_support.hpp"

#include "exoid/experiments/protocol/controller_io.hpp"

#include <stdexcept>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = exoid::fuzz::asFile(data, size, ".json");
  // The APAL leg's two joints, or a 3-joint leg's (by the input's length: any input meets both).
  const std::vector<std::string> joints = size % 2 ? std::vector<std::string>{"hip", "knee"} : std::vector<std::string>{"hip", "knee", "ankle"};
  try {
    const exoid::ident::Controller c = exoid::experiments::readControllerJson(path, joints);
    c.validate(joints);  // what was read must be a controller IDIM-IV can simulate
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
