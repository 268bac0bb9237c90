#pragma once
// Output files appear whole or not at all: written to a temporary beside the target, then renamed.
#include <functional>
#include <iosfwd>
#include <string>

namespace exoid::ident {

/// Calls `write` on a stream to a temporary file in the target's folder and renames it onto
/// `path` when the stream is good. On any failure the temporary is removed and
/// std::runtime_error names the path; an existing file at `path` is left untouched.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace exoid::ident
