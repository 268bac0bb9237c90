#include "urdf_file.hpp"

#include "exoid/core/format.hpp"

#include <Eigen/Eigenvalues>
#include <console_bridge/console.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <mutex>
#include <stdexcept>

namespace exoid::sim {
namespace {

// Collects what urdfdom reports through console_bridge while it parses (one parse at a time: the
// handler is process-wide).
class Collector : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors += (errors.empty() ? "" : "; ") + text;
  }
  std::string errors;
};

std::mutex& parseMutex() {
  static std::mutex m;
  return m;
}

std::string number(double v) { return core::toText(v); }

void requireFinite(const std::string& path, const std::string& what, std::initializer_list<double> values) {
  for (double v : values) {
    if (!std::isfinite(v)) throw std::invalid_argument("'" + path + "': " + what + " has a non-finite number (" + number(v) + ")");
  }
}

void requireFinite(const std::string& path, const std::string& what, const urdf::Pose& p) {
  requireFinite(path, what, {p.position.x, p.position.y, p.position.z, p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w});
}

void checkNumbers(const std::string& path, const urdf::ModelInterface& model) {
  for (const auto& [name, link] : model.links_) {
    if (!link->inertial) continue;
    const urdf::Inertial& in = *link->inertial;
    const std::string what = "link '" + name + "' <inertial>";
    requireFinite(path, what + " <origin>", in.origin);
    requireFinite(path, what + " <mass>/<inertia>", {in.mass, in.ixx, in.ixy, in.ixz, in.iyy, in.iyz, in.izz});
  }
  for (const auto& [name, joint] : model.joints_) {
    const std::string what = "joint '" + name + "'";
    requireFinite(path, what + " <origin>", joint->parent_to_joint_origin_transform);
    requireFinite(path, what + " <axis>", {joint->axis.x, joint->axis.y, joint->axis.z});
    const double axis_norm = std::sqrt(joint->axis.x * joint->axis.x + joint->axis.y * joint->axis.y + joint->axis.z * joint->axis.z);
    if (joint->type != urdf::Joint::FIXED && joint->type != urdf::Joint::FLOATING && joint->type != urdf::Joint::PLANAR && !(axis_norm > 0.0)) {
      throw std::invalid_argument("'" + path + "': " + what + " <axis>: the zero vector (the joint would move nothing)");
    }
    if (joint->limits) {
      const urdf::JointLimits& l = *joint->limits;
      requireFinite(path, what + " <limit>", {l.lower, l.upper, l.effort, l.velocity});
    }
    if (joint->dynamics) requireFinite(path, what + " <dynamics>", {joint->dynamics->damping, joint->dynamics->friction});
  }
}

}  // namespace

urdf::ModelInterfaceSharedPtr readUrdf(const std::string& path) {
  {
    std::ifstream probe(path);
    if (!probe) throw std::invalid_argument("cannot read URDF file '" + path + "'");
  }
  Collector collector;
  urdf::ModelInterfaceSharedPtr model;
  {
    const std::lock_guard<std::mutex> lock(parseMutex());
    // Whatever level the process set (urdfdom is often silenced), its errors reach the collector.
    const console_bridge::LogLevel level = console_bridge::getLogLevel();
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_ERROR);
    console_bridge::useOutputHandler(&collector);
    try {
      model = urdf::parseURDFFile(path);
    } catch (...) {
      console_bridge::restorePreviousOutputHandler();
      console_bridge::setLogLevel(level);
      throw;
    }
    console_bridge::restorePreviousOutputHandler();
    console_bridge::setLogLevel(level);
  }
  if (!collector.errors.empty()) {
    throw std::invalid_argument("'" + path + "': urdfdom could not read the URDF: " + collector.errors +
                                " (exoid does not identify a model that is not the file's)");
  }
  if (!model) throw std::invalid_argument("'" + path + "': urdfdom could not parse the URDF");
  checkNumbers(path, *model);
  return model;
}

namespace {

double largestInertiaEntry(const urdf::ModelInterface& model) {
  double largest = 0.0;
  for (const auto& [name, l] : model.links_) {
    if (!l || !l->inertial) continue;
    const urdf::Inertial& in = *l->inertial;
    for (const double v : {in.ixx, in.iyy, in.izz, in.ixy, in.ixz, in.iyz}) largest = std::max(largest, std::abs(v));
  }
  return largest;
}

}  // namespace

void checkUsedLink(const std::string& path, const urdf::ModelInterface& model, const urdf::Link& link) {
  if (!link.inertial) return;
  const urdf::Inertial& in = *link.inertial;
  const std::string at = "'" + path + "': link '" + link.name + "' <inertial>";
  if (in.mass < 0.0) throw std::invalid_argument(at + ": negative mass " + number(in.mass) + " kg");
  Eigen::Matrix3d I;
  I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  const Eigen::Vector3d eig = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
  // Round-off of an inertia written to six digits, not a physical negative moment: on the scale of
  // the link's own entries, with a floor far below any body of the model (a zero inertia with a
  // 1e-20 residue off its diagonal) that a link several times its own size off never passes.
  const double tol = 1e-6 * I.cwiseAbs().maxCoeff() + 1e-12 * largestInertiaEntry(model);
  if (eig.minCoeff() < -tol) {
    throw std::invalid_argument(at + ": the inertia (ixx " + number(in.ixx) + ", iyy " + number(in.iyy) + ", izz " + number(in.izz) + ", ixy " +
                                number(in.ixy) + ", ixz " + number(in.ixz) + ", iyz " + number(in.iyz) +
                                " kg m^2) is not positive semi-definite (smallest principal moment " + number(eig.minCoeff()) + ")");
  }
}

void checkChainJoint(const std::string& path, const urdf::Joint& joint) {
  if (!joint.limits) return;
  const std::string at = "'" + path + "': joint '" + joint.name + "' <limit>";
  const urdf::JointLimits& l = *joint.limits;
  const char* zero = "; 0 reads as not given)";
  if (l.effort < 0.0) throw std::invalid_argument(at + ": effort " + number(l.effort) + " N m (expected >= 0" + zero);
  if (l.velocity < 0.0) throw std::invalid_argument(at + ": velocity " + number(l.velocity) + " rad/s (expected >= 0" + zero);
  if (joint.type == urdf::Joint::REVOLUTE && l.lower > l.upper) {
    throw std::invalid_argument(at + ": lower " + number(l.lower) + " rad above upper " + number(l.upper) + " rad");
  }
  if (joint.type == urdf::Joint::REVOLUTE && l.lower == l.upper && l.lower != 0.0) {
    throw std::invalid_argument(at + ": lower = upper = " + number(l.lower) + " rad: a joint that cannot move (hold it with --lock " + joint.name + "=" +
                                number(l.lower) + ", or make it fixed)");
  }
}

}  // namespace exoid::sim
