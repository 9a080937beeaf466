#pragma once
// The pipeline options radar_odometry, radar_paper_tables and radar_batch share: one command-line
// option per field the library's run options' tables name (AutomotiveRunOptions,
// ScanningRunOptions; field_options.h), applied over the library's defaults only when given, so a
// setting's name, help, range and default live in one place, its field table. No algorithm lives
// here.

#include <string>
#include <vector>

#include <boost/program_options.hpp>

#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/run_settings.h"
#include "radar_ndt/pipeline/scanning_run.h"

namespace radar_ndt {
namespace apps {

enum class Pipeline { Automotive, Scanning };

/// "nuscenes" (automotive) or "oxford" / "radiate" / "boreas" (scanning); throws std::invalid_argument.
Pipeline pipelineOf(const std::string& format);

/// Adds --format, --dataroot, --sequence, --version, --scene, every pipeline setting the field
/// tables name (their help gives the library's defaults), --no-prefetch and --quiet.
void addPipelineOptions(boost::program_options::options_description& options);

/// Every pipeline option as a markdown table: option, the field it sets, the pipeline or layout,
/// its meaning and default (radar_odometry --list-options; docs/apps.md holds it).
std::string pipelineOptionsMarkdown();

/// The settings the command line gives for the automotive pipeline (nuscenes, rosbag) and the
/// scanning one (--format's layout): each given option's field and typed value. An option that
/// sets nothing for --format is refused (std::invalid_argument naming it).
Settings automotiveSettings(const boost::program_options::variables_map& vm);
Settings scanningSettings(const boost::program_options::variables_map& vm);
/// Whether the command line runs the 6-DoF pipeline: --format rosbag with a 6-DoF --method.
bool asksInertial(const boost::program_options::variables_map& vm);
Settings inertialSettings(const boost::program_options::variables_map& vm);

/// The automotive run options the command line asks for (nuscenes); throws std::invalid_argument
/// naming a bad value.
AutomotiveRunOptions automotiveOptions(const boost::program_options::variables_map& vm);
/// The scanning run options the command line asks for (oxford, radiate, boreas), over `base` (the
/// library's defaults for the sequence's radar: defaultScanningOptions); a layout's own settings
/// (--bin-size, --bins) apply to --format's.
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
