#pragma once
// One table cell's text, the same in every CSV and JSON table exoid writes: a number that is not
// finite is an empty CSV cell and a JSON null (never "nan", which neither format has).
#include <nlohmann/json.hpp>

#include <string>

namespace exoid::experiments {

/// 10 significant digits ("%.10g"); empty when v is NaN or infinite.
std::string csvNumber(double v);
/// s as one CSV field: quoted (quotes doubled) when it holds a comma, a quote or a line break.
std::string csvField(const std::string& s);
/// v, or null when it is NaN or infinite.
nlohmann::json jsonNumber(double v);

}  // namespace exoid::experiments
