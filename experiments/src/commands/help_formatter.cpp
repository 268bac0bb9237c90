#include "exoid/experiments/commands/help_formatter.hpp"

#include <algorithm>
#include <sstream>

namespace exoid::experiments {

std::string readableTypeName(const std::string& type_name) {
  const std::string::size_type in = type_name.find("value in {");
  if (type_name.rfind("ENUM:", 0) == 0 && in != std::string::npos) {
    const std::string::size_type open = in + 10, close = type_name.find('}', open);
    std::string keys, item;
    std::istringstream list(type_name.substr(open, close - open));
    while (std::getline(list, item, ',')) keys += (keys.empty() ? "" : "|") + item.substr(0, item.find("->"));
    return keys;
  }
  const std::string::size_type colon = type_name.find(':');
  if (colon != std::string::npos) {
    const std::string head = type_name.substr(0, colon);
    if (head == "TEXT" || head == "FLOAT" || head == "INT" || head == "UINT" || head == "NUMBER") return type_name.substr(colon + 1);
  }
  return type_name;
}

std::string readableDefault(const std::string& default_str, const std::string& shipped_dir) {
  if (shipped_dir.empty()) return default_str;
  const std::string prefix = shipped_dir.back() == '/' ? shipped_dir : shipped_dir + "/";
  if (default_str.size() > prefix.size() && default_str.compare(0, prefix.size(), prefix) == 0) {
    return "the shipped " + default_str.substr(prefix.size());
  }
  return default_str;
}

std::string wrapText(const std::string& text, std::size_t width) {
  std::string out, line;
  std::istringstream lines(text);
  bool first_line = true;
  while (std::getline(lines, line)) {
    if (!first_line) out += '\n';
    first_line = false;
    std::istringstream words(line);
    std::string word, current;
    while (words >> word) {
      if (!current.empty() && current.size() + 1 + word.size() > width) {
        out += current + '\n';
        current.clear();
      }
      current += (current.empty() ? "" : " ") + word;
    }
    out += current;
  }
  return out;
}

std::string HelpFormatter::make_option_name(const CLI::Option* opt, bool is_positional) const {
  std::string name = CLI::Formatter::make_option_name(opt, is_positional);
  for (std::string::size_type open; (open = name.find('{')) != std::string::npos;) {  // "--no-filter{false}"
    const std::string::size_type close = name.find('}', open);
    name.erase(open, close == std::string::npos ? std::string::npos : close - open + 1);
  }
  return name;
}

std::string HelpFormatter::make_option_opts(const CLI::Option* opt) const {
  if (!opt->get_option_text().empty() || opt->get_type_size() == 0) return CLI::Formatter::make_option_opts(opt);
  std::ostringstream out;
  const std::string type = readableTypeName(opt->get_type_name());
  if (!type.empty()) out << " " << type;
  if (!opt->get_default_str().empty()) out << " (default " << readableDefault(opt->get_default_str(), shipped_dir_) << ")";
  if (opt->get_expected_max() == CLI::detail::expected_max_vector_size) out << " ...";
  if (opt->get_required()) out << " REQUIRED";
  return out.str();
}

std::string HelpFormatter::make_option_desc(const CLI::Option* opt) const {
  const std::size_t width = kLineWidth > get_column_width() + 2 ? kLineWidth - get_column_width() - 2 : 40;
  return wrapText(opt->get_description(), width);
}

std::string HelpFormatter::make_subcommand(const CLI::App* sub) const {
  const std::size_t width = kLineWidth > get_column_width() + 2 ? kLineWidth - get_column_width() - 2 : 40;
  std::string flat = sub->get_description();
  std::replace(flat.begin(), flat.end(), '\n', ' ');
  std::stringstream out;
  CLI::detail::format_help(out, sub->get_display_name(true), wrapText(flat, width), get_column_width());
  return out.str();
}

std::string HelpFormatter::make_description(const CLI::App* app) const {
  return wrapText(CLI::Formatter::make_description(app), kLineWidth) + "\n\n";
}

}  // namespace exoid::experiments
