#pragma once
// The pipeline options radar_odometry and radar_paper_tables share: one command-line option per
// setting of the library's run options (AutomotiveRunOptions, ScanningRunOptions), applied over the
// library's defaults only when given, so the defaults and their range checks live in one place,
// the library. No algorithm lives here.

#include <string>
#include <vector>

#include <boost/program_options.hpp>

#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/scanning_run.h"

namespace radar_ndt {
namespace apps {

enum class Pipeline { Automotive, Scanning };

/// "nuscenes" (automotive) or "oxford" / "radiate" / "boreas" (scanning); throws std::invalid_argument.
Pipeline pipelineOf(const std::string& format);

/// Adds --format, --dataroot, --sequence, --version, --scene, --method and every pipeline
/// setting (their help gives the library's defaults), and --quiet.
void addPipelineOptions(boost::program_options::options_description& options);

/// The automotive run options the command line asks for (nuscenes); throws std::invalid_argument
/// naming a bad value.
AutomotiveRunOptions automotiveOptions(const boost::program_options::variables_map& vm);
/// The scanning run options the command line asks for (oxford, radiate, boreas), over `base` (the
/// library's defaults for the sequence's radar: defaultScanningOptions).
ScanningRunOptions scanningOptions(const boost::program_options::variables_map& vm,
                                   const ScanningRunOptions& base = {});

/// The dataroot --dataroot and --version name (std::invalid_argument without --dataroot).
NuScenesDataset openDataset(const boost::program_options::variables_map& vm);
/// The scenes --scene names: one, or every scene of the dataset for "all".
std::vector<const NuScenesScene*> selectScenes(const NuScenesDataset& dataset,
                                               const boost::program_options::variables_map& vm);

/// --sequence's directories (at least one; std::invalid_argument otherwise).
std::vector<std::string> sequenceDirs(const boost::program_options::variables_map& vm);

/// A progress bar on stderr (when enabled), every 10 steps and at the end.
struct Progress {
  bool enabled;
  std::string label;
  void operator()(std::size_t done, std::size_t total) const;
};

}  // namespace apps
}  // namespace radar_ndt
