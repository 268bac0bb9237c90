// The `exoid` Python module: the identification library (ident) with numpy arrays in and out.
// Errors keep their messages: std::invalid_argument -> ValueError, other std exceptions (e.g. a
// dataset's file:line:column error) -> RuntimeError.
#include "exoid/ident/dataset.hpp"
#include "exoid/ident/identifiability.hpp"
#include "exoid/ident/methods.hpp"
#include "exoid/ident/params.hpp"
#include "exoid/ident/preprocess.hpp"
#include "exoid/ident/regressor.hpp"

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <string>

namespace py = pybind11;
using namespace exoid::ident;

namespace {

CsvReadOptions readOptions(const std::map<std::string, std::string>& columns, const std::string& time_unit,
                           const std::string& angle_unit, const std::pair<double, double>& torque_sign, bool strict_sampling,
                           double max_gap_s) {
  CsvReadOptions o;
  for (const auto& [ours, theirs] : columns) o.format.columns.emplace_back(ours, theirs);
  o.format.time_scale_s = parseTimeUnit(time_unit);
  o.format.angle_scale_rad = parseAngleUnit(angle_unit);
  o.format.torque_sign << torque_sign.first, torque_sign.second;
  o.sampling = strict_sampling ? SamplingMode::kStrict : SamplingMode::kResample;
  o.max_gap_s = max_gap_s;
  return o;
}

py::dict datasetDict(const Dataset& d) {
  py::dict out;
  out["t"] = d.t_s;
  out["q"] = Eigen::MatrixXd(d.q_rad);
  out["tau"] = Eigen::MatrixXd(d.tau_Nm);
  if (d.qd_radps) out["qd"] = Eigen::MatrixXd(*d.qd_radps);
  if (d.qdd_radps2) out["qdd"] = Eigen::MatrixXd(*d.qdd_radps2);
  py::dict extra;
  for (std::size_t k = 0; k < d.extra_names.size(); ++k) extra[py::str(d.extra_names[k])] = Eigen::VectorXd(d.extra.col(static_cast<Eigen::Index>(k)));
  out["extra"] = extra;
  out["comments"] = d.comments;
  const SamplingReport& s = d.sampling;
  out["sampling"] = py::dict(py::arg("rows_read") = s.rows_read, py::arg("median_dt_s") = s.median_dt_s,
                             py::arg("min_dt_s") = s.min_dt_s, py::arg("max_dt_s") = s.max_dt_s,
                             py::arg("intervals_off") = s.intervals_off, py::arg("resampled") = s.resampled);
  return out;
}

Dataset datasetFrom(const py::dict& d) {
  Dataset out;
  out.t_s = d["t"].cast<Eigen::VectorXd>();
  out.q_rad = d["q"].cast<Eigen::MatrixX2d>();
  out.tau_Nm = d["tau"].cast<Eigen::MatrixX2d>();
  if (d.contains("qd")) out.qd_radps = d["qd"].cast<Eigen::MatrixX2d>();
  if (d.contains("qdd")) out.qdd_radps2 = d["qdd"].cast<Eigen::MatrixX2d>();
  out.extra.resize(out.t_s.size(), 0);
  if (d.contains("extra")) {
    const py::dict extra = d["extra"].cast<py::dict>();
    out.extra.resize(out.t_s.size(), static_cast<Eigen::Index>(extra.size()));
    Eigen::Index k = 0;
    for (const auto& [name, col] : extra) {
      out.extra_names.push_back(name.cast<std::string>());
      out.extra.col(k++) = col.cast<Eigen::VectorXd>();
    }
  }
  if (out.q_rad.rows() != out.t_s.size() || out.tau_Nm.rows() != out.t_s.size()) {
    throw std::invalid_argument("dataset: t, q and tau must have the same number of rows");
  }
  return out;
}

py::object optional(const std::optional<double>& v) { return v ? py::cast(*v) : py::none(); }

}  // namespace

PYBIND11_MODULE(exoid, m) {
  m.doc() = "exoid: dynamic parameter identification of a 2-link leg (X = [Mxt, Myt, Jt, fc1, fv1, Mxs, Mys, Js, "
            "fc2, fv2], SI units). The identification library of the exoid harness, numpy in and out.";
  m.attr("__version__") = "0.1.0";

  m.def("param_names", [] {
        std::vector<std::string> n;
        for (int i = 0; i < kNumParams; ++i) n.emplace_back(paramName(i));
        return n;
      },
      "The 10 parameter names in X's order.");

  m.def("read_dataset",
        [](const std::string& path, const std::map<std::string, std::string>& columns, const std::string& time_unit,
           const std::string& angle_unit, const std::pair<double, double>& torque_sign, bool strict_sampling,
           double max_gap_s) {
          return datasetDict(readDatasetCsv(path, readOptions(columns, time_unit, angle_unit, torque_sign, strict_sampling, max_gap_s)));
        },
        py::arg("path"), py::arg("columns") = std::map<std::string, std::string>{}, py::arg("time_unit") = "s",
        py::arg("angle_unit") = "rad", py::arg("torque_sign") = std::make_pair(1.0, 1.0), py::arg("strict_sampling") = false,
        py::arg("max_gap_s") = 0.0,
        "Read a dataset CSV (as `exoid identify` does): a dict with t (N), q, tau (N x 2: hip, knee), optional qd, qdd, "
        "extra columns, comments and the sampling report. columns maps exoid names to the log's (e.g. "
        "{'t': 'time', 'q_hip': 'pos_meas1'}); jittered timestamps are resampled unless strict_sampling. Errors name "
        "file:line:column.");
  m.def("parse_dataset",
        [](const std::string& text, const std::string& source, const std::map<std::string, std::string>& columns,
           const std::string& time_unit, const std::string& angle_unit, const std::pair<double, double>& torque_sign,
           bool strict_sampling, double max_gap_s) {
          return datasetDict(parseDatasetText(text, source, readOptions(columns, time_unit, angle_unit, torque_sign, strict_sampling, max_gap_s)));
        },
        py::arg("text"), py::arg("source") = "<text>", py::arg("columns") = std::map<std::string, std::string>{},
        py::arg("time_unit") = "s", py::arg("angle_unit") = "rad", py::arg("torque_sign") = std::make_pair(1.0, 1.0),
        py::arg("strict_sampling") = false, py::arg("max_gap_s") = 0.0,
        "read_dataset from a string (e.g. a gzip file's decompressed text); source names it in errors.");

  m.def("regressor",
        [](const Eigen::MatrixX2d& q, const Eigen::MatrixX2d& qd, const Eigen::MatrixX2d& qdd, double thigh_length_m,
           double gravity_mps2) {
          if (qd.rows() != q.rows() || qdd.rows() != q.rows()) throw std::invalid_argument("regressor: q, qd, qdd need the same rows");
          const LegConstants c{thigh_length_m, gravity_mps2};
          c.validate();
          Eigen::MatrixXd hip(q.rows(), kNumParams), knee(q.rows(), kNumParams);
          RegressorRow h, k;
          for (Eigen::Index i = 0; i < q.rows(); ++i) {
            regressorRows(c, q.row(i).transpose(), qd.row(i).transpose(), qdd.row(i).transpose(), h, k);
            hip.row(i) = h;
            knee.row(i) = k;
          }
          return py::make_tuple(hip, knee);
        },
        py::arg("q"), py::arg("qd"), py::arg("qdd"), py::arg("thigh_length_m"), py::arg("gravity_mps2") = 9.81,
        "The corrected regressor: (hip rows, knee rows), each N x 10, so that tau_hip = hip @ X, tau_knee = knee @ X. "
        "q, qd, qdd: N x 2 (hip, knee) in rad, rad/s, rad/s^2.");

  m.def("process_record",
        [](const py::dict& dataset, double thigh_length_m, double gravity_mps2, const std::string& processing, double cutoff_hz,
           int filter_order, int decimation, const std::string& base_terms) {
          SignalOptions o;
          o.processing = processing == "paper" ? Processing::kPaper : processing == "parallel" ? Processing::kParallel
                             : throw std::invalid_argument("processing must be 'parallel' or 'paper', got '" + processing + "'");
          if (o.processing == Processing::kParallel) o.differentiation = Differentiation::kCentral4;
          o.cutoff_hz = cutoff_hz;
          o.filter_order = filter_order;
          o.decimation = decimation;
          o.base_terms = base_terms == "auto" ? BaseTerms::kAuto : base_terms == "on" ? BaseTerms::kOn : base_terms == "off"
                             ? BaseTerms::kOff : throw std::invalid_argument("base_terms must be auto, on or off");
          const LegConstants c{thigh_length_m, gravity_mps2};
          c.validate();
          const ProcessedRecord r = processRecord(datasetFrom(dataset), c, o);
          return py::dict(py::arg("hip") = r.hip, py::arg("knee") = r.knee, py::arg("tau") = Eigen::MatrixXd(r.tau_Nm),
                          py::arg("t") = r.states.t_s);
        },
        py::arg("dataset"), py::arg("thigh_length_m"), py::arg("gravity_mps2") = 9.81, py::arg("processing") = "parallel",
        py::arg("cutoff_hz") = 10.0, py::arg("filter_order") = 2, py::arg("decimation") = 0, py::arg("base_terms") = "auto",
        "A dataset (dict as read_dataset returns) to the rows a method fits, as `exoid identify` processes it: "
        "'parallel' (default: regressor from the states, the same zero-phase filter on torque and every column, "
        "decimated; exact data give exact parameters) or 'paper'. Returns hip, knee (rows x 10), tau (rows x 2), t.");

  m.def("identify",
        [](const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const std::string& method, std::uint64_t seed, long pso_iterations,
           double wide_box_half_width) {
          MethodOptions o;
          o.rls_pso.pso.seed = seed;
          o.rls_pso.pso.max_iterations = pso_iterations;
          o.wide_box_half_width = wide_box_half_width;
          const Estimate e = estimate(parseMethod(method), H, y, o);
          py::dict out(py::arg("x") = e.x, py::arg("method") = toString(e.method), py::arg("status") = toString(e.summary.status),
                       py::arg("usable") = usable(e.summary.status), py::arg("message") = e.summary.message,
                       py::arg("l1_cost") = e.l1_cost, py::arg("wall_time_s") = e.summary.wall_time_s);
          out["rank"] = e.rank ? py::cast(*e.rank) : py::none();
          out["condition_number"] = optional(e.condition_number);
          out["optimality_gap"] = optional(e.optimality_gap_rel);
          if (e.box) out["box"] = py::make_tuple(e.box->lower, e.box->upper);
          return out;
        },
        py::arg("H"), py::arg("y"), py::arg("method") = "ls", py::arg("seed") = 1, py::arg("pso_iterations") = 10000,
        py::arg("wide_box_half_width") = 50.0,
        "Identify x in y = H x with one method: 'ls', 'rls', 'pso', 'rls-pso' (the paper's), 'lad' (exact L1 "
        "optimum). Returns x, status, usable, message, rank and condition number (LS), the search box (PSO, RLS-PSO, "
        "RLS's fluctuation range) and the optimality gap against the exact L1 optimum (PSO, RLS-PSO).");

  m.def("identifiability",
        [](const Eigen::MatrixXd& H, const Eigen::VectorXd& y, double noise_sigma) {
          const IdentifiabilityReport r = analyzeIdentifiability(H, y, noise_sigma);
          std::vector<long> unid(r.unidentifiable.begin(), r.unidentifiable.end());
          return py::dict(py::arg("rank") = r.rank, py::arg("condition_number") = r.condition_number,
                          py::arg("unidentifiable") = unid, py::arg("crb_std") = r.crb_std, py::arg("crb_rel_std") = r.crb_rel_std,
                          py::arg("collinearity_r2") = r.collinearity_r2);
        },
        py::arg("H"), py::arg("y"), py::arg("noise_sigma"),
        "What y = H x can identify: rank, condition number of the column-scaled H, unidentifiable columns, the "
        "Cramer-Rao std of each parameter for white noise of std noise_sigma (and relative to the LS estimate), each "
        "column's R^2 on the others.");
}
