#include "exoid/sim/serial_chain.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace exoid::sim {

namespace {

using Matrix3r = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

Eigen::Matrix3d bodyRotation(const mjData* d, int body) { return Eigen::Map<const Matrix3r>(d->xmat + 9 * body); }

std::string nameOf(const mjModel* m, mjtObj type, int id) {
  const char* n = mj_id2name(m, type, id);
  return n ? n : "#" + std::to_string(id);
}

// True when body b moves on no joint of its own but the locked ones.
bool heldBody(const mjModel* m, int b, const std::map<int, double>& locked) {
  for (int j = m->body_jntadr[b]; j < m->body_jntadr[b] + m->body_jntnum[b]; ++j) {
    if (!locked.count(j)) return false;
  }
  return true;
}

// The bodies welded to `root` (reached from it without crossing a joint that is not locked), root included.
std::vector<int> weldedTo(const mjModel* m, int root, const std::map<int, double>& locked) {
  std::vector<int> out{root};
  for (int b = root + 1; b < m->nbody; ++b) {
    int p = b;
    while (p > root && heldBody(m, p, locked)) p = m->body_parentid[p];
    if (p == root && b != root) out.push_back(b);
  }
  return out;
}

bool isBelow(const mjModel* m, int body, int ancestor) {
  for (int p = body; p > 0; p = m->body_parentid[p]) {
    if (p == ancestor) return true;
  }
  return ancestor == 0;
}

int bodyNamed(const mjModel* m, const std::string& path, const std::string& name, const char* option) {
  const int id = mj_name2id(m, mjOBJ_BODY, name.c_str());
  if (id < 0) throw std::invalid_argument("'" + path + "': " + option + " " + name + ": the model has no body of that name");
  return id;
}

// The bodies without children below `from`, by name.
std::string leavesBelow(const mjModel* m, int from) {
  std::string out;
  for (int b = from; b < m->nbody; ++b) {
    bool leaf = isBelow(m, b, from);
    for (int c = b + 1; c < m->nbody && leaf; ++c) leaf = m->body_parentid[c] != b;
    if (leaf) out += (out.empty() ? "" : ", ") + nameOf(m, mjOBJ_BODY, b);
  }
  return out;
}

// Bodies below `root` that move by a joint of their own not in the chain.
void collectLeftOut(const mjModel* m, int root, const std::vector<int>& chain_bodies, const std::map<int, double>& locked,
                    std::vector<std::string>& out) {
  for (int b = root + 1; b < m->nbody; ++b) {
    if (heldBody(m, b, locked)) continue;
    bool in_chain = false;
    for (int c : chain_bodies) in_chain = in_chain || c == b;
    if (in_chain) continue;
    int p = m->body_parentid[b];
    while (p > root && heldBody(m, p, locked)) p = m->body_parentid[p];
    if (p == root) out.push_back(nameOf(m, mjOBJ_BODY, b));
  }
}

// Mass, COM and inertia about the COM of `bodies`, in the frame (R, o).
void lumpBodies(const mjModel* m, const mjData* d, const std::vector<int>& bodies, const Eigen::Matrix3d& R,
                const Eigen::Vector3d& o, ChainLinkBody& link) {
  double mass = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d I_origin = Eigen::Matrix3d::Zero();
  for (int b : bodies) {
    const double mb = m->body_mass[b];
    const Eigen::Vector3d principal = Eigen::Map<const Eigen::Vector3d>(m->body_inertia + 3 * b);
    // MuJoCo 2.2.2 compiles a negative mass; the chain takes no body that is not physical.
    if (!std::isfinite(mb) || mb < 0.0 || !principal.allFinite() || principal.minCoeff() < 0.0) {
      throw std::invalid_argument("body '" + nameOf(m, mjOBJ_BODY, b) + "': mass " + std::to_string(mb) + " kg, principal inertia " +
                                  std::to_string(principal.x()) + " " + std::to_string(principal.y()) + " " + std::to_string(principal.z()) +
                                  " kg m^2 (expected finite, mass >= 0, inertia positive semi-definite)");
    }
    const Eigen::Vector3d c = R.transpose() * (Eigen::Map<const Eigen::Vector3d>(d->xipos + 3 * b) - o);
    const Eigen::Matrix3d A = R.transpose() * Eigen::Map<const Matrix3r>(d->ximat + 9 * b);
    const Eigen::Matrix3d I_com = A * Eigen::Map<const Eigen::Vector3d>(m->body_inertia + 3 * b).asDiagonal() * A.transpose();
    mass += mb;
    first += mb * c;
    I_origin += I_com + mb * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  }
  link.mass_kg = mass;
  link.com_m = mass > 0.0 ? Eigen::Vector3d(first / mass) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d& c = link.com_m;
  link.inertia_com_kgm2 = I_origin - mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
}

// What MuJoCo 2.2.2 compiles without a word: a non-finite number (it reads "nan"), a negative
// mass (set to 0) or principal inertia. Refused by file, line and attribute. A plain scan of the
// file's attributes (comments skipped; not the files it <include>s): a value is numeric when every
// token of it reads as a number and it has a digit or a numeric attribute's name (name="Inf" is a name).
void checkMjcfText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  static const std::set<std::string> kNumeric = {"mass", "diaginertia", "fullinertia", "pos", "quat", "axis", "range", "damping", "armature",
                                                 "frictionloss", "gear", "forcerange", "ctrlrange", "size", "density", "euler", "fromto"};
  std::size_t at = 0;
  while ((at = text.find_first_of("=<", at)) != std::string::npos) {
    if (text.compare(at, 4, "<!--") == 0) {
      at = text.find("-->", at);
      if (at == std::string::npos) return;
      continue;
    }
    if (text[at] == '<') {
      ++at;
      continue;
    }
    std::size_t name_end = at;
    while (name_end > 0 && std::isspace(static_cast<unsigned char>(text[name_end - 1]))) --name_end;
    std::size_t name_start = name_end;
    while (name_start > 0 && (std::isalnum(static_cast<unsigned char>(text[name_start - 1])) || text[name_start - 1] == '_')) --name_start;
    std::size_t open = text.find_first_not_of(" \t\r\n", at + 1);
    if (open == std::string::npos || (text[open] != '"' && text[open] != '\'')) {
      ++at;
      continue;
    }
    const std::size_t close = text.find(text[open], open + 1);
    if (close == std::string::npos) return;  // MuJoCo's parser has refused the file already
    const std::string name = text.substr(name_start, name_end - name_start), value = text.substr(open + 1, close - open - 1);
    at = close + 1;
    std::istringstream tokens(value);
    std::vector<double> numbers;
    bool numeric = true;
    for (std::string token; numeric && tokens >> token;) {
      char* end = nullptr;
      numbers.push_back(std::strtod(token.c_str(), &end));
      numeric = end != token.c_str() && *end == '\0';
    }
    if (!numeric || numbers.empty() || (value.find_first_of("0123456789") == std::string::npos && !kNumeric.count(name))) continue;
    const auto where = [&] {
      const long line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(open), '\n');
      return "'" + path + "', line " + std::to_string(line) + ": " + name + "=\"" + value + "\"";
    };
    for (double v : numbers) {
      if (!std::isfinite(v)) throw std::invalid_argument(where() + ": a non-finite number");
      if ((name == "mass" || name == "diaginertia") && v < 0.0) throw std::invalid_argument(where() + ": negative (a mass and principal inertias are >= 0)");
    }
  }
}

}  // namespace

int chainBaseBody(const mjModel* m, int first_body) {
  int base = m->body_parentid[first_body];
  while (base > 0 && m->body_jntnum[base] == 0) base = m->body_parentid[base];
  return base;
}

SerialChain serialChainFromMjcf(const mjModel* m, const std::vector<int>& joints, const std::vector<double>& coulomb_Nm,
                                const std::string& source, const std::map<int, double>& locked) {
  if (joints.empty()) throw std::invalid_argument("'" + source + "': no joints given for the chain");
  if (coulomb_Nm.size() != joints.size()) throw std::invalid_argument("'" + source + "': one Coulomb value per chain joint expected");
  DataPtr d = makeData(m);
  mju_copy(d->qpos, m->qpos0, m->nq);
  for (const auto& [j, value] : locked) {
    if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) {
      throw std::invalid_argument("'" + source + "': --lock " + nameOf(m, mjOBJ_JOINT, j) + ": a ball or free joint cannot be held at one value");
    }
    d->qpos[m->jnt_qposadr[j]] = value;
  }
  mj_kinematics(m, d.get());
  SerialChain chain;
  chain.source = source;
  chain.gravity_mps2 = Eigen::Map<const Eigen::Vector3d>(m->opt.gravity);
  std::vector<int> bodies;
  for (int j : joints) bodies.push_back(m->jnt_bodyid[j]);
  // The chain's base frame at qpos0 (the world, or a stand that moves on its mount); gravity in it.
  const int base = chainBaseBody(m, bodies.front());
  Eigen::Matrix3d R_parent = bodyRotation(d.get(), base);
  Eigen::Vector3d o_parent = Eigen::Map<const Eigen::Vector3d>(d->xpos + 3 * base);
  chain.gravity_mps2 = R_parent.transpose() * chain.gravity_mps2;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const int j = joints[i], b = bodies[i];
    const std::string at = "'" + source + "', joint '" + nameOf(m, mjOBJ_JOINT, j) + "'";
    if (m->jnt_type[j] != mjJNT_HINGE) throw std::invalid_argument(at + ": not a hinge (exoid's chains are revolute joints)");
    if (m->body_jntnum[b] != 1) throw std::invalid_argument(at + ": its body has " + std::to_string(m->body_jntnum[b]) + " joints (one expected)");
    if (i > 0) {  // directly below the previous link, through welded bodies only
      int p = m->body_parentid[b];
      while (p != bodies[i - 1] && p > 0 && heldBody(m, p, locked)) p = m->body_parentid[p];
      if (p != bodies[i - 1]) throw std::invalid_argument(at + ": not below joint '" + nameOf(m, mjOBJ_JOINT, joints[i - 1]) + "' (not a serial chain)");
    }
    ChainLinkBody link;
    link.joint = nameOf(m, mjOBJ_JOINT, j);
    link.link = nameOf(m, mjOBJ_BODY, b);
    const Eigen::Matrix3d R = bodyRotation(d.get(), b);
    const Eigen::Vector3d o = Eigen::Map<const Eigen::Vector3d>(d->xanchor + 3 * j);  // the link frame on the axis
    link.parent_R_joint = R_parent.transpose() * R;
    link.parent_p_joint_m = R_parent.transpose() * (o - o_parent);
    link.axis = Eigen::Map<const Eigen::Vector3d>(m->jnt_axis + 3 * j).normalized();
    try {
      lumpBodies(m, d.get(), weldedTo(m, b, locked), R, o, link);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("'" + source + "', " + e.what());
    }
    const int dof = m->jnt_dofadr[j];
    link.coulomb_Nm = coulomb_Nm[i];
    link.damping_Nms = m->dof_damping[dof];
    link.armature_kgm2 = m->dof_armature[dof];
    if (m->jnt_limited[j]) {
      link.q_min_rad = m->jnt_range[2 * j];
      link.q_max_rad = m->jnt_range[2 * j + 1];
    }
    for (int a = 0; a < m->nu; ++a) {
      if (m->actuator_trntype[a] != mjTRN_JOINT || m->actuator_trnid[2 * a] != j) continue;
      const double gear = std::abs(m->actuator_gear[6 * a]);
      if (m->actuator_forcelimited[a]) {
        link.tau_max_Nm = gear * std::max(std::abs(m->actuator_forcerange[2 * a]), std::abs(m->actuator_forcerange[2 * a + 1]));
      } else if (m->actuator_ctrllimited[a]) {
        link.tau_max_Nm = gear * std::max(std::abs(m->actuator_ctrlrange[2 * a]), std::abs(m->actuator_ctrlrange[2 * a + 1]));
      }
      if (!(link.tau_max_Nm > 0.0)) {
        throw std::invalid_argument(at + ": actuator '" + nameOf(m, mjOBJ_ACTUATOR, a) + "' limits the torque to " + std::to_string(link.tau_max_Nm) +
                                    " N m (expected > 0)");
      }
    }
    collectLeftOut(m, b, bodies, locked, chain.left_out);
    chain.links.push_back(link);
    R_parent = R;
    o_parent = o;
  }
  return chain;
}

std::vector<int> drivenHinges(const mjModel* m, const std::string& path) {
  std::vector<int> driven;
  for (int a = 0; a < m->nu; ++a) {
    if (m->actuator_trntype[a] != mjTRN_JOINT) continue;
    const int j = m->actuator_trnid[2 * a];
    if (m->jnt_type[j] != mjJNT_HINGE) {
      static const char* const kTypes[] = {"free", "ball", "slide", "hinge"};
      throw std::invalid_argument("'" + path + "': actuator '" + nameOf(m, mjOBJ_ACTUATOR, a) + "' drives joint '" +
                                  nameOf(m, mjOBJ_JOINT, j) + "', a " + kTypes[m->jnt_type[j]] +
                                  " joint: exoid identifies chains of revolute (hinge) joints only");
    }
    bool seen = false;
    for (int k : driven) seen = seen || k == j;
    if (!seen) driven.push_back(j);
  }
  if (driven.empty()) throw std::invalid_argument("'" + path + "': no actuator drives a hinge joint: no chain to identify");
  std::sort(driven.begin(), driven.end());  // joint ids follow the tree, base to tip
  return driven;
}

SerialChain serialChainFromMjcfFile(const std::string& path, const ChainSelection& selection) {
  const ModelPtr model = loadMjcfFile(path);
  checkMjcfText(path);
  const mjModel* m = model.get();
  std::map<int, double> locked;
  for (const auto& [name, value] : selection.locks) {
    const int j = mj_name2id(m, mjOBJ_JOINT, name.c_str());
    if (j < 0) throw std::invalid_argument("'" + path + "': --lock " + name + ": the model has no joint of that name");
    if (!std::isfinite(value)) throw std::invalid_argument("'" + path + "': --lock " + name + ": the value is not a finite number");
    locked[j] = value;
  }
  const int base = selection.base.empty() ? 0 : bodyNamed(m, path, selection.base, "--base");
  const int tip = selection.tip.empty() ? -1 : bodyNamed(m, path, selection.tip, "--tip");
  if (tip >= 0 && !isBelow(m, tip, base)) {
    throw std::invalid_argument("'" + path + "': --tip " + selection.tip + " is not below --base " + nameOf(m, mjOBJ_BODY, base));
  }
  // The driven hinges from the base to the tip (every one below the base without a tip); the
  // others hang from the base (left out) or off a chain link (refused unless locked).
  std::vector<int> chain_joints, off_chain;
  for (int j : drivenHinges(m, path)) {
    if (locked.count(j)) continue;
    const int b = m->jnt_bodyid[j];
    const bool on_path = b != base && isBelow(m, b, base) && (tip < 0 || isBelow(m, tip, b));
    (on_path ? chain_joints : off_chain).push_back(j);
  }
  if (chain_joints.empty()) throw std::invalid_argument("'" + path + "': no driven hinge between --base and --tip: no chain to identify");
  for (std::size_t i = 1; i < chain_joints.size(); ++i) {
    if (!isBelow(m, m->jnt_bodyid[chain_joints[i]], m->jnt_bodyid[chain_joints[i - 1]])) {
      throw std::invalid_argument("'" + path + "': joints '" + nameOf(m, mjOBJ_JOINT, chain_joints[i - 1]) + "' and '" + nameOf(m, mjOBJ_JOINT, chain_joints[i]) +
                                  "' are driven on two branches: a tree, not a serial chain. Choose the chain with --tip BODY (and --base BODY, "
                                  "default '" + nameOf(m, mjOBJ_BODY, base) + "'); the leaf bodies below it: " + leavesBelow(m, base));
    }
  }
  for (int j : off_chain) {
    if (isBelow(m, m->jnt_bodyid[j], m->jnt_bodyid[chain_joints.front()])) {
      throw std::invalid_argument("'" + path + "': driven joint '" + nameOf(m, mjOBJ_JOINT, j) + "' moves a branch off the chain: hold it with --lock " +
                                  nameOf(m, mjOBJ_JOINT, j) + "=VALUE (rad, or m for a prismatic joint; lumped at that posture), or choose another --base/--tip");
    }
  }
  std::vector<double> coulomb;
  for (int j : chain_joints) {
    const int id = mj_name2id(m, mjOBJ_NUMERIC, ("exoid_fc_" + nameOf(m, mjOBJ_JOINT, j)).c_str());
    coulomb.push_back(id >= 0 ? m->numeric_data[m->numeric_adr[id]] : 0.0);
  }
  SerialChain chain = serialChainFromMjcf(m, chain_joints, coulomb, path, locked);
  // Driven branches hanging from the base: left out, named.
  for (int j : off_chain) chain.left_out.push_back(nameOf(m, mjOBJ_BODY, m->jnt_bodyid[j]));
  // A lock is used on the path (holding a joint of it) or below the chain's first link (a branch
  // lumped into a link); one anywhere else would be silently unused.
  const int first = m->jnt_bodyid[chain_joints.front()];
  for (const auto& [j, value] : locked) {
    const int b = m->jnt_bodyid[j];
    const bool on_path = isBelow(m, b, base) && b != base && (tip < 0 || isBelow(m, tip, b)) && isBelow(m, first, b);
    if (!on_path && !isBelow(m, b, first)) {
      throw std::invalid_argument("'" + path + "': --lock " + nameOf(m, mjOBJ_JOINT, j) + ": the joint is neither on the chain nor on a branch off it");
    }
  }
  chain.name = m->nnames > 0 && m->names[0] ? m->names : path;  // MuJoCo keeps <mujoco model=...> first
  return chain;
}

SerialChain serialChainFromFile(const std::string& path, const ChainSelection& selection) {
  return isUrdfFile(path) ? serialChainFromUrdf(path, selection) : serialChainFromMjcfFile(path, selection);
}

SerialChain serialChain(const LegModel& leg) {
  const std::vector<int> joints{leg.idx.jnt[0], leg.idx.jnt[1]};
  SerialChain chain = serialChainFromMjcf(leg.model.get(), joints, {leg.coulomb.fc_Nm[0], leg.coulomb.fc_Nm[1]}, leg.path);
  chain.name = "apal_leg";
  return chain;
}

}  // namespace exoid::sim
