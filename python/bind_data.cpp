// Datasets, the regressor and signal processing.
#include "bindings.hpp"
#include "convert.hpp"

#include "exoid/ident/signals/signals.hpp"

#include <optional>

namespace exoid::python {

using namespace exoid::ident;

namespace {

CsvReadOptions readOptions(const std::map<std::string, std::string>& columns, const std::string& time_unit,
                           const std::string& angle_unit, const std::vector<double>& torque_sign, bool strict_sampling,
                           double max_gap_s, const std::vector<std::string>& joints) {
  CsvReadOptions o;
  o.joints = joints;
  for (const auto& [ours, theirs] : columns) o.format.columns.emplace_back(ours, theirs);
  o.format.time_scale_s = parseTimeUnit(time_unit);
  o.format.angle_scale_rad = parseAngleUnit(angle_unit);
  o.format.torque_sign = torque_sign;
  o.sampling = strict_sampling ? SamplingMode::kStrict : SamplingMode::kResample;
  o.max_gap_s = max_gap_s;
  return o;
}

}  // namespace

void bindData(py::module_& m) {
  m.def("param_names", [] {
        std::vector<std::string> n;
        for (int i = 0; i < kNumParams; ++i) n.emplace_back(paramName(i));
        return n;
      },
      "The 10 parameter names in X's order.");

  m.def("read_dataset",
        [](const std::string& path, const std::map<std::string, std::string>& columns, const std::string& time_unit,
           const std::string& angle_unit, const std::vector<double>& torque_sign, bool strict_sampling,
           double max_gap_s, const std::vector<std::string>& joints) {
          return datasetDict(readDatasetCsv(path, readOptions(columns, time_unit, angle_unit, torque_sign, strict_sampling, max_gap_s, joints)));
        },
        py::arg("path"), py::arg("columns") = std::map<std::string, std::string>{}, py::arg("time_unit") = "s",
        py::arg("angle_unit") = "rad", py::arg("torque_sign") = std::vector<double>{}, py::arg("strict_sampling") = false,
        py::arg("max_gap_s") = 0.0, py::arg("joints") = std::vector<std::string>{"hip", "knee"},
        "Read a dataset CSV (as `exoid identify` does): a dict with joints, t (N), q, tau (N x joints: the APAL leg's hip, "
        "knee unless joints names a model's, e.g. load_chain('leg3')['joints']), optional qd, qdd, "
        "extra columns, comments (metadata lines) and the sampling report. columns maps exoid names to the log's "
        "(e.g. {'t': 'time', 'q_hip': 'pos_meas1'}); time_unit s|ms|us|ns, angle_unit rad|deg, torque_sign (one per "
        "joint, default all +1) multiplies the torques; jittered timestamps are resampled unless strict_sampling; max_gap_s=0 means a "
        "tenth of the default filter's period. Errors name file:line:column.");
  m.def("parse_dataset",
        [](const std::string& text, const std::string& source, const std::map<std::string, std::string>& columns,
           const std::string& time_unit, const std::string& angle_unit, const std::vector<double>& torque_sign,
           bool strict_sampling, double max_gap_s, const std::vector<std::string>& joints) {
          return datasetDict(
              parseDatasetText(text, source, readOptions(columns, time_unit, angle_unit, torque_sign, strict_sampling, max_gap_s, joints)));
        },
        py::arg("text"), py::arg("source") = "<text>", py::arg("columns") = std::map<std::string, std::string>{},
        py::arg("time_unit") = "s", py::arg("angle_unit") = "rad", py::arg("torque_sign") = std::vector<double>{},
        py::arg("strict_sampling") = false, py::arg("max_gap_s") = 0.0, py::arg("joints") = std::vector<std::string>{"hip", "knee"},
        "read_dataset from a string (e.g. a gzip file's decompressed text); source names it in errors.");

  m.def("regressor",
        [](const Eigen::MatrixX2d& q, const Eigen::MatrixX2d& qd, const Eigen::MatrixX2d& qdd, double thigh_length_m,
           double gravity_mps2) {
          if (qd.rows() != q.rows() || qdd.rows() != q.rows()) throw std::invalid_argument("regressor: q, qd, qdd need the same rows");
          const LegConstants c = legConstants(thigh_length_m, gravity_mps2);
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
        [](const py::dict& dataset, double thigh_length_m, double gravity_mps2, const std::string& processing, std::optional<double> cutoff_hz,
           int filter_order, int decimation, const std::string& base_terms) {
          const RecordRows r = processRecord(datasetFrom(dataset), twoLinkLeg(legConstants(thigh_length_m, gravity_mps2)),
                                             signalOptions(processing, cutoff_hz, filter_order, decimation, base_terms));
          Eigen::MatrixXd tau(r.samples(), 2);
          tau << r.jointY(0), r.jointY(1);
          return py::dict(py::arg("hip") = r.jointW(0), py::arg("knee") = r.jointW(1), py::arg("tau") = tau, py::arg("t") = r.states.t_s);
        },
        py::arg("dataset"), py::arg("thigh_length_m"), py::arg("gravity_mps2") = 9.81, py::arg("processing") = "parallel",
        py::arg("cutoff_hz") = py::none(), py::arg("filter_order") = 2, py::arg("decimation") = 0, py::arg("base_terms") = "auto",
        (std::string("A dataset (dict as read_dataset returns) to the rows a method fits. Returns hip, knee (rows x 10), "
                     "tau (rows x 2), t. ") + kSignalOptionsDoc).c_str());

  m.def("lowpass",
        [](const Eigen::MatrixXd& x, double cutoff_hz, double sample_rate_hz, int order) {
          return filtfilt(butterworthLowpass(order, cutoff_hz, sample_rate_hz), x);
        },
        py::arg("x"), py::arg("cutoff_hz"), py::arg("sample_rate_hz"), py::arg("order") = 2,
        "Zero-phase Butterworth low-pass of each column of x (forward-backward, odd extension at the ends): "
        "the filter process_record applies.");
  m.def("differentiate",
        [](const Eigen::MatrixXd& x, double dt_s, const std::string& method) {
          const Differentiation d = method == "forward"    ? Differentiation::kForward
                                    : method == "central"  ? Differentiation::kCentral
                                    : method == "central4" ? Differentiation::kCentral4
                                                           : throw std::invalid_argument(
                                                                 "differentiate: method must be forward, central or central4, got '" + method + "'");
          return differentiate(x, dt_s, d);
        },
        py::arg("x"), py::arg("dt_s"), py::arg("method") = "central4",
        "Time derivative of each column of x sampled every dt_s: 'forward' (the paper's), 'central' or 'central4' "
        "(five-point, the parallel processing's).");
}

}  // namespace exoid::python
