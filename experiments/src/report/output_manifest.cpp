#include "exoid/experiments/report/output_manifest.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/core/sha256.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace exoid::experiments {

namespace fs = std::filesystem;

nlohmann::json outputManifest(const std::string& dir, const std::vector<std::string>& files) {
  nlohmann::json out = nlohmann::json::array();
  for (const std::string& f : files) {
    const fs::path p = fs::path(dir) / f;
    out.push_back({{"file", f}, {"bytes", fs::file_size(p)}, {"sha256", core::sha256OfFile(p.string())}});
  }
  return out;
}

std::string OutputProblem::describe() const { return file + (missing ? " missing" : " changed since it was written"); }

std::vector<OutputProblem> checkOutputs(const std::string& dir, const nlohmann::json& manifest) {
  std::vector<OutputProblem> problems;
  const bool listed = manifest.is_array() && std::all_of(manifest.begin(), manifest.end(), [](const nlohmann::json& e) {
                        return e.is_object() && e.contains("file") && e.contains("bytes") && e.contains("sha256");
                      });
  if (!listed) return {{"complete.json", false}};  // no sizes and digests to check against
  for (const nlohmann::json& e : manifest) {
    const std::string f = e["file"].get<std::string>();
    const fs::path p = fs::path(dir) / f;
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) {
      problems.push_back({f, true});
      continue;
    }
    const bool same = fs::file_size(p, ec) == e["bytes"].get<std::uintmax_t>() && !ec &&
                      core::sha256OfFile(p.string()) == e["sha256"].get<std::string>();
    if (!same) problems.push_back({f, false});
  }
  return problems;
}

std::vector<std::string> pngFilesIn(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.is_regular_file() && e.path().extension() == ".png") out.push_back(e.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<OutputProblem> announceRewrites(const std::string& dir, const nlohmann::json& manifest, bool keep_edits,
                                            const std::string& rewrite_from, std::ostream& log) {
  const std::vector<OutputProblem> problems = checkOutputs(dir, manifest);
  std::string changed;
  for (const OutputProblem& p : problems) {
    if (!p.missing) changed += (changed.empty() ? "" : ", ") + p.file;
  }
  if (keep_edits && !changed.empty()) {
    throw std::invalid_argument("refusing to rewrite " + changed + " in " + dir +
                                ": changed since exoid wrote them, and --keep-edits keeps hand edits (move them aside, or rerun "
                                "without --keep-edits" + (rewrite_from.empty() ? "" : " to have them rewritten from " + rewrite_from) + ")");
  }
  for (const OutputProblem& p : problems) log << p.describe() << ": rewriting\n";
  return problems;
}

void startFolderRun(const std::string& dir, bool keep_edits, std::ostream& log) {
  const fs::path marker = fs::path(dir) / "complete.json";
  std::error_code ec;
  if (!fs::exists(marker, ec)) return;
  nlohmann::json m;
  try {
    std::ifstream in(marker);
    m = nlohmann::json::parse(in);
  } catch (const std::exception&) {
    m = nullptr;
  }
  announceRewrites(dir, m.is_object() ? m.value("outputs", nlohmann::json()) : nlohmann::json(), keep_edits, "", log);
  fs::remove(marker, ec);
}

void finishFolderRun(const std::string& dir, fs::file_time_type since, const nlohmann::json& extra) {
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), dir).generic_string();
    if (rel == "complete.json" || e.last_write_time() < since) continue;
    files.push_back(rel);
  }
  std::sort(files.begin(), files.end());
  nlohmann::json j = extra;
  j["outputs"] = outputManifest(dir, files);
  core::writeFileAtomically((fs::path(dir) / "complete.json").string(), [&](std::ostream& o) { o << j.dump(2) << "\n"; });
}

}  // namespace exoid::experiments
