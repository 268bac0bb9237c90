#pragma once
// The Python module's parts, each registering its functions (module.cpp calls them).
#include <pybind11/pybind11.h>

namespace exoid::python {

void bindData(pybind11::module_& m);     ///< datasets, regressor, processing (bind_data.cpp)
void bindMethods(pybind11::module_& m);  ///< identification and identifiability (bind_methods.cpp)
void bindModel(pybind11::module_& m);    ///< robot models: serial chains and their regressor (bind_model.cpp)
/// simulate (bind_sim.cpp); built with MuJoCo only, else module.cpp registers a stub that says so.
void bindSim(pybind11::module_& m);

}  // namespace exoid::python
