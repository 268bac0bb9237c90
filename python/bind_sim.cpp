// simulate: the MuJoCo rig from Python, with exactly the options of `exoid simulate`.
#include "bindings.hpp"
#include "convert.hpp"

#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/commands/simulate_request.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/sim/model.hpp"
#include "exoid/sim/serial_chain.hpp"
#include "exoid/sim/simulate.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <map>
#include <variant>

namespace exoid::python {

namespace {

// A keyword argument as the command line's words: noise_tau=0.5 -> --noise-tau 0.5,
// lock_hip=True -> --lock-hip, feedforward=False -> --no-feedforward (a flag without a --no- form:
// nothing), fourier_hip=[..] -> one word each, lock={'j': 0.1} -> --lock j=0.1.
void appendArgument(const CLI::App& app, std::vector<std::string>& args, const std::string& key, const py::handle& value) {
  std::string flag = key;
  std::replace(flag.begin(), flag.end(), '_', '-');
  if (py::isinstance<py::bool_>(value)) {
    if (value.cast<bool>()) {
      args.push_back("--" + flag);
    } else if (app.get_option_no_throw("--no-" + flag) != nullptr || app.get_option_no_throw("--" + flag) == nullptr) {
      args.push_back("--no-" + flag);  // an unknown keyword is named as given, below
    }
  } else if (py::isinstance<py::dict>(value)) {
    args.push_back("--" + flag);
    for (const auto& [k, v] : value.cast<py::dict>()) args.push_back(py::str(k).cast<std::string>() + "=" + py::str(v).cast<std::string>());
  } else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    args.push_back("--" + flag);
    for (const py::handle& item : value) args.push_back(py::str(item).cast<std::string>());
  } else {
    args.push_back("--" + flag);
    args.push_back(py::str(value).cast<std::string>());
  }
}

py::object jsonToPython(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

}  // namespace

void bindSim(py::module_& m) {
  m.def("simulate",
        [](const py::kwargs& kw) {
          CLI::App app{"exoid.simulate"};
          experiments::SimulateRequest request;
          experiments::addSimulateOptions(app, request);
          std::vector<std::string> args;
          for (const auto& [key, value] : kw) {
            const std::size_t first = args.size();
            appendArgument(app, args, key.cast<std::string>(), value);
            if (args.size() > first && app.get_option_no_throw(args[first]) == nullptr) {
              throw py::type_error("simulate() got an unexpected keyword argument '" + key.cast<std::string>() +
                                   "' (keywords are `exoid simulate`'s options with '_' for '-', see its --help)");
            }
          }
          std::reverse(args.begin(), args.end());  // CLI11 parses a vector from its back
          std::variant<sim::SimConfig, sim::ChainSimConfig> rig;
          try {
            app.parse(args);
            rig = experiments::simulationOf(request);
          } catch (const CLI::Error& e) {
            throw std::invalid_argument(std::string("simulate: ") + e.what() +
                                        " (keywords are `exoid simulate`'s options with '_' for '-')");
          }
          if (const auto* chain = std::get_if<sim::ChainSimConfig>(&rig)) {
            // Another robot: the serial-chain simulator (as `exoid simulate --model` runs it).
            const sim::ChainSimResult r = sim::simulateChain(*chain);
            const nlohmann::json side = experiments::chainSimulationSidecar(r);
            return py::dict(py::arg("dataset") = datasetDict(experiments::chainDataset(r)), py::arg("truth") = jsonToPython(side.at("truth")),
                            py::arg("sidecar") = jsonToPython(side));
          }
          const sim::SimResult r = sim::simulate(std::get<sim::SimConfig>(rig));
          const ident::Dataset d = experiments::toDataset(r);
          py::dict truth(py::arg("x") = Eigen::VectorXd(experiments::toParamVector(r.truth.x)),
                         py::arg("thigh_length_m") = r.truth.thigh_length_m, py::arg("gravity_mps2") = r.truth.gravity_mps2,
                         py::arg("knee_armature_kgm2") = r.truth.knee_armature_kgm2, py::arg("source") = r.truth.source);
          return py::dict(py::arg("dataset") = datasetDict(d), py::arg("truth") = truth,
                          py::arg("sidecar") = jsonToPython(experiments::simulationSidecar(r, d)));
        },
        "Simulate the MuJoCo rig as `exoid simulate` does and return a dict: dataset (as read_dataset returns, "
        "with the exact columns and the controller's metadata, so identify_idim_iv can use it), truth (x of the "
        "rigid links, thigh_length_m, gravity_mps2, knee_armature_kgm2, source) and sidecar (every setting, the "
        "seed, versions, statistics). Keywords are the command's options with '_' for '-': trajectory=3, "
        "duration=10, noise_q_deg, noise_tau, vibration, seed, lock_hip=True, feedforward=False, excitation='d.json', "
        "fourier_hip=[...], model='leg.xml', ... (see `exoid simulate --help`); defaults are the command's "
        "(no noise, welded pedestal). model='leg3' (or any model other than the APAL leg) runs the serial-chain "
        "simulator: dataset has the model's joints, truth its standard_parameters and base_parameters; a URDF's "
        "tree takes base=, tip=, lock=['JOINT=VALUE'] as the command's --base, --tip, --lock. An option that does "
        "not apply to the robot raises ValueError naming it, as the command refuses it.");
  m.def("load_chain",
        [](const std::string& model, const std::string& base, const std::string& tip, const std::map<std::string, double>& lock) {
          const std::string path = sim::modelPathFor(model);
          const sim::SerialChain chain = sim::serialChainFromFile(path, core::ChainSelection{base, tip, lock});
          const ident::ChainModel cm = experiments::chainModel(chain);
          py::dict limits;
          for (const sim::ChainLinkBody& l : chain.links) {
            limits[py::str(l.joint)] = py::dict(py::arg("q_min_rad") = l.q_min_rad, py::arg("q_max_rad") = l.q_max_rad,
                                                py::arg("qd_max_radps") = l.qd_max_radps, py::arg("tau_max_Nm") = l.tau_max_Nm);
          }
          return py::dict(py::arg("model") = cm, py::arg("phi") = experiments::standardParameters(chain), py::arg("joints") = cm.jointNames(),
                          py::arg("limits") = limits, py::arg("name") = chain.name, py::arg("path") = path);
        },
        py::arg("model"), py::arg("base") = "", py::arg("tip") = "", py::arg("lock") = std::map<std::string, double>{},
        "A robot model as a serial chain: 'apal', 'leg3' or an MJCF/URDF file; base, tip and lock (joint -> value) pick "
        "a chain out of a tree as the commands' --base, --tip and --lock do. Returns model (a ChainModel: regressor, "
        "base_parameters, consistent_fit), phi (the file's standard parameters, in model.parameter_names' order), joints, "
        "limits per joint (range, speed, torque; inf where the file gives none), name, path. Refuses what is not a serial "
        "chain of revolute joints, naming what it found.");
  m.attr("has_simulator") = true;
}

}  // namespace exoid::python
