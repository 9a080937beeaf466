#pragma once
// Internal to RadarNDT::io: a Boreas pose CSV parsed from text already read (readTrajectory reads
// a file once, then tells a Boreas pose CSV by its header).
#include <string>
#include <vector>

#include "radar_ndt/io/boreas_ground_truth.h"

namespace radar_ndt {
namespace detail {

/// readBoreasPoses on `text`, the whole of the file `path` (named in errors).
std::vector<BoreasPose> parseBoreasPoses(const std::string& path, const std::string& text);

}  // namespace detail
}  // namespace radar_ndt
