#pragma once
// radar_paper_tables' three jobs, each reproducing a table on the data given with every method
// through the same front-end, guesses and failure handling (docs/apps.md):
//  - runScanningTable: pw-ndt against PCL's NDT and ICP (documented settings and the best grid of
//    a sweep) and the paper's ablations on every scanning sequence (KITTI metric, frame errors);
//  - runNuScenesTable: the paper's nuScenes table (N = 1, 3, 5, 10 for PCL's ICP and pw-ndt, N = 1
//    for the Doppler integral and rapp-ndt; 1m metric, mean over scenes), then the default pipeline;
//  - runNoiseCalibration: the fusion's covariances calibrated on every scene and checked leaving
//    each scene out (motion_noise.h).
// Each prints a markdown table, or with `json_out` one JSON object.

#include <string>
#include <vector>

#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/scanning_sequence.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/scanning_run.h"

namespace radar_ndt {
namespace apps {

/// `base` on every sequence of `dirs` (with ground truth), then each PCL matcher at its
/// documented grid and at the best of a sweep scored on the first `sweep_scans` scans of the first
/// sequence, then the ablations, one setting changed each.
int runScanningTable(const ScanningRunOptions& base, ScanFormat format, const std::vector<std::string>& dirs,
                     std::size_t sweep_scans, bool json_out, bool progress_on);

/// The paper's table from `options` (each method through withMethod), on `scenes`.
int runNuScenesTable(const AutomotiveRunOptions& options, const NuScenesDataset& dataset,
                     const std::vector<const NuScenesScene*>& scenes, bool json_out, bool progress_on);

/// --noise-calibration: calibrated on all scenes, checked leaving each out (mean NEES; 3 is
/// calibrated), then what the match adds to the Doppler motion per axis.
int runNoiseCalibration(const AutomotiveRunOptions& options, const NuScenesDataset& dataset,
                        const std::vector<const NuScenesScene*>& scenes, bool json_out, bool progress_on);

}  // namespace apps
}  // namespace radar_ndt
