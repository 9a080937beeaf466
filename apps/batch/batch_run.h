#pragma once
// radar_batch's execution: what a task's state is on disk (the resume decision), running one task
// (its log, its result written atomically last), and the engines' inputs (GNU parallel's command
// line, the Slurm job-array script).

#include <string>
#include <vector>

#include "batch_plan.h"

namespace radar_ndt {
namespace batch {

enum class TaskState {
  Complete,  ///< result.json for the same command, exit code 0: skipped by `run`
  Failed,    ///< result.json for the same command with a non-zero exit code: run again
  Stale,     ///< result.json for another command (the plan changed): run again
  Missing,   ///< no result.json (never run, or killed before it finished): run again
};
const char* toString(TaskState state);

/// The state of `task` in `run_dir` (a result.json that cannot be parsed counts as Missing).
TaskState taskState(const std::string& run_dir, const Task& task);

/// Runs `task` with `threads` (appended as --threads, not part of the command's identity):
/// stdout and stderr into tasks/<id>/log.txt, then tasks/<id>/result.json written atomically:
/// {id, command, exit_code, seconds, threads, summary (radar_odometry's JSON, or null)}.
/// Returns the exit code (128 + signal for a killed app; 127 when it cannot be started).
int executeTask(const std::string& run_dir, const Task& task, int threads);

/// GNU parallel's argv: runs `radar_batch exec RUN ID` for each line of `ids_file`, `jobs` at a
/// time, with its job log in the run folder.
std::vector<std::string> parallelCommand(const std::string& parallel, const std::string& self,
                                         const std::string& run_dir, const std::string& ids_file, int jobs,
                                         int threads);

struct SlurmOptions {
  int throttle = 0;  ///< at most this many array tasks at once (0: no limit)
  std::string time = "01:00:00";
  std::string memory = "2G";
  int cpus_per_task = 1;
  std::string partition, account, job_name = "radar_batch";
};
/// The job-array script: one array index per line of `ids_file`, logs in run_dir/slurm/.
std::string slurmScript(const SlurmOptions& options, const std::string& self, const std::string& run_dir,
                        const std::string& ids_file, std::size_t count);

}  // namespace batch
}  // namespace radar_ndt
