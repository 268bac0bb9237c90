// Built without MuJoCo: simulate exists and says why it cannot run.
#include "bindings.hpp"

#include <stdexcept>

namespace exoid::python {

void bindSim(pybind11::module_& m) {
  m.def("simulate",
        [](const pybind11::kwargs&) -> pybind11::object {
          throw std::runtime_error("simulate: this exoid was built without MuJoCo (EXOID_WITH_MUJOCO=OFF)");
        },
        "Not available: this exoid was built without MuJoCo (EXOID_WITH_MUJOCO=OFF).");
  m.attr("has_simulator") = false;
}

}  // namespace exoid::python
