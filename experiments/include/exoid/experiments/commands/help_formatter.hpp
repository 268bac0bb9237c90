#pragma once
// exoid's --help: CLI11's layout without its internals. Enumerations read "paper|parallel",
// validators their own words ("auto|HZ>=0", "FILE"), flags without "{false}", and descriptions
// wrapped so no line passes 100 characters. A default under exoid's data directory reads "the
// shipped models/apal_leg.xml": where a build put the file differs between machines.
#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <utility>

namespace exoid::experiments {

class HelpFormatter : public CLI::Formatter {
 public:
  static constexpr std::size_t kLineWidth = 100;
  /// shipped_dir: exoid's data directory, or empty when there is none (defaults then print as they are).
  explicit HelpFormatter(std::string shipped_dir = {}) : shipped_dir_(std::move(shipped_dir)) {}
  std::string make_option_name(const CLI::Option* opt, bool is_positional) const override;
  std::string make_option_opts(const CLI::Option* opt) const override;
  std::string make_option_desc(const CLI::Option* opt) const override;
  std::string make_subcommand(const CLI::App* sub) const override;  ///< its description reflowed
  std::string make_description(const CLI::App* app) const override;

 private:
  std::string shipped_dir_;
};

/// "<shipped_dir>/models/apal_leg.xml" -> "the shipped models/apal_leg.xml"; anything else unchanged.
std::string readableDefault(const std::string& default_str, const std::string& shipped_dir);

/// "ENUM:value in {paper->0,parallel->1} OR {0,1}" -> "paper|parallel"; "TEXT:auto|HZ>=0" ->
/// "auto|HZ>=0"; "FLOAT" stays. (The type label CLI11 builds from the type and its validators.)
std::string readableTypeName(const std::string& type_name);
/// text with every line wrapped at `width` characters on spaces (existing line breaks kept).
std::string wrapText(const std::string& text, std::size_t width);

}  // namespace exoid::experiments
