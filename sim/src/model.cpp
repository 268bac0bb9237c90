#include "exoid/sim/model.hpp"

#include "exoid/sim/data_dir.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace exoid::sim {

std::string defaultModelPath() { return dataPath("models/apal_leg.xml"); }

std::string modelPathFor(const std::string& name_or_path) {
  if (name_or_path == "apal") return defaultModelPath();
  if (name_or_path == "leg3") return dataPath("models/leg3.xml");
  return name_or_path;
}

std::string readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::invalid_argument("cannot read model file '" + path +
                                "': no such file or not readable (expected an MJCF .xml file)");
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

namespace {
struct VfsDeleter {
  void operator()(mjVFS* v) const {
    mj_deleteVFS(v);
    delete v;
  }
};
}  // namespace

ModelPtr compileMjcf(const std::string& xml, const std::string& source) {
  installMujocoHooks();
  // mjVFS holds ~2 MB of names: keep it on the heap.
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  const char* name = "exoid_model.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0) {
    throw MujocoError(source + ": cannot create an in-memory file for the model");
  }
  const int i = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[i], xml.data(), xml.size());
  char err[1024] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), err, sizeof err);
  if (!m) throw MujocoError(source + ": MuJoCo could not compile the model: " + err);
  return ModelPtr(m);
}

namespace {

// The name of an XML file's root element: the first tag after any declaration, comment or DOCTYPE
// within its first 64 kB ("" when the file cannot be read or none is found there).
std::string xmlRootElement(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(64 * 1024, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  for (std::size_t at = head.find('<'); at != std::string::npos && at + 1 < head.size(); at = head.find('<', at + 1)) {
    const char next = head[at + 1];
    if (next == '?' || next == '!') {  // a declaration, comment or DOCTYPE: skip to its end
      std::size_t end = std::string::npos;
      if (next == '?') {
        end = head.find("?>", at + 2);
      } else if (head.compare(at, 4, "<!--") == 0) {
        end = head.find("-->", at + 4);
      } else {  // <!DOCTYPE ...>, its internal subset [ ... ] included
        end = head.find_first_of("[>", at + 2);
        if (end != std::string::npos && head[end] == '[') end = head.find("]", end);
        if (end != std::string::npos) end = head.find('>', end);
      }
      if (end == std::string::npos) return "";
      at = end;
      continue;
    }
    std::size_t stop = at + 1;
    while (stop < head.size() && (std::isalnum(static_cast<unsigned char>(head[stop])) || head[stop] == '_' || head[stop] == ':' ||
                                  head[stop] == '-' || head[stop] == '.')) {
      ++stop;
    }
    return head.substr(at + 1, stop - at - 1);
  }
  return "";
}

}  // namespace

bool isUrdfFile(const std::string& path) {
  const std::string root = xmlRootElement(path);
  if (!root.empty()) return root == "robot";
  if (path.size() < 5) return false;  // unreadable: its name says which reader will name the problem
  std::string ext = path.substr(path.size() - 5);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".urdf";
}

bool isApalLegModel(const std::string& path) {
  if (isUrdfFile(path)) return false;
  const ModelPtr m = loadMjcfFile(path);
  return m->nnames > 0 && std::string(m->names) == "apal_leg";
}

ModelPtr loadMjcfFile(const std::string& path) {
  installMujocoHooks();
  {
    std::ifstream probe(path);
    if (!probe) {
      throw MujocoError("cannot open model file '" + path + "': no such file or not readable");
    }
  }
  char err[1024] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, err, sizeof err);
  if (!m) throw MujocoError("'" + path + "': MuJoCo could not load the model: " + err);
  return ModelPtr(m);
}

DataPtr makeData(const mjModel* m) {
  installMujocoHooks();
  mjData* d = mj_makeData(m);
  if (!d) throw MujocoError("mj_makeData failed");
  return DataPtr(d);
}

double numericOr(const mjModel* m, const std::string& name, double fallback) {
  const int id = mj_name2id(m, mjOBJ_NUMERIC, name.c_str());
  return id >= 0 && m->numeric_size[id] > 0 ? m->numeric_data[m->numeric_adr[id]] : fallback;
}

void integrateStep(const mjModel* m, mjData* d) {
  if (m->opt.integrator == mjINT_RK4) {
    mj_RungeKutta(m, d, 4);
  } else {
    mj_Euler(m, d);
  }
}

std::string stripMountJoints(const std::string& xml, const std::string& source) {
  std::string out;
  out.reserve(xml.size());
  std::size_t pos = 0;
  int removed = 0;
  while (true) {
    const std::size_t open = xml.find("<joint", pos);
    if (open == std::string::npos) break;
    const std::size_t close = xml.find('>', open);
    if (close == std::string::npos) break;
    const std::string tag = xml.substr(open, close - open + 1);
    const bool is_mount = tag.find("class=\"mount\"") != std::string::npos;
    // "<joint" also prefixes nothing else in MJCF bodies; equality <joint> has no class mount.
    if (is_mount) {
      if (tag.size() < 2 || tag[tag.size() - 2] != '/') {
        throw std::invalid_argument(source + ": mount joint element must be self-closing ('<joint ... />'): " + tag);
      }
      out.append(xml, pos, open - pos);
      ++removed;
    } else {
      out.append(xml, pos, close + 1 - pos);
    }
    pos = close + 1;
  }
  out.append(xml, pos, std::string::npos);
  if (removed == 0) {
    throw std::invalid_argument(source +
                                ": no mount joints (class=\"mount\") found; the pedestal mount "
                                "must be declared to weld or vibrate it");
  }
  return out;
}

std::uint64_t fnv1a64(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string toHex(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

void ModelVariant::validate() const {
  auto bad = [](const std::string& field, double v, const std::string& expected) {
    std::ostringstream ss;
    ss.precision(17);
    ss << "'" << field << "' must be " << expected << ", got " << v;
    throw std::invalid_argument(ss.str());
  };
  if (!std::isfinite(cylinder_mass_scale) || cylinder_mass_scale < 0 || cylinder_mass_scale > 10)
    bad("cylinder_mass_scale", cylinder_mass_scale, "in [0, 10]");
  if (!std::isfinite(vibration_level) || vibration_level < 0 || vibration_level > 20)
    bad("vibration_level", vibration_level, "in [0, 20] (0 = welded pedestal)");
  const std::pair<const char*, const std::optional<double>*> fr[] = {
      {"fc_hip_Nm", &fc_hip_Nm}, {"fv_hip_Nms", &fv_hip_Nms}, {"fc_knee_Nm", &fc_knee_Nm},
      {"fv_knee_Nms", &fv_knee_Nms}, {"knee_armature_kgm2", &knee_armature_kgm2}};
  for (const auto& [name, v] : fr) {
    if (v->has_value() && (!std::isfinite(**v) || **v < 0)) bad(name, **v, "finite and >= 0");
  }
}

double CoulombFriction::torque(int joint, double qd) const {
  return fc_Nm[static_cast<std::size_t>(joint)] * std::tanh(qd / v0_radps);
}

namespace {
int need(const mjModel* m, mjtObj type, const char* name, const std::string& source, const char* what) {
  const int id = mj_name2id(m, type, name);
  if (id < 0) {
    throw std::invalid_argument(source + ": the model has no " + what + " named '" + name +
                                "' (see models/apal_leg.xml for the names the simulator needs)");
  }
  return id;
}
}  // namespace

LegIndices findLegIndices(const mjModel* m, const std::string& source) {
  LegIndices x;
  x.body_pedestal = need(m, mjOBJ_BODY, "pedestal", source, "body");
  x.body_trunk = need(m, mjOBJ_BODY, "trunk", source, "body");
  x.body_thigh = need(m, mjOBJ_BODY, "thigh", source, "body");
  x.body_shank = need(m, mjOBJ_BODY, "shank", source, "body");
  x.body_cylinder = need(m, mjOBJ_BODY, "cylinder", source, "body");
  x.body_rod = need(m, mjOBJ_BODY, "rod", source, "body");
  const char* jn[2] = {"hip", "knee"};
  const char* an[2] = {"hip_motor", "knee_motor"};
  for (int j = 0; j < 2; ++j) {
    const int id = need(m, mjOBJ_JOINT, jn[j], source, "joint");
    if (m->jnt_type[id] != mjJNT_HINGE) throw std::invalid_argument(source + ": joint '" + jn[j] + "' must be a hinge");
    x.jnt[j] = id;
    x.qadr[j] = m->jnt_qposadr[id];
    x.vadr[j] = m->jnt_dofadr[id];
    x.act[j] = need(m, mjOBJ_ACTUATOR, an[j], source, "actuator");
  }
  x.jnt_cyl = need(m, mjOBJ_JOINT, "cylinder_hinge", source, "joint");
  x.jnt_rod = need(m, mjOBJ_JOINT, "rod_slide", source, "joint");
  if (m->jnt_type[x.jnt_cyl] != mjJNT_HINGE || m->jnt_type[x.jnt_rod] != mjJNT_SLIDE) {
    throw std::invalid_argument(source + ": 'cylinder_hinge' must be a hinge and 'rod_slide' a slide joint");
  }
  x.qadr_cyl = m->jnt_qposadr[x.jnt_cyl];
  x.vadr_cyl = m->jnt_dofadr[x.jnt_cyl];
  x.qadr_rod = m->jnt_qposadr[x.jnt_rod];
  x.vadr_rod = m->jnt_dofadr[x.jnt_rod];
  const char* mn[3] = {"mount_x", "mount_z", "mount_pitch"};
  for (int k = 0; k < 3; ++k) {
    const int id = mj_name2id(m, mjOBJ_JOINT, mn[k]);
    x.mount_jnt[k] = id;
    if (id >= 0) {
      x.mount_qadr[k] = m->jnt_qposadr[id];
      x.mount_vadr[k] = m->jnt_dofadr[id];
    }
  }
  if ((x.mount_jnt[0] >= 0) != (x.mount_jnt[1] >= 0) || (x.mount_jnt[0] >= 0) != (x.mount_jnt[2] >= 0)) {
    throw std::invalid_argument(source + ": the mount needs all of mount_x, mount_z, mount_pitch or none");
  }
  x.eq_loop = need(m, mjOBJ_EQUALITY, "loop", source, "equality");
  x.eq_hip_lock = need(m, mjOBJ_EQUALITY, "hip_lock", source, "equality");
  if (m->eq_type[x.eq_loop] != mjEQ_CONNECT || m->eq_obj1id[x.eq_loop] != x.body_rod ||
      m->eq_obj2id[x.eq_loop] != x.body_shank) {
    throw std::invalid_argument(source + ": equality 'loop' must be a connect from body1 'rod' to body2 'shank'");
  }
  if (m->eq_type[x.eq_hip_lock] != mjEQ_JOINT || m->eq_obj1id[x.eq_hip_lock] != x.jnt[0] ||
      m->eq_obj2id[x.eq_hip_lock] >= 0) {
    throw std::invalid_argument(source + ": equality 'hip_lock' must be a joint equality on 'hip' alone");
  }
  x.site_imu = need(m, mjOBJ_SITE, "imu", source, "site");
  return x;
}

LegModel loadLeg(const std::string& path, const ModelVariant& variant, bool force_welded) {
  variant.validate();
  LegModel leg;
  leg.path = path;
  leg.variant = variant;
  std::string xml;
  try {
    xml = readFileBytes(path);
  } catch (const std::invalid_argument& e) {
    throw MujocoError(e.what());
  }
  leg.xml_fnv1a64 = fnv1a64(xml);
  leg.xml_bytes = xml.size();
  leg.welded = force_welded || variant.vibration_level == 0.0;
  if (leg.welded) {
    // Compile from memory: the model must not reference other files by relative path.
    leg.model = compileMjcf(stripMountJoints(xml, path), "'" + path + "' (mount removed)");
  } else {
    leg.model = loadMjcfFile(path);
  }
  mjModel* m = leg.model.get();
  leg.idx = findLegIndices(m, path);
  const LegIndices& x = leg.idx;
  if (!leg.welded && !x.hasMount()) {
    throw std::invalid_argument("'" + path + "': vibration_level > 0 needs mount joints mount_x, mount_z, mount_pitch");
  }

  // Friction: Coulomb from the custom numerics (applied by the simulator), viscous = damping.
  leg.coulomb.fc_Nm = {numericOr(m, "exoid_fc_hip", 0.0), numericOr(m, "exoid_fc_knee", 0.0)};
  leg.coulomb.v0_radps = numericOr(m, "exoid_coulomb_v0", 2e-3);
  if (!(leg.coulomb.v0_radps > 0)) throw std::invalid_argument("'" + path + "': exoid_coulomb_v0 must be > 0");
  if (variant.fc_hip_Nm) leg.coulomb.fc_Nm[0] = *variant.fc_hip_Nm;
  if (variant.fc_knee_Nm) leg.coulomb.fc_Nm[1] = *variant.fc_knee_Nm;
  if (variant.fv_hip_Nms) m->dof_damping[x.vadr[0]] = *variant.fv_hip_Nms;
  if (variant.fv_knee_Nms) m->dof_damping[x.vadr[1]] = *variant.fv_knee_Nms;
  if (variant.knee_armature_kgm2) m->dof_armature[x.vadr[1]] = *variant.knee_armature_kgm2;

  // Moving actuator mass.
  const double s = variant.cylinder_mass_scale;
  for (int b : {x.body_cylinder, x.body_rod}) {
    m->body_mass[b] *= s;
    for (int k = 0; k < 3; ++k) m->body_inertia[3 * b + k] *= s;
  }
  if (s == 0.0) {
    leg.kinematic_loop = true;
    m->eq_active[x.eq_loop] = 0;
    m->dof_armature[x.vadr_cyl] = kMasslessArmature;
    m->dof_armature[x.vadr_rod] = kMasslessArmature;
  }

  // Mount compliance.
  if (!leg.welded) {
    const double L = variant.vibration_level;
    for (int k = 0; k < 3; ++k) {
      m->jnt_stiffness[x.mount_jnt[k]] /= L * L;
      m->dof_damping[x.mount_vadr[k]] /= L;
    }
  }
  // Masses changed: recompute the derived constants (body_subtreemass, invweight0 used by the
  // constraint impedance).
  DataPtr d = makeData(m);
  mj_setConst(m, d.get());
  return leg;
}

}  // namespace exoid::sim
