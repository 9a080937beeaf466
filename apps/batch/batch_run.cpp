#include "batch_run.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/pipeline/inertial_run.h"

namespace radar_ndt {
namespace batch {

namespace fs = std::filesystem;
using nlohmann::json;

const char* toString(TaskState s) {
  switch (s) {
    case TaskState::Complete: return "complete";
    case TaskState::Failed: return "failed";
    case TaskState::Stale: return "stale";
    case TaskState::Missing: return "missing";
  }
  return "?";
}

TaskState taskState(const std::string& run_dir, const Task& task) {
  std::ifstream in(fs::path(taskDir(run_dir, task.id)) / "result.json");
  if (!in) return TaskState::Missing;
  try {
    const json r = json::parse(in);
    if (r.at("command").get<std::string>() != joinShellWords(task.command)) return TaskState::Stale;
    return r.at("exit_code").get<int>() == 0 && r.at("summary").is_object() ? TaskState::Complete : TaskState::Failed;
  } catch (const json::exception&) {
    return TaskState::Missing;
  }
}

int executeTask(const std::string& run_dir, const Task& task, int threads) {
  const fs::path dir = taskDir(run_dir, task.id);
  fs::create_directories(dir);
  const std::string log = (dir / "log.txt").string(), out = (dir / "stdout.json").string();
  std::vector<std::string> argv = task.command;
  // A 6-DoF run is one stream on one thread: radar_odometry refuses --threads for it.
  if (!isInertialMethod(task.method)) argv.insert(argv.end(), {"--threads", std::to_string(threads)});
  const auto t0 = std::chrono::steady_clock::now();
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int log_fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int out_fd = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (log_fd < 0 || out_fd < 0) _exit(127);
    dup2(out_fd, 1);
    dup2(log_fd, 2);
    std::vector<char*> args;
    for (auto& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    execv(args[0], args.data());
    dprintf(2, "radar_batch: cannot start %s\n", args[0]);
    _exit(127);
  }
  int status = 0, code = 127;
  if (pid > 0 && waitpid(pid, &status, 0) == pid)
    code = WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 127;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  json summary = nullptr;
  {
    std::ifstream in(out);
    std::stringstream text;
    text << in.rdbuf();
    if (code == 0) summary = json::parse(text.str(), nullptr, false);
    if (summary.is_discarded() || (code == 0 && !summary.is_object())) {
      summary = nullptr;
      if (code == 0) code = 125;  // the app said it succeeded, but printed no summary
    }
  }
  fs::remove(out);
  const json result = {{"id", task.id},      {"command", joinShellWords(task.command)},
                       {"exit_code", code},  {"seconds", seconds},
                       {"threads", threads}, {"summary", summary}};
  writeFileAtomically((dir / "result.json").string(), result.dump(2) + "\n");
  return code;
}

std::vector<std::string> parallelCommand(const std::string& parallel, const std::string& self,
                                         const std::string& run_dir, const std::string& ids_file, int jobs,
                                         int threads) {
  // -q: parallel runs the command through a shell; quoted, a run folder with spaces stays one word.
  return {parallel,
          "--will-cite",
          "-q",
          "--halt",
          "never",
          "-j",
          std::to_string(jobs),
          "--joblog",
          (fs::path(run_dir) / "parallel.joblog").string(),
          self,
          "exec",
          run_dir,
          "{}",
          "--threads",
          std::to_string(threads),
          "::::",
          ids_file};
}

std::string slurmScript(const SlurmOptions& o, const std::string& self, const std::string& run_dir,
                        const std::string& ids_file, std::size_t count) {
  const std::string logs = (fs::path(run_dir) / "slurm" / "logs").string();
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# radar_batch: one array index per task of " << ids_file << "\n"
    << "#SBATCH --job-name=" << o.job_name << "\n"
    << "#SBATCH --array=1-" << count << (o.throttle > 0 ? "%" + std::to_string(o.throttle) : "") << "\n"
    << "#SBATCH --time=" << o.time << "\n"
    << "#SBATCH --mem=" << o.memory << "\n"
    << "#SBATCH --cpus-per-task=" << o.cpus_per_task << "\n"
    << "#SBATCH --output=" << logs << "/%A_%a.out\n";
  if (!o.partition.empty()) s << "#SBATCH --partition=" << o.partition << "\n";
  if (!o.account.empty()) s << "#SBATCH --account=" << o.account << "\n";
  s << "set -euo pipefail\n"
    << "id=$(sed -n \"${SLURM_ARRAY_TASK_ID}p\" " << shellQuote(ids_file) << ")\n"
    << "exec " << shellQuote(self) << " exec " << shellQuote(run_dir) << " \"$id\" --threads " << o.cpus_per_task
    << "\n";
  return s.str();
}

}  // namespace batch
}  // namespace radar_ndt
