#pragma once
#include <string>

namespace radar_ndt {

/// Writes `content` to a temporary file beside `path` (`path.tmp.<pid>`), flushes it to disk, then
/// renames it over `path`, so readers never see a half-written file under the final name. Throws
/// IoError naming the file on any failure (and removes the temporary file).
void writeFileAtomically(const std::string& path, const std::string& content);

}  // namespace radar_ndt
