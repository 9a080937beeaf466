#pragma once
// radar_batch's plan: the sequences of a dataset folder x methods x a grid of settings expanded
// into tasks, each one exact radar_odometry command with a stable id, written into a run folder
// (plan.json, tasks.tsv) and read back by `run` and `report`. No algorithm lives here.

#include <string>
#include <utility>
#include <vector>

namespace radar_ndt {
namespace batch {

/// One `--set name=v1,v2,...`: a radar_odometry option (without its dashes) and its values.
struct SettingAxis {
  std::string name;
  std::vector<std::string> values;
  /// A switch of radar_odometry's (--imu): its values are on and off, a task's command carries
  /// `--name` for on and nothing for off (radar_batch plan marks it; plan.json keeps it).
  bool is_switch = false;
};
/// "grid=3,3.75" → {grid, {3, 3.75}}; std::invalid_argument for a malformed one.
SettingAxis parseSettingAxis(const std::string& text);

struct Sequence {
  std::string name;  ///< the folder's name (scanning), the scene's (nuscenes), the bag's stem (rosbag)
  std::string path;  ///< the folder (scanning), the dataroot (nuscenes) or the bag (rosbag)
};

/// The sequences of `root` for `format`: nuscenes, every scene of the dataroot; oxford, radiate,
/// boreas, every folder (root itself, or its subfolders) laid out as the format's reader wants
/// (radar.timestamps; Navtech_Polar.txt; radar/ with PNGs); rosbag, root itself when it is a file,
/// else every *.bag of the folder; by name. `names` keeps only those
/// (std::invalid_argument naming one that is not there); `glob` (fnmatch) only those matching.
std::vector<Sequence> findSequences(const std::string& format, const std::string& root,
                                    const std::vector<std::string>& names = {}, const std::string& glob = "");

struct Task {
  std::string id;  ///< stable: a hash of sequence, method and settings (not of paths or order)
  std::string sequence;
  std::string method;
  std::vector<std::pair<std::string, std::string>> settings;  ///< in the plan's axis order
  std::vector<std::string> command;                           ///< radar_odometry's argv, outputs included
  /// "grid=3 power-shift=0.333", or "default" without settings.
  std::string settingsText() const;
};

struct PlanRequest {
  std::string format;
  std::string root;
  std::vector<std::string> sequences;  ///< names; empty: all
  std::string glob;
  std::string sensors;  ///< rosbag: the sensor description every task reads (absolute, or preset:NAME)
  std::vector<std::string> methods{"pw-ndt"};
  std::vector<SettingAxis> settings;
  std::string odometry_app;  ///< the radar_odometry every task runs
  std::string run_dir;       ///< absolute; tasks write into run_dir/tasks/<id>/
};

/// Every sequence x method x setting combination, in that nesting order, with its command:
/// radar_odometry --format F (--sequence DIR | --dataroot ROOT --scene NAME | --bag BAG --sensors S)
/// --method M [--NAME VALUE ... | --SWITCH ...] [--eval --metric all] --json -q --out RUN/tasks/ID/trajectory.txt
/// (--eval when the sequence has ground truth: for bags, when the description names a topic). Throws
/// std::invalid_argument for duplicate ids.
std::vector<Task> expandPlan(const PlanRequest& request, const std::vector<Sequence>& sequences);

/// A task's id: 16 hex digits of FNV-1a over sequence, method and settings.
std::string taskId(const std::string& sequence, const std::string& method,
                   const std::vector<std::pair<std::string, std::string>>& settings);

/// `arg` for a POSIX shell: as it is when it is only safe characters, else in single quotes ('\''
/// for a quote inside). splitShellWords reads back exactly what joinShellWords wrote.
std::string shellQuote(const std::string& arg);
std::string joinShellWords(const std::vector<std::string>& words);
/// Splits a line of words joined by joinShellWords (plain words and single-quoted parts);
/// std::invalid_argument for an unterminated quote.
std::vector<std::string> splitShellWords(const std::string& line);

struct Plan {
  PlanRequest request;
  std::vector<Sequence> sequences;
  std::vector<Task> tasks;
  std::string version, git_revision;
};

/// Writes run_dir/plan.json and run_dir/tasks.tsv (id, sequence, method, settings, command),
/// each atomically.
void writePlan(const Plan& plan);
/// Reads them back (IoError naming the file for a missing or malformed one).
Plan readPlan(const std::string& run_dir);

/// The folder of a task's results: run_dir/tasks/<id>.
std::string taskDir(const std::string& run_dir, const std::string& id);

}  // namespace batch
}  // namespace radar_ndt
