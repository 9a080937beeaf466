#pragma once
// Internal to RadarNDT::io: the whole of a file as bytes, for the readers that parse from memory.
#include <string>

namespace radar_ndt {
namespace detail {

/// Throws IoError naming the file when it cannot be opened or read.
std::string readWholeFile(const std::string& path);
/// The same into `bytes`, reusing its storage.
void readWholeFile(const std::string& path, std::string& bytes);

}  // namespace detail
}  // namespace radar_ndt
