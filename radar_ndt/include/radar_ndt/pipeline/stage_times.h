#pragma once
// Per-cycle or per-scan wall-clock times of a run's stages, as both dataset runners report them.

namespace radar_ndt {

struct StageTimes {
  double read_ms = 0, front_end_ms = 0, submap_ms = 0, match_ms = 0;
  double total() const { return read_ms + front_end_ms + submap_ms + match_ms; }
};

}  // namespace radar_ndt
