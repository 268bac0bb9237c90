#pragma once
// Conversions between exoid's C++ types and the Python module's dicts and keyword options,
// shared by the binding files (bind_*.cpp).
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/leg/regressor.hpp"
#include "exoid/ident/estimators/segmental.hpp"

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

namespace exoid::python {

namespace py = pybind11;

/// A Dataset as the dict read_dataset returns: t, q, tau, optional qd, qdd, extra, comments, sampling.
py::dict datasetDict(const ident::Dataset& d);
/// The reverse; throws std::invalid_argument naming a missing key or a size mismatch.
ident::Dataset datasetFrom(const py::dict& d);

/// What the command line would say beside an estimate: not usable, unidentified columns, a
/// condition number above 100 (identify's threshold).
std::vector<std::string> estimateWarnings(const ident::Estimate& e);
/// One estimate: x, method, the summary (status, usable, message, iterations, costs, wall time),
/// whatever the method reports (rank, condition number, box, optimality gaps, history) and its
/// warnings (estimateWarnings).
py::dict estimateDict(const ident::Estimate& e);

/// MethodOptions from keyword arguments (the names in kMethodOptionNames); every key is consumed
/// or a TypeError names it and the accepted ones; the result is validated (ValueError).
ident::MethodOptions methodOptions(const py::kwargs& kw, const char* function);
/// The keyword options every identification function accepts, for docstrings.
extern const char* const kMethodOptionsDoc;

/// SignalOptions as `exoid identify` sets them for a processing ("parallel" or "paper").
ident::SignalOptions signalOptions(const std::string& processing, std::optional<double> cutoff_hz, int filter_order, int decimation,
                                   const std::string& base_terms);
extern const char* const kSignalOptionsDoc;

ident::LegConstants legConstants(double thigh_length_m, double gravity_mps2);

py::object optional(const std::optional<double>& v);

}  // namespace exoid::python
