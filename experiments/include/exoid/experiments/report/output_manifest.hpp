#pragma once
// complete.json's list of outputs: every file a command wrote into its folder, with its size and
// SHA-256. A rerun checks the folder against it, so "complete" is never said of a folder whose
// outputs are missing or were changed after they were written.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <ostream>

#include <string>
#include <vector>

namespace exoid::experiments {

/// [{"file", "bytes", "sha256"}] of `files` (names relative to dir), in the given order. Throws
/// std::runtime_error naming a file that cannot be read.
nlohmann::json outputManifest(const std::string& dir, const std::vector<std::string>& files);

/// One output that is not as the manifest says.
struct OutputProblem {
  std::string file;
  bool missing = false;  ///< else it exists and differs (size or SHA-256)
  std::string describe() const;  ///< "timing.json missing" / "summary.md changed since it was written"
};

/// The outputs of `manifest` (outputManifest's form) that are missing from dir or differ. A
/// manifest not in that form (an older exoid's list of names) gives one problem, file
/// "complete.json", as changed.
std::vector<OutputProblem> checkOutputs(const std::string& dir, const nlohmann::json& manifest);

/// checkOutputs(dir, manifest), each problem said on log ("summary.md changed since it was
/// written: rewriting"); with keep_edits a changed output is refused instead (std::invalid_argument
/// naming the files, nothing said or touched). `rewrite_from` ends the refusal: what a rerun without
/// --keep-edits rewrites them from. Returns the problems.
std::vector<OutputProblem> announceRewrites(const std::string& dir, const nlohmann::json& manifest, bool keep_edits,
                                            const std::string& rewrite_from, std::ostream& log);

/// The PNG files directly in dir, sorted (the plots a script wrote).
std::vector<std::string> pngFilesIn(const std::string& dir);

/// A command that writes a whole folder each run (reproduce): before its work, what a previous
/// run's complete.json says is missing or changed ("report.md changed since it was written:
/// rewriting"), complete.json removed (an interrupted run is never "complete"); with keep_edits a
/// changed output is refused instead (std::invalid_argument naming the files), nothing touched.
void startFolderRun(const std::string& dir, bool keep_edits, std::ostream& log);
/// After the work: complete.json listing every file under dir written since `since` (relative
/// paths, sorted) with its size and SHA-256, plus `extra`'s keys.
void finishFolderRun(const std::string& dir, std::filesystem::file_time_type since, const nlohmann::json& extra);

}  // namespace exoid::experiments
