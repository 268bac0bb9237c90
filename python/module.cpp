// The `exoid` Python module: the identification library with numpy arrays in and out, and the
// simulator when exoid is built with MuJoCo. Errors keep their messages: std::invalid_argument ->
// ValueError, other std exceptions (e.g. a dataset's file:line:column error) -> RuntimeError.
#include "bindings.hpp"

#include "exoid/experiments/version.hpp"

PYBIND11_MODULE(exoid, m) {
  m.doc() = "exoid: dynamic parameter identification of a 2-link leg (X = [Mxt, Myt, Jt, fc1, fv1, Mxs, Mys, Js, "
            "fc2, fv2], SI units). The identification library of the exoid harness, numpy in and out; simulate() "
            "when built with MuJoCo (has_simulator).";
  m.attr("__version__") = exoid::kVersion;
  m.attr("git_revision") = exoid::kGitRevision;
  exoid::python::bindData(m);
  exoid::python::bindMethods(m);
  exoid::python::bindModel(m);
  exoid::python::bindSim(m);
}
