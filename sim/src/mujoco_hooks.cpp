#include "exoid/sim/mujoco_hooks.hpp"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>

namespace exoid::sim {
namespace {

std::atomic<std::size_t> g_warning_count{0};
std::mutex g_warning_mutex;
std::string g_last_warning;  // guarded by g_warning_mutex

void onMujocoError(const char* msg) {
  // MuJoCo's C code is built with unwind tables on this platform, so throwing through it is
  // well defined for the frames involved; the mjData that raised it must not be used again.
  throw MujocoError(std::string("MuJoCo error: ") + (msg ? msg : "(no message)"));
}

void onMujocoWarning(const char* msg) {
  g_warning_count.fetch_add(1, std::memory_order_relaxed);
  std::lock_guard<std::mutex> lock(g_warning_mutex);
  g_last_warning = msg ? msg : "";
}

}  // namespace

void installMujocoHooks() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = &onMujocoError;
    mju_user_warning = &onMujocoWarning;
  });
}

std::size_t mujocoWarningCount() { return g_warning_count.load(std::memory_order_relaxed); }

std::string lastMujocoWarning() {
  std::lock_guard<std::mutex> lock(g_warning_mutex);
  return g_last_warning;
}

const char* warningName(int warning) {
  switch (warning) {
    case mjWARN_INERTIA: return "mjWARN_INERTIA (near-singular inertia matrix)";
    case mjWARN_CONTACTFULL: return "mjWARN_CONTACTFULL (contact buffer full)";
    case mjWARN_CNSTRFULL: return "mjWARN_CNSTRFULL (constraint buffer full: raise <size njmax>)";
    case mjWARN_VGEOMFULL: return "mjWARN_VGEOMFULL (visual geom buffer full)";
    case mjWARN_BADQPOS: return "mjWARN_BADQPOS (bad number in qpos)";
    case mjWARN_BADQVEL: return "mjWARN_BADQVEL (bad number in qvel)";
    case mjWARN_BADQACC: return "mjWARN_BADQACC (bad number in qacc: the simulation diverged)";
    case mjWARN_BADCTRL: return "mjWARN_BADCTRL (bad number in ctrl)";
    default: return "unknown MuJoCo warning";
  }
}

void checkStepHealth(const mjModel* m, const mjData* d, double t_s, const char* context) {
  for (int i = 0; i < mjNWARNING; ++i) {
    if (d->warning[i].number > 0) {
      char buf[160];
      std::snprintf(buf, sizeof buf, " (info %d) at t = %.6g s during %s", d->warning[i].lastinfo,
                    t_s, context);
      throw SimulationError(std::string("MuJoCo warning ") + warningName(i) + buf +
                            ". Last MuJoCo message: '" + lastMujocoWarning() +
                            "'. MuJoCo would reset the state silently; the run stops instead "
                            "(check gains, timestep, vibration level).");
    }
  }
  for (int i = 0; i < m->nv; ++i) {
    if (!std::isfinite(d->qacc[i]) || !std::isfinite(d->qvel[i])) {
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "non-finite state at t = %.6g s during %s: dof %d qvel %g qacc %g", t_s,
                    context, i, d->qvel[i], d->qacc[i]);
      throw SimulationError(buf);
    }
  }
  for (int i = 0; i < m->nq; ++i) {
    if (!std::isfinite(d->qpos[i])) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "non-finite qpos[%d] at t = %.6g s during %s", i, t_s, context);
      throw SimulationError(buf);
    }
  }
}

}  // namespace exoid::sim
