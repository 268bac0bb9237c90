#include "convert.hpp"

#include "exoid/core/format.hpp"
#include "exoid/experiments/protocol/options.hpp"

#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>
#include <stdexcept>

namespace exoid::python {

using namespace exoid::ident;

py::dict datasetDict(const Dataset& d) {
  py::dict out;
  out["joints"] = d.joints;
  out["t"] = d.t_s;
  out["q"] = Eigen::MatrixXd(d.q_rad);
  out["tau"] = Eigen::MatrixXd(d.tau_Nm);
  if (d.qd_radps) out["qd"] = Eigen::MatrixXd(*d.qd_radps);
  if (d.qdd_radps2) out["qdd"] = Eigen::MatrixXd(*d.qdd_radps2);
  py::dict extra;
  for (std::size_t k = 0; k < d.extra_names.size(); ++k) {
    extra[py::str(d.extra_names[k])] = Eigen::VectorXd(d.extra.col(static_cast<Eigen::Index>(k)));
  }
  out["extra"] = extra;
  out["comments"] = d.comments;
  const SamplingReport& s = d.sampling;
  out["sampling"] = py::dict(py::arg("rows_read") = s.rows_read, py::arg("median_dt_s") = s.median_dt_s,
                             py::arg("min_dt_s") = s.min_dt_s, py::arg("max_dt_s") = s.max_dt_s,
                             py::arg("intervals_off") = s.intervals_off, py::arg("resampled") = s.resampled);
  return out;
}

Dataset datasetFrom(const py::dict& d) {
  for (const char* key : {"t", "q", "tau"}) {
    if (!d.contains(key)) throw std::invalid_argument(std::string("dataset: missing key '") + key + "' (need t, q, tau)");
  }
  Dataset out;
  if (d.contains("joints")) out.joints = d["joints"].cast<std::vector<std::string>>();
  out.t_s = d["t"].cast<Eigen::VectorXd>();
  out.q_rad = d["q"].cast<Eigen::MatrixXd>();
  out.tau_Nm = d["tau"].cast<Eigen::MatrixXd>();
  if (d.contains("qd")) out.qd_radps = d["qd"].cast<Eigen::MatrixXd>();
  if (d.contains("qdd")) out.qdd_radps2 = d["qdd"].cast<Eigen::MatrixXd>();
  const auto dof = static_cast<Eigen::Index>(out.joints.size());
  for (const auto& [name, m] : {std::pair<const char*, const Eigen::MatrixXd*>{"q", &out.q_rad}, {"tau", &out.tau_Nm}}) {
    if (m->cols() != dof) {
      throw std::invalid_argument(std::string("dataset: '") + name + "' has " + std::to_string(m->cols()) + " columns for " + std::to_string(dof) +
                                  " joints (its 'joints' key; the APAL leg's hip, knee when absent)");
    }
  }
  if (d.contains("comments")) out.comments = d["comments"].cast<std::vector<std::string>>();
  out.extra.resize(out.t_s.size(), 0);
  if (d.contains("extra")) {
    const py::dict extra = d["extra"].cast<py::dict>();
    out.extra.resize(out.t_s.size(), static_cast<Eigen::Index>(extra.size()));
    Eigen::Index k = 0;
    for (const auto& [name, col] : extra) {
      const Eigen::VectorXd v = col.cast<Eigen::VectorXd>();
      if (v.size() != out.t_s.size()) {
        throw std::invalid_argument("dataset: extra column '" + name.cast<std::string>() + "' has " +
                                    core::toText(v.size()) + " rows, t has " + core::toText(out.t_s.size()));
      }
      out.extra_names.push_back(name.cast<std::string>());
      out.extra.col(k++) = v;
    }
  }
  auto check = [&](const char* what, Eigen::Index rows) {
    if (rows != out.t_s.size()) {
      throw std::invalid_argument(std::string("dataset: ") + what + " has " + core::toText(rows) + " rows, t has " +
                                  core::toText(out.t_s.size()));
    }
  };
  check("q", out.q_rad.rows());
  check("tau", out.tau_Nm.rows());
  if (out.qd_radps) check("qd", out.qd_radps->rows());
  if (out.qdd_radps2) check("qdd", out.qdd_radps2->rows());
  return out;
}

py::object optional(const std::optional<double>& v) { return v ? py::cast(*v) : py::none(); }

std::vector<std::string> estimateWarnings(const Estimate& e) {
  std::vector<std::string> w;
  if (!usable(e.summary.status)) w.push_back("not usable: " + e.summary.message);
  if (!e.unidentifiable.empty()) {
    std::string cols;
    for (Eigen::Index c : e.unidentifiable) cols += (cols.empty() ? "" : ", ") + std::to_string(c);
    w.push_back("columns " + cols + " are not identified by these rows (rank " + (e.rank ? std::to_string(*e.rank) : std::string("?")) +
                " of " + std::to_string(e.x.size()) + ")");
  }
  // The command line's threshold (identify's "excitation" line): above it, what the model leaves
  // out is amplified in the estimate up to that factor.
  if (e.condition_number && *e.condition_number > 100.0) {
    std::ostringstream s;
    s.precision(4);
    s << "condition number " << *e.condition_number
      << " (columns scaled) > 100: errors the model leaves out are amplified up to that much in the estimate; "
         "exoid.identifiability (or exoid identifiability --data) says which motion would separate the parameters";
    w.push_back(s.str());
  }
  return w;
}

py::dict estimateDict(const Estimate& e) {
  const Summary& s = e.summary;
  py::dict out(py::arg("x") = e.x, py::arg("method") = toString(e.method), py::arg("status") = toString(s.status),
               py::arg("usable") = usable(s.status), py::arg("message") = s.message, py::arg("iterations") = s.iterations,
               py::arg("initial_cost") = s.initial_cost, py::arg("final_cost") = s.final_cost,
               py::arg("wall_time_s") = s.wall_time_s, py::arg("l1_cost") = e.l1_cost);
  out["rank"] = e.rank ? py::cast(*e.rank) : py::none();
  out["condition_number"] = optional(e.condition_number);
  out["unidentifiable"] = std::vector<long>(e.unidentifiable.begin(), e.unidentifiable.end());
  out["box"] = e.box ? py::object(py::make_tuple(e.box->lower, e.box->upper)) : py::none();
  out["optimum_l1_cost"] = optional(e.optimum_l1_cost);
  out["optimality_gap"] = optional(e.optimality_gap_rel);
  out["optimum_box_l1_cost"] = optional(e.optimum_box_l1_cost);
  out["optimality_gap_box"] = optional(e.optimality_gap_box_rel);
  out["cost_history"] = e.cost_history;
  out["warnings"] = estimateWarnings(e);  // what the command line would print beside the estimate
  return out;
}

namespace {

using Setter = std::function<void(MethodOptions&, const py::handle&)>;

template <typename T, typename Field>
Setter set(Field field) {
  return [field](MethodOptions& o, const py::handle& v) { field(o) = v.cast<T>(); };
}

const std::map<std::string, Setter>& methodSetters() {
  static const std::map<std::string, Setter> setters{
      {"seed", set<std::uint64_t>([](MethodOptions& o) -> auto& { return o.rls_pso.pso.seed; })},
      {"pso_iterations", set<long>([](MethodOptions& o) -> auto& { return o.rls_pso.pso.max_iterations; })},
      {"pso_swarm_size", set<int>([](MethodOptions& o) -> auto& { return o.rls_pso.pso.swarm_size; })},
      {"pso_cost_tolerance", set<double>([](MethodOptions& o) -> auto& { return o.rls_pso.pso.cost_tolerance; })},
      {"pso_w_max", set<double>([](MethodOptions& o) -> auto& { return o.rls_pso.pso.w_max; })},
      {"pso_w_min", set<double>([](MethodOptions& o) -> auto& { return o.rls_pso.pso.w_min; })},
      {"pso_c1", set<double>([](MethodOptions& o) -> auto& { return o.rls_pso.pso.c1; })},
      {"pso_c2", set<double>([](MethodOptions& o) -> auto& { return o.rls_pso.pso.c2; })},
      {"pso_velocity_fraction", set<double>([](MethodOptions& o) -> auto& { return o.rls_pso.pso.velocity_fraction; })},
      {"pso_boundary",
       [](MethodOptions& o, const py::handle& v) {
         const std::string b = v.cast<std::string>();
         if (b != "clamp" && b != "reflect") throw std::invalid_argument("pso_boundary must be 'clamp' or 'reflect', got '" + b + "'");
         o.rls_pso.pso.boundary = b == "clamp" ? BoundaryPolicy::kClamp : BoundaryPolicy::kReflect;
       }},
      {"cost",
       [](MethodOptions& o, const py::handle& v) {
         const std::string c = v.cast<std::string>();
         if (c != "L1" && c != "L2") throw std::invalid_argument("cost must be 'L1' or 'L2', got '" + c + "'");
         o.rls_pso.cost = c == "L1" ? CostNorm::kL1 : CostNorm::kL2;
       }},
      {"rls_forgetting", set<double>([](MethodOptions& o) -> auto& { return o.rls_pso.rls.forgetting; })},
      {"rls_initial_covariance", set<double>([](MethodOptions& o) -> auto& { return o.rls_pso.rls.initial_covariance; })},
      {"range_burn_in_fraction", set<double>([](MethodOptions& o) -> auto& { return o.rls_pso.range.burn_in_fraction; })},
      {"range_margin_fraction", set<double>([](MethodOptions& o) -> auto& { return o.rls_pso.range.margin_fraction; })},
      {"range_min_width", set<double>([](MethodOptions& o) -> auto& { return o.rls_pso.range.min_width; })},
      {"ls_rank_tolerance", set<double>([](MethodOptions& o) -> auto& { return o.ls.rank_tolerance; })},
      {"ls_max_condition", set<double>([](MethodOptions& o) -> auto& { return o.ls.max_condition; })},
      {"lad_gap_tolerance", set<double>([](MethodOptions& o) -> auto& { return o.lad.gap_tolerance; })},
      {"lad_max_iterations", set<int>([](MethodOptions& o) -> auto& { return o.lad.max_iterations; })},
      {"wide_box_half_width", set<double>([](MethodOptions& o) -> auto& { return o.wide_box_half_width; })},
      {"report_optimality_gap", set<bool>([](MethodOptions& o) -> auto& { return o.report_optimality_gap; })},
  };
  return setters;
}

}  // namespace

const char* const kMethodOptionsDoc =
    "Method options (keywords, defaults as `exoid identify`): seed=1, pso_iterations=10000 (G), pso_swarm_size=40, "
    "pso_cost_tolerance=1e-2, pso_w_max=0.9, pso_w_min=0.4, pso_c1=2, pso_c2=2, pso_velocity_fraction=0.2, "
    "pso_boundary='clamp'|'reflect', cost='L1'|'L2' (PSO's cost), rls_forgetting=1, rls_initial_covariance=1e6, "
    "range_burn_in_fraction=0.1, range_margin_fraction=0, range_min_width=1e-6 (RLS-PSO's box), "
    "ls_rank_tolerance=1e-8, ls_max_condition=1e5, lad_gap_tolerance=1e-10, lad_max_iterations=100, "
    "wide_box_half_width=50 (the PSO baseline's box; `exoid identify` sizes it from the data unless given), "
    "report_optimality_gap=True.";

MethodOptions methodOptions(const py::kwargs& kw, const char* function) {
  MethodOptions o;
  const auto& setters = methodSetters();
  for (const auto& [key, value] : kw) {
    const std::string name = key.cast<std::string>();
    const auto it = setters.find(name);
    if (it == setters.end()) {
      std::string accepted;
      for (const auto& [n, s] : setters) accepted += (accepted.empty() ? "" : ", ") + n;
      throw py::type_error(std::string(function) + "() got an unexpected keyword argument '" + name +
                           "'; method options are: " + accepted);
    }
    try {
      it->second(o, value);
    } catch (const py::cast_error&) {
      throw py::type_error(std::string(function) + "(): option '" + name + "' has the wrong type (" +
                           py::str(py::type::of(value)).cast<std::string>() + ")");
    }
  }
  o.validate();
  return o;
}

const char* const kSignalOptionsDoc =
    "Processing (as `exoid identify`): processing='parallel' (default: the regressor from the states, the same "
    "zero-phase filter on the torques and every column, decimated; exact data give exact parameters) or 'paper'; "
    "cutoff_hz=None (chosen from each record, as `exoid identify --cutoff-hz auto`; the paper's processing uses 10), "
    "filter_order=2, decimation=0 (automatic), base_terms='auto'|'on'|'off'|'judged'.";

SignalOptions signalOptions(const std::string& processing, std::optional<double> cutoff_hz, int filter_order, int decimation,
                            const std::string& base_terms) {
  SignalOptions o = experiments::defaultIdentifySignals();
  if (processing != "paper" && processing != "parallel") {
    throw std::invalid_argument("processing must be 'parallel' or 'paper', got '" + processing + "'");
  }
  o.processing = processing == "paper" ? Processing::kPaper : Processing::kParallel;
  if (cutoff_hz) {
    o.cutoff_from_data = false;
    o.cutoff_hz = *cutoff_hz;
  }
  o.filter_order = filter_order;
  o.decimation = decimation;
  const auto& choices = experiments::baseTermsChoices();
  if (!choices.count(base_terms)) throw std::invalid_argument("base_terms must be 'auto', 'on', 'off' or 'judged', got '" + base_terms + "'");
  o.base_terms = choices.at(base_terms);
  return o;
}

LegConstants legConstants(double thigh_length_m, double gravity_mps2) {
  const LegConstants c{thigh_length_m, gravity_mps2};
  c.validate();
  return c;
}

}  // namespace exoid::python
