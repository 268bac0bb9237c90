#include "exoid/sim/table.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include <unistd.h>

namespace exoid::sim {

Eigen::Index Table::column(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<Eigen::Index>(i);
  }
  std::string all;
  for (const auto& n : names) all += (all.empty() ? "" : ",") + n;
  throw std::invalid_argument("table has no column '" + name + "' (columns: " + all + ")");
}

bool Table::has(const std::string& name) const {
  for (const auto& n : names) {
    if (n == name) return true;
  }
  return false;
}

std::string tableCsv(const Table& t) {
  if (static_cast<Eigen::Index>(t.names.size()) != t.values.cols()) {
    throw std::invalid_argument("table: " + core::toText(t.names.size()) + " names for " +
                                core::toText(t.values.cols()) + " columns");
  }
  std::string out;
  out.reserve(static_cast<std::size_t>(t.values.size()) * 24 + 1024);
  for (const auto& [k, v] : t.metadata) out += "# " + k + ": " + v + "\n";
  for (std::size_t i = 0; i < t.names.size(); ++i) {
    if (i) out += ',';
    out += t.names[i];
  }
  out += '\n';
  char buf[40];
  for (Eigen::Index r = 0; r < t.values.rows(); ++r) {
    for (Eigen::Index c = 0; c < t.values.cols(); ++c) {
      if (c) out += ',';
      const int n = std::snprintf(buf, sizeof buf, "%.17g", t.values(r, c));
      out.append(buf, static_cast<std::size_t>(n));
    }
    out += '\n';
  }
  return out;
}

void writeTableCsv(const Table& t, const std::string& path) { core::writeFileAtomically(path, tableCsv(t)); }

}  // namespace exoid::sim
