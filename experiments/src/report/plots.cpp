#include "exoid/experiments/report/plots.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/sim/data_dir.hpp"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <sys/wait.h>

namespace exoid::experiments {

namespace {
std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

void runPlotScript(const std::string& script, const std::vector<std::string>& args) {
  // Debian's python3 owns python3-matplotlib; a python3 earlier on PATH may not have it.
  const char* python = std::getenv("EXOID_PYTHON") ? std::getenv("EXOID_PYTHON") : "/usr/bin/python3";
  std::string cmd = shellQuote(python) + " " + shellQuote(sim::dataPath("plots/" + script));
  for (const std::string& a : args) cmd += " " + shellQuote(a);
  cmd += " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  if (!pipe) throw std::runtime_error("cannot start " + std::string(python) + " for plotting");
  std::string output;
  std::array<char, 512> buf{};
  while (fgets(buf.data(), static_cast<int>(buf.size()), pipe.get())) output += buf.data();
  const int status = pclose(pipe.release());
  if (status != 0) {
    throw std::runtime_error("plotting with " + script + " failed (is python3-matplotlib installed? "
                             "scripts/deps.sh installs it; reproduce --no-plots and excite --no-plot skip figures):\n" + output);
  }
}

void plotTorqueFit(const std::string& png, const std::vector<std::string>& joints, const ident::RecordRows& shown,
                   const Eigen::VectorXd& theta, const std::string& title) {
  const std::string series = png.substr(0, png.rfind('.')) + "_series.csv";
  const Eigen::VectorXd predicted = shown.W * theta;
  const auto dof = static_cast<Eigen::Index>(joints.size());
  core::writeFileAtomically(series, [&](std::ostream& out) {
    out << "t_s";
    for (const std::string& j : joints) out << ",tau_" << j << ",tau_" << j << "_predicted";
    out << "\n";
    char buf[32];
    for (Eigen::Index k = 0; k < shown.samples(); ++k) {
      std::snprintf(buf, sizeof buf, "%.9g", shown.states.t_s[k]);
      out << buf;
      for (Eigen::Index j = 0; j < dof; ++j) {
        std::snprintf(buf, sizeof buf, ",%.9g,", shown.y[k * dof + j]);
        out << buf;
        std::snprintf(buf, sizeof buf, "%.9g", predicted[k * dof + j]);
        out << buf;
      }
      out << "\n";
    }
  });
  runPlotScript("torque_fit_plot.py", {series, png, title});
  std::cout << "wrote " << png << " and " << series << "\n";
}

}  // namespace exoid::experiments
