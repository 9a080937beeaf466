#pragma once
#include <string>

#include "radar_ndt/evaluation/metrics.h"
#include "radar_ndt/evaluation/report.h"

namespace radar_ndt {

/// Writes an SVG (atomically) with the top view of both trajectories (equal axes, start marked,
/// estimate as given, not aligned) and, when the report has the KITTI metric, the translational
/// and rotational error per segment length; otherwise the frame-to-frame translational error along
/// the sequence; for a 6-DoF evaluation (the report has the 6-DoF ATE), the side view below: both
/// heights over the distance travelled. Throws IoError when the file cannot be written.
void writeEvaluationSvg(const std::string& path, const PosePairs& pairs, const EvaluationReport& report,
                        const std::string& title = "");

}  // namespace radar_ndt
