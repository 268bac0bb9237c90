// Identification methods, the segmental strategy, IDIM-IV, identifiability and consistent LS.
#include "bindings.hpp"
#include "convert.hpp"

#include "exoid/experiments/protocol/controller_io.hpp"
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/leg/consistency.hpp"
#include "exoid/ident/design/identifiability.hpp"
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/ident/estimators/segmental.hpp"
#include "exoid/ident/estimators/segmental_errors.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <limits>
#include <optional>

namespace exoid::python {

using namespace exoid::ident;

namespace {

// The APAL leg's two stages: the knee's (Mxs .. fv2) and the hip's (Mxt .. fv1).
py::dict segmentalDict(const SegmentalResult& r) {
  const Estimate& knee = r.stages.at(0).estimate;
  const Estimate& hip = r.stages.at(1).estimate;
  std::vector<std::string> warnings;  // both stages', named
  for (const std::string& w : estimateWarnings(knee)) warnings.push_back("knee stage: " + w);
  for (const std::string& w : estimateWarnings(hip)) warnings.push_back("hip stage: " + w);
  return py::dict(py::arg("x") = Eigen::VectorXd(r.theta.head<kNumParams>()), py::arg("knee") = estimateDict(knee),
                  py::arg("hip") = estimateDict(hip), py::arg("warnings") = warnings);
}

// The knee record's processing: its band from its knee equation (its hip is locked).
SignalOptions kneeRecordSignals(const Dataset& d, const Robot& robot, const SignalOptions& s) {
  BandRule rule;
  rule.first_moving_joint = 1;
  return resolveSignalOptions(d, robot, s, rule);
}

std::string sourceOf(const py::dict& d, const char* role) {
  return d.contains("source") ? d["source"].cast<std::string>() : std::string("<") + role + " record>";
}

}  // namespace

void bindMethods(py::module_& m) {
  m.def("identify",
        [](const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const std::string& method, const py::kwargs& kw) {
          return estimateDict(estimate(parseMethod(method), H, y, methodOptions(kw, "identify")));
        },
        py::arg("H"), py::arg("y"), py::arg("method") = "ls",
        (std::string("Identify x in y = H x with one method: 'ls', 'rls', 'pso', 'rls-pso' (the paper's), 'lad' "
                     "(exact L1 optimum). Returns a dict: x, method, status, usable, message, iterations, "
                     "initial_cost, final_cost, wall_time_s, l1_cost; rank, condition_number, unidentifiable (LS); "
                     "box (PSO, RLS-PSO; RLS's fluctuation range); optimum_l1_cost, optimality_gap and their "
                     "in-box versions (PSO, RLS-PSO); cost_history (PSO); warnings (what the command line would say: "
                     "not usable, unidentified columns, condition number above 100). ") + kMethodOptionsDoc).c_str());

  m.def("identify_segmental",
        [](const py::dict& knee_record, const py::dict& both_record, double thigh_length_m, const std::string& method,
           double gravity_mps2, const std::string& processing, std::optional<double> cutoff_hz, int filter_order, int decimation,
           const std::string& base_terms, const py::kwargs& kw) {
          const Robot robot = twoLinkLeg(legConstants(thigh_length_m, gravity_mps2));
          const SignalOptions s = signalOptions(processing, cutoff_hz, filter_order, decimation, base_terms);
          const MethodOptions o = methodOptions(kw, "identify_segmental");
          // Each record processed in its own band (the knee record's from its knee equation: its hip is locked).
          const Dataset kd = datasetFrom(knee_record), bd = datasetFrom(both_record);
          const std::vector<SegmentalStage> stages = {{1, processRecord(kd, robot, kneeRecordSignals(kd, robot, s))}, {0, processRecord(bd, robot, s)}};
          const SegmentalResult r = identifySegmental(robot, stages, parseMethod(method), o);
          py::dict out = segmentalDict(r);
          if (method == "ls" && r.usable()) {
            // What `exoid identify --knee-data --both-data` reports: identify's rule stage by stage.
            const ReportedErrors e = segmentalReportedErrors(robot, stages, r);
            out["std_error"] = e.reported;
            out["std_error_newey_west"] = e.newey_west;
            out["std_error_jackknife"] = e.jackknife;
          }
          return out;
        },
        py::arg("knee_record"), py::arg("both_record"), py::arg("thigh_length_m"), py::arg("method") = "rls-pso",
        py::arg("gravity_mps2") = 9.81, py::arg("processing") = "parallel", py::arg("cutoff_hz") = py::none(),
        py::arg("filter_order") = 2, py::arg("decimation") = 0, py::arg("base_terms") = "auto",
        (std::string("The paper's segmental strategy: the knee parameters (Mxs, Mys, Js, fc2, fv2) from a record with the "
                     "hip fixed, then the hip parameters from a record where both joints move, its hip torque minus "
                     "the knee part. Records are dataset dicts (read_dataset). Returns x (10) and the knee and hip "
                     "stages' estimates (dicts as identify returns) and warnings (both stages', named); method='ls' also std_error (10: "
                     "the larger of Newey-West and the block jackknife, stage by stage with what the knee stage carries into the "
                     "hip's, as `exoid identify` reports), std_error_newey_west, std_error_jackknife. ") + kSignalOptionsDoc + " " + kMethodOptionsDoc).c_str());

  m.def("identify_chain_idim_iv",
        [](const ChainModel& model, const py::dict& record, const std::string& controller, std::optional<double> cutoff_hz, int filter_order,
           int decimation, double step_tolerance, int max_iterations) {
          const Dataset d = datasetFrom(record);
          const SignalOptions s = signalOptions("parallel", cutoff_hz, filter_order, decimation, "auto");
          IvOptions iv;
          iv.step_tolerance = step_tolerance;
          iv.max_iterations = max_iterations;
          iv.validate();
          // As `exoid identify --model ... --method idim-iv`: the record's rows in its band, its
          // reference and controller, the instruments processed alike.
          const Robot robot = chainRobot(model);
          std::optional<BandChoice> band;
          const RecordRows rows = processRecord(d, robot, s, {}, &band);
          const SignalOptions used = band ? withBand(s, *band) : resolveSignalOptions(d, robot, s);
          const ClosedLoopRecord r = experiments::closedLoopRecord(d, sourceOf(record, "chain"), rows, used, controller);
          const BaseParameters& base = robot.basis;
          const Estimate e = identifyIdimIv(robot, {r}, iv);
          return py::dict(py::arg("x") = e.x, py::arg("names") = base.names, py::arg("all") = estimateDict(e));
        },
        py::arg("model"), py::arg("record"), py::arg("controller") = "", py::arg("cutoff_hz") = py::none(), py::arg("filter_order") = 2,
        py::arg("decimation") = 0, py::arg("step_tolerance") = 0.1, py::arg("max_iterations") = 10,
        "IDIM-IV on any serial chain (model: a ChainModel, e.g. load_chain('leg3')['model']): the base parameters "
        "(x, in base_parameters()['names'] order, also names) from one record (a dataset dict with the model's "
        "joints), instruments from closed-loop simulations of the chain identified at the previous iteration, "
        "processed as the record's rows (parallel processing, the band chosen from the record unless cutoff_hz). "
        "The record needs its reference (q_<joint>_ref columns) and its controller: the record's metadata "
        "(controller_kp_Nm_per_rad, ..., as `exoid simulate --model` writes them) or controller, a JSON file "
        "{\"kp\": [one per joint], \"kd\": [..], \"derivative\": \"measured_velocity\", \"feedforward\": \"model\", "
        "\"actuator_bandwidth_hz\": ..}. "
        "all: the estimate as identify returns it.");

  m.def("identify_idim_iv",
        [](const py::dict& both_record, double thigh_length_m, const std::optional<py::dict>& knee_record,
           const std::string& controller, double gravity_mps2, std::optional<double> cutoff_hz, int filter_order, int decimation,
           const std::string& base_terms, double step_tolerance, int max_iterations, bool knee_armature) {
          const LegConstants c = legConstants(thigh_length_m, gravity_mps2);
          const Robot robot = twoLinkLeg(c, knee_armature && !knee_record);
          const SignalOptions s = signalOptions("parallel", cutoff_hz, filter_order, decimation, base_terms);
          IvOptions iv;
          iv.step_tolerance = step_tolerance;
          iv.max_iterations = max_iterations;
          iv.validate();
          auto closedLoop = [&](const py::dict& record, const char* role, bool knee_only) {
            const Dataset d = datasetFrom(record);
            // The band chosen from this record, by the leg's own model (X).
            const SignalOptions rs = knee_only ? kneeRecordSignals(d, twoLinkLeg(c), s) : resolveSignalOptions(d, twoLinkLeg(c), s);
            return experiments::closedLoopRecord(d, sourceOf(record, role), processRecord(d, robot, rs), rs, controller, knee_only ? 1 : 0);
          };
          const ClosedLoopRecord both = closedLoop(both_record, "both", false);
          if (!knee_record) {
            const Estimate e = identifyIdimIv(robot, {both}, iv);
            return py::dict(py::arg("x") = e.x, py::arg("all") = estimateDict(e));
          }
          if (knee_armature) throw std::invalid_argument("identify_idim_iv: knee_armature needs the single-record form (no knee_record)");
          return segmentalDict(identifySegmentalIdimIv(robot, {{1, closedLoop(*knee_record, "knee", true)}, {0, both}}, iv));
        },
        py::arg("both_record"), py::arg("thigh_length_m"), py::arg("knee_record") = py::none(), py::arg("controller") = "",
        py::arg("gravity_mps2") = 9.81, py::arg("cutoff_hz") = py::none(), py::arg("filter_order") = 2, py::arg("decimation") = 0,
        py::arg("base_terms") = "auto", py::arg("step_tolerance") = 0.1, py::arg("max_iterations") = 10,
        py::arg("knee_armature") = false,
        "IDIM-IV (Janot et al. 2014): instrumental variables from closed-loop simulations of the model identified at the "
        "previous iteration, on the parallel processing. With knee_record, the segmental strategy (returns x, knee, "
        "hip); without, all 10 parameters from both_record (returns x, all; with knee_armature, 11: Ia2 last). Each record needs its reference "
        "(extra columns q_hip_ref, q_knee_ref) and its controller: from the record's metadata (comments, as `exoid "
        "simulate` writes them) or controller, a JSON file {\"kp\": [hip, knee], \"kd\": [..], ...}. A record dict's "
        "optional 'source' names it in errors.");

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

  m.def("consistent_least_squares",
        [](const Eigen::MatrixXd& H, const Eigen::VectorXd& y, double thigh_length_m, std::optional<Eigen::VectorXd> x_ls,
           std::optional<Eigen::MatrixXd> covariance, double significance_sigmas) {
          const Eigen::VectorXd x = x_ls ? *x_ls : solveLeastSquares(H, y).x;
          const Eigen::MatrixXd cov = covariance ? *covariance : Eigen::MatrixXd::Constant(H.cols(), H.cols(), std::numeric_limits<double>::infinity());
          ConsistencyOptions o;
          o.significance_sigmas = significance_sigmas;
          const ConsistentEstimate e = solveConsistentLeastSquares(H, y, thigh_length_m, x, cov, o);
          py::list checks;
          for (const ConsistencyCheck& k : e.checks) {
            checks.append(py::dict(py::arg("condition") = k.name, py::arg("value") = k.value, py::arg("standard_error") = k.standard_error,
                                   py::arg("violated") = k.violated(), py::arg("significant") = k.significant(significance_sigmas),
                                   py::arg("active") = k.active));
          }
          return py::dict(py::arg("x") = e.x, py::arg("constrained") = e.constrained, py::arg("checks") = checks,
                          py::arg("significant_violations") = e.significantViolations(significance_sigmas));
        },
        py::arg("H"), py::arg("y"), py::arg("thigh_length_m"), py::arg("x_ls") = py::none(), py::arg("covariance") = py::none(),
        py::arg("significance_sigmas") = 2.0,
        "The physically consistent least-squares estimate of X (10 columns, or 11 with the knee armature Ia2 last): "
        "min ||y - H x|| subject to friction >= 0, Js >= 0, Jt >= Js, (Jt - Js) Js >= Lt^2 (Mxs^2 + Mys^2) (and Ia2 >= 0), "
        "by a log-barrier interior point; x_ls (default: the LS estimate) is returned unchanged when it satisfies them. "
        "covariance (of x_ls) gives each condition's standard error; checks lists every condition at x_ls.");
}

}  // namespace exoid::python
