// Robot models: a serial chain of revolute joints and its regressor (ident/model).
#include "bindings.hpp"

#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/newton_euler.hpp"
#include "exoid/ident/signals/processing.hpp"
#include "exoid/ident/model/consistent_fit.hpp"
#include "convert.hpp"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <optional>

namespace exoid::python {

namespace py = pybind11;
using namespace exoid::ident;

namespace {

template <typename T>
T item(const py::dict& d, const char* key, const T& fallback) {
  return d.contains(key) ? d[key].cast<T>() : fallback;
}

ChainJoint jointFrom(const py::dict& d) {
  ChainJoint j;
  if (!d.contains("name") || !d.contains("link")) throw py::value_error("ChainModel: every joint needs 'name' and 'link'");
  j.name = d["name"].cast<std::string>();
  j.link = d["link"].cast<std::string>();
  j.parent_R_joint = item<Eigen::Matrix3d>(d, "rotation", Eigen::Matrix3d::Identity());
  j.parent_p_joint_m = item<Eigen::Vector3d>(d, "origin_m", Eigen::Vector3d::Zero());
  j.axis = item<Eigen::Vector3d>(d, "axis", Eigen::Vector3d::UnitZ());
  j.friction = item<bool>(d, "friction", true);
  j.armature = item<bool>(d, "armature", false);
  return j;
}

}  // namespace

void bindModel(py::module_& m) {
  py::class_<ChainModel>(m, "ChainModel",
                         "A serial chain of revolute joints (URDF frames): joints is a list of dicts with name, link, "
                         "rotation (3x3, the joint frame in the parent link's frame), origin_m (3), axis (3, unit, joint "
                         "frame), friction (bool, default True), armature (bool, default False); gravity_mps2 in the "
                         "base frame.")
      .def(py::init([](const py::list& joints, const Eigen::Vector3d& gravity, const std::string& name) {
             ChainModel model;
             model.name = name;
             model.gravity_mps2 = gravity;
             for (const py::handle& j : joints) model.joints.push_back(jointFrom(j.cast<py::dict>()));
             model.validate();
             return model;
           }),
           py::arg("joints"), py::arg("gravity_mps2") = Eigen::Vector3d(0.0, 0.0, -9.81), py::arg("name") = "chain")
      .def_property_readonly("dof", &ChainModel::dof)
      .def_property_readonly("parameter_names", &ChainModel::standardParameterNames,
                             "Standard parameters in order: per joint its link's m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, "
                             "Izz (about the link frame's origin), then the joint's fc, fv (friction) and Ia (armature).")
      .def(
          "regressor",
          [](const ChainModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
             const std::optional<Eigen::Vector3d>& specific_force_mps2, const Eigen::Vector3d& omega_radps,
             const Eigen::Vector3d& alpha_radps2) {
            ChainBaseMotion base = ChainBaseMotion::still(model);
            if (specific_force_mps2) base.specific_force_mps2 = *specific_force_mps2;
            base.omega_radps = omega_radps;
            base.alpha_radps2 = alpha_radps2;
            return chainRegressor(model, q, qd, qdd, base);
          },
          py::arg("q"), py::arg("qd"), py::arg("qdd"), py::arg("specific_force_mps2") = py::none(),
          py::arg("omega_radps") = Eigen::Vector3d::Zero(), py::arg("alpha_radps2") = Eigen::Vector3d::Zero(),
          "dof x len(parameter_names) regressor Y: tau = Y @ phi. The base is still under gravity unless "
          "specific_force_mps2 (a - g of the base origin), omega_radps, alpha_radps2 (base frame) are given.")
      .def(
          "base_parameters",
          [](const ChainModel& model, int samples, std::uint64_t seed) {
            BaseParameterOptions o;
            o.samples = samples;
            o.seed = seed;
            const BaseParameters b = baseParameters(model, o);
            return py::dict(py::arg("rank") = b.rank, py::arg("names") = b.names, py::arg("combinations") = b.combinations, py::arg("combination") = b.combination,
                            py::arg("independent") = b.independent, py::arg("no_effect") = b.no_effect,
                            py::arg("regrouped") = b.regrouped);
          },
          py::arg("samples") = 200, py::arg("seed") = 1,
          "The identifiable combinations (QR with column pivoting of the regressor over random states): rank; "
          "names, one readable combination each; combination (rank x parameters: beta = combination @ phi); "
          "independent (the standard parameter each is named after); no_effect (parameters that move no torque); "
          "regrouped ((parameter, [base indices]) pairs).")
      .def(
          "consistent_fit",
          [](const ChainModel& model, const Eigen::MatrixXd& W, const Eigen::VectorXd& y, const Eigen::VectorXd& phi_start,
             double max_link_mass_kg, double link_radius_m, double barrier_gap) {
            ConsistentFitOptions o;
            o.max_link_mass_kg = max_link_mass_kg;
            o.link_radius_m = link_radius_m;
            o.barrier_gap = barrier_gap;
            const BaseParameters base = baseParameters(model);
            // W in the standard parameters' columns (stacked regressor rows), or in the base parameters'
            // (process_chain_record's rows).
            const bool base_columns = W.cols() == base.rank && base.rank != model.standardParameterCount();
            const ConsistentFit f = base_columns ? consistentFitNormal(model, base, W.transpose() * W, W.transpose() * y, y.squaredNorm(), phi_start, o)
                                                 : consistentFit(model, base, W, y, phi_start, o);
            return py::dict(py::arg("phi") = f.phi, py::arg("beta") = f.beta, py::arg("beta_ls") = f.beta_ls,
                            py::arg("combination") = base.combination, py::arg("excess_cost") = f.excess_cost,
                            py::arg("ls_cost") = f.ls_cost, py::arg("status") = std::string(toString(f.status)),
                            py::arg("link_min_eigenvalue") = f.link_min_eigenvalue, py::arg("message") = f.message);
          },
          py::arg("W"), py::arg("y"), py::arg("phi_start"), py::arg("max_link_mass_kg") = ConsistentFitOptions{}.max_link_mass_kg,
          py::arg("link_radius_m") = ConsistentFitOptions{}.link_radius_m, py::arg("barrier_gap") = ConsistentFitOptions{}.barrier_gap,
          "Physically consistent least squares in base-parameter space: W (stacked regressor rows, in the standard "
          "parameters' columns or the base parameters' as process_chain_record gives them), y (torques), "
          "phi_start (standard parameters to start from). Every link's pseudo-inertia positive definite, its mass "
          "below max_link_mass_kg and within link_radius_m of its origin, friction and armature >= 0. Returns phi, "
          "beta (= combination @ phi), beta_ls, excess_cost ((beta - beta_ls)' Wb' Wb (beta - beta_ls)), ls_cost, "
          "status, link_min_eigenvalue, message.");
  m.def("process_chain_record",
        [](const ChainModel& model, const py::dict& dataset, const std::string& processing, std::optional<double> cutoff_hz, int filter_order,
           int decimation) {
          const RecordRows r = processRecord(datasetFrom(dataset), chainRobot(model), signalOptions(processing, cutoff_hz, filter_order, decimation, "auto"));
          return py::dict(py::arg("W") = r.W, py::arg("y") = r.y, py::arg("t") = r.states.t_s, py::arg("dof") = r.dof);
        },
        py::arg("model"), py::arg("dataset"), py::arg("processing") = "parallel", py::arg("cutoff_hz") = py::none(),
        py::arg("filter_order") = 2, py::arg("decimation") = 0,
        (std::string("A chain's record (dict as read_dataset returns, with the model's joints) to the rows a method fits: W "
                     "(rows x the base parameters, base_parameters()['names'] order; sample k's joint j at row k * dof + j), y, "
                     "t (one per sample), dof. model.consistent_fit(W, y, phi) fits consistently. ") +
         kSignalOptionsDoc)
            .c_str());
  m.def("link_parameters",
        [](double mass_kg, const Eigen::Vector3d& com_m, const Eigen::Matrix3d& inertia_com_kgm2) {
          return Eigen::VectorXd(linkParameters(mass_kg, com_m, inertia_com_kgm2));
        },
        py::arg("mass_kg"), py::arg("com_m"), py::arg("inertia_com_kgm2"),
        "A link's 10 standard parameters from its mass, centre of mass and inertia about the centre of mass (link frame).");
}

}  // namespace exoid::python
