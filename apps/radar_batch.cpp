// radar_batch: whole datasets in one command. `plan` expands sequences x methods x a grid of
// settings into tasks (each one exact radar_odometry command) in a run folder; `run` runs the
// tasks without a complete result, serially, with GNU parallel or as a Slurm job array; `report`
// aggregates the results into summary.csv, summary.md and summary.svg. docs/batch.md.

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <thread>

#include "app_common.h"
#include "batch/batch_plan.h"
#include "batch/batch_report.h"
#include "batch/batch_run.h"
#include "pipeline_options.h"
#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/pipeline/inertial_run.h"

#ifndef RADAR_NDT_VERSION
#define RADAR_NDT_VERSION "unknown"
#endif
#ifndef RADAR_NDT_SOURCE_DIR
#define RADAR_NDT_SOURCE_DIR "."
#endif

using namespace radar_ndt;
using namespace radar_ndt::batch;
namespace fs = std::filesystem;
namespace po = boost::program_options;

namespace {

std::string selfPath() {
  return fs::canonical("/proc/self/exe").string();
}

/// Runs argv, its output passed through; its exit code (127 when it cannot be started).
int spawn(const std::vector<std::string>& argv) {
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> args;
    for (auto a : argv) args.push_back(strdup(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    std::fprintf(stderr, "radar_batch: cannot start %s\n", args[0]);
    _exit(127);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) != pid) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// The output of a shell command, stderr included, trailing white space removed; its exit code in
/// `*code` when given, else "" when it fails.
std::string capture(const std::string& command, int* code = nullptr) {
  std::string out;
  int status = -1;
  if (FILE* p = popen((command + " 2>&1").c_str(), "r")) {
    char buf[256];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    status = pclose(p);
  }
  const int exit_code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : 127;
  if (code)
    *code = exit_code;
  else if (exit_code != 0)
    return "";
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out;
}

/// Polls squeue every second until Slurm lists no task of `job` any more (a job Slurm no longer
/// knows has ended too). sbatch --wait would do it, but polls ever more slowly: tens of seconds
/// late on a short array.
void waitForJob(const std::string& job) {
  int errors = 0;
  for (;;) {
    std::this_thread::sleep_for(std::chrono::seconds(1));
    int code = 0;
    const std::string out = capture("squeue -h -r -j " + job + " -o %i", &code);
    if (code == 0 && out.empty()) return;
    if (code != 0 && out.find("Invalid job id") != std::string::npos) return;
    if (code != 0 && ++errors > 60) throw std::runtime_error("squeue keeps failing: " + out);
  }
}

std::vector<std::string> commaList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

/// Whether the plan's methods are 6-DoF ones (a bag's 4D radar: pw-ndt-3d, doppler-imu, ...); each
/// one known, and all of one kind: the two kinds run different pipelines with different settings.
bool checkMethods(const PlanRequest& r) {
  std::size_t six_dof = 0;
  for (const auto& m : r.methods) {
    if (r.format == "rosbag" && isInertialMethod(m))
      ++six_dof;
    else
      findMatcher(m);  // std::invalid_argument naming an unknown one
  }
  if (six_dof > 0 && six_dof < r.methods.size())
    throw std::invalid_argument("--method: 6-DoF methods (" + inertialMethodChoices() +
                                ") and planar ones run different pipelines; plan them in separate runs");
  return six_dof > 0;
}

/// Every combination of settings parsed as radar_odometry parses them, so a bad name or value is
/// refused now, not in every task. A switch (--imu) is marked so, its values on and off.
void checkSettings(PlanRequest& r, bool six_dof) {
  po::options_description opts;
  apps::addPipelineOptions(opts);
  for (auto& axis : r.settings) {
    const po::option_description* option = opts.find_nothrow(axis.name, false);
    if (!option)
      throw std::invalid_argument("--set " + axis.name + ": not a pipeline option of radar_odometry (see its --help)");
    axis.is_switch = option->semantic()->max_tokens() == 0;
    for (const auto& v : axis.values) {
      std::vector<std::string> args{"radar_odometry", "--format", r.format};
      if (six_dof) args.insert(args.end(), {"--method", r.methods.front()});
      if (!axis.is_switch)
        args.insert(args.end(), {"--" + axis.name, v});
      else if (v == "on")
        args.push_back("--" + axis.name);
      else if (v != "off")
        throw std::invalid_argument("--set " + axis.name + "=" + v + ": --" + axis.name +
                                    " is a switch: its values are on and off");
      po::variables_map vm;
      std::vector<const char*> argv;
      for (const auto& a : args) argv.push_back(a.c_str());
      po::store(po::parse_command_line(static_cast<int>(argv.size()), argv.data(), opts), vm);
      po::notify(vm);
      if (six_dof) {
        apps::inertialSettings(vm);
        continue;
      }
      // A bag runs the pipeline of its described radar: a scanning radar's, or the automotive one.
      const bool scanning_bag = r.format == "rosbag" && !r.sensors.empty() &&
                                readSensorDescription(r.sensors).radars[0].kind == RadarKind::Scanning;
      if (apps::pipelineOf(r.format) == apps::Pipeline::Automotive && !scanning_bag)
        apps::automotiveOptions(vm);
      else
        apps::scanningOptions(vm);
    }
  }
}

po::options_description planOptions() {
  po::options_description o("radar_batch plan");
  // clang-format off
  o.add_options()
    ("help,h", "this help")
    ("format", po::value<std::string>()->required(), "nuscenes | rosbag | oxford | radiate | boreas")
    ("root", po::value<std::string>()->required(),
     "nuscenes: the dataroot (each scene a sequence); rosbag: a bag, or a folder of *.bag files (each a sequence); "
     "scanning: a sequence folder, or a folder of them")
    ("sensors", po::value<std::string>(), "rosbag: the sensor description every bag is read with (FILE.yaml or preset:NAME)")
    ("sequences", po::value<std::string>(), "comma-separated sequence (scene) names (default: every one found)")
    ("glob", po::value<std::string>(), "only sequences whose name matches this pattern (fnmatch, e.g. '2019-01-1*')")
    ("method", po::value<std::string>()->default_value("pw-ndt"),
     "comma-separated methods (radar_odometry --method): planar ones, or (rosbag, a 4D radar) 6-DoF ones")
    ("set", po::value<std::vector<std::string>>()->composing(),
     "NAME=V1,V2,...: a radar_odometry pipeline option and its values, repeatable; the tasks run every "
     "combination (e.g. --set grid=3,3.75 --set power-shift=0,0.333); a switch takes on and off (--set imu=off,on)")
    ("odometry-app", po::value<std::string>(), "the radar_odometry to run (default: the one beside radar_batch)")
    ("out", po::value<std::string>()->required(), "the run folder (created; plan.json, tasks.tsv, tasks/)");
  // clang-format on
  return o;
}

int plan(int argc, char** argv) {
  const po::options_description o = planOptions();
  po::variables_map vm;
  const int parsed = apps::parseCommandLine(
      argc, argv, o, "Usage: radar_batch plan --format F --root DIR --out RUN [--method M1,M2] [--set NAME=V1,V2]...",
      vm);
  if (parsed >= 0) return parsed;
  Plan p;
  auto& r = p.request;
  r.format = vm["format"].as<std::string>();
  r.root = fs::absolute(vm["root"].as<std::string>()).lexically_normal().string();
  if (vm.count("sequences")) r.sequences = commaList(vm["sequences"].as<std::string>());
  if (vm.count("glob")) r.glob = vm["glob"].as<std::string>();
  if (vm.count("sensors")) {
    r.sensors = vm["sensors"].as<std::string>();
    if (r.sensors.rfind("preset:", 0) != 0) r.sensors = fs::absolute(r.sensors).lexically_normal().string();
    readSensorDescription(r.sensors);  // a bad description refused now, not in every task
  }
  r.methods = commaList(vm["method"].as<std::string>());
  const bool six_dof = checkMethods(r);
  if (vm.count("set"))
    for (const auto& s : vm["set"].as<std::vector<std::string>>()) r.settings.push_back(parseSettingAxis(s));
  r.odometry_app = vm.count("odometry-app") ? fs::absolute(vm["odometry-app"].as<std::string>()).string()
                                            : (fs::path(selfPath()).parent_path() / "radar_odometry").string();
  r.run_dir = fs::absolute(vm["out"].as<std::string>()).lexically_normal().string();
  checkSettings(r, six_dof);
  p.sequences = findSequences(r.format, r.root, r.sequences, r.glob);
  p.tasks = expandPlan(r, p.sequences);
  p.version = RADAR_NDT_VERSION;
  p.git_revision = capture("git -C '" RADAR_NDT_SOURCE_DIR "' rev-parse HEAD 2>/dev/null");
  if (p.git_revision.empty()) p.git_revision = "unknown";
  writePlan(p);
  std::printf("%s: %zu tasks (%zu sequences x %zu methods x %zu settings)\n", r.run_dir.c_str(), p.tasks.size(),
              p.sequences.size(), r.methods.size(), p.tasks.size() / p.sequences.size() / r.methods.size());
  return 0;
}

/// Counts of the tasks' states, printed; true when every task is complete.
bool printStates(const Plan& p, const char* when) {
  std::size_t n[4] = {0, 0, 0, 0};
  for (const auto& t : p.tasks) ++n[static_cast<int>(taskState(p.request.run_dir, t))];
  std::printf("%s: %zu tasks, %zu complete, %zu failed, %zu without a result\n", when, p.tasks.size(), n[0], n[1],
              n[2] + n[3]);
  return n[0] == p.tasks.size();
}

po::options_description runOptions() {
  po::options_description o("radar_batch run RUN");
  // clang-format off
  o.add_options()
    ("help,h", "this help")
    ("run", po::value<std::string>()->required(), "the run folder radar_batch plan wrote")
    ("engine", po::value<std::string>()->default_value("parallel"),
     "parallel (GNU parallel on this machine) | slurm (a job array, sbatch) | serial (one task after another)")
    ("jobs,j", po::value<int>()->default_value(0), "parallel: tasks at once (0: one per core)")
    ("threads", po::value<int>()->default_value(1), "threads each task runs with (radar_odometry --threads; outputs do not depend on it)")
    ("parallel", po::value<std::string>()->default_value("parallel"), "parallel: the GNU parallel program")
    ("throttle", po::value<int>()->default_value(0), "slurm: at most this many array tasks at once (--array=1-N%T; 0: no limit)")
    ("time", po::value<std::string>()->default_value("01:00:00"), "slurm: time limit per task")
    ("mem", po::value<std::string>()->default_value("2G"), "slurm: memory per task")
    ("partition", po::value<std::string>()->default_value(""), "slurm: partition (default: the cluster's)")
    ("account", po::value<std::string>()->default_value(""), "slurm: account")
    ("wait", po::bool_switch(), "slurm: wait until the array has finished (squeue, every second), then print the states")
    ("dry-run", po::bool_switch(), "slurm: print the job script, submit nothing");
  // clang-format on
  return o;
}

/// The pending tasks as a Slurm job array (--engine slurm); true when it waited for the job to end
/// (the states are worth printing), false for a dry run or a job left running.
bool runOnSlurm(const po::variables_map& vm, const std::string& dir, const std::vector<const Task*>& pending,
                const std::string& ids, int threads) {
  fs::create_directories(fs::path(dir) / "slurm" / "logs");
  std::size_t n = 1;
  while (fs::exists(fs::path(dir) / "slurm" / ("pending-" + std::to_string(n) + ".txt"))) ++n;
  const std::string ids_file = (fs::path(dir) / "slurm" / ("pending-" + std::to_string(n) + ".txt")).string();
  SlurmOptions so;
  so.throttle = vm["throttle"].as<int>();
  so.time = vm["time"].as<std::string>();
  so.memory = vm["mem"].as<std::string>();
  so.cpus_per_task = threads;
  so.partition = vm["partition"].as<std::string>();
  so.account = vm["account"].as<std::string>();
  const std::string script = slurmScript(so, selfPath(), dir, ids_file, pending.size());
  if (vm["dry-run"].as<bool>()) {
    std::cout << script;
    return false;
  }
  writeFileAtomically(ids_file, ids);
  const std::string script_file = (fs::path(dir) / "slurm" / ("array-" + std::to_string(n) + ".sh")).string();
  writeFileAtomically(script_file, script);
  int code = 0;
  const std::string submitted = capture("sbatch --parsable " + shellQuote(script_file), &code);
  const std::string job = submitted.substr(0, submitted.find(';'));  // "ID" or "ID;cluster"
  if (code != 0 || job.empty() || job.find_first_not_of("0123456789") != std::string::npos)
    throw std::runtime_error("sbatch did not submit " + script_file + " (exit " + std::to_string(code) +
                             "): " + submitted);
  std::printf("Submitted batch job %s\n", job.c_str());
  if (!vm["wait"].as<bool>()) return false;
  waitForJob(job);
  return true;
}

int run(int argc, char** argv) {
  const po::options_description o = runOptions();
  po::positional_options_description pos;
  pos.add("run", 1);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(argc, argv).options(o).positional(pos).run(), vm);
    if (vm.count("help")) {
      std::cout << "Usage: radar_batch run RUN [--engine parallel|slurm|serial] [options]\n\n" << o << std::endl;
      return 0;
    }
    po::notify(vm);
  } catch (const po::error& e) {
    std::fprintf(stderr, "radar_batch run: %s (see --help)\n", e.what());
    return 1;
  }
  const Plan p = readPlan(vm["run"].as<std::string>());
  const std::string dir = p.request.run_dir, engine = vm["engine"].as<std::string>();
  const int threads = vm["threads"].as<int>();
  if (threads < 1) throw std::invalid_argument("--threads must be at least 1");
  std::vector<const Task*> pending;
  for (const auto& t : p.tasks)
    if (taskState(dir, t) != TaskState::Complete) pending.push_back(&t);
  std::printf("%zu tasks: %zu complete (skipped), %zu to run with %s\n", p.tasks.size(),
              p.tasks.size() - pending.size(), pending.size(), engine.c_str());
  if (pending.empty()) return 0;
  std::string ids;
  for (const Task* t : pending) ids += t->id + "\n";
  if (engine == "serial") {
    for (const Task* t : pending) {
      const int code = executeTask(dir, *t, threads);
      std::printf("%s %s %s %s: exit %d\n", t->id.c_str(), t->sequence.c_str(), t->method.c_str(),
                  t->settingsText().c_str(), code);
    }
  } else if (engine == "parallel") {
    const std::string ids_file = (fs::path(dir) / "pending.txt").string();
    writeFileAtomically(ids_file, ids);
    int jobs = vm["jobs"].as<int>();
    if (jobs <= 0) jobs = static_cast<int>(std::max(1L, sysconf(_SC_NPROCESSORS_ONLN)));
    const int code = spawn(parallelCommand(vm["parallel"].as<std::string>(), selfPath(), dir, ids_file, jobs, threads));
    if (code == 127 || code == 255)
      throw std::runtime_error("GNU parallel did not run (exit " + std::to_string(code) +
                               "): is it installed (Debian: parallel)?");
  } else if (engine == "slurm") {
    if (!runOnSlurm(vm, dir, pending, ids, threads)) return 0;
  } else {
    throw std::invalid_argument("--engine must be parallel, slurm or serial, not '" + engine + "'");
  }
  return printStates(p, "run") ? 0 : 1;
}

int report(int argc, char** argv) {
  if (argc != 3 || std::string(argv[2]).rfind("-", 0) == 0) {
    std::puts(
        "Usage: radar_batch report RUN\n\nWrites RUN/summary.csv (a row per task), RUN/summary.md (per method "
        "and setting: mean and median over the sequences, the best setting, failed and missing tasks) and "
        "RUN/summary.svg (the primary metric per sequence).");
    return argc == 3 ? 0 : 1;
  }
  const Plan p = readPlan(argv[2]);
  const auto rows = collectRows(p);
  const fs::path dir = p.request.run_dir;
  writeFileAtomically((dir / "summary.csv").string(), summaryCsv(rows));
  writeFileAtomically((dir / "summary.md").string(), summaryMarkdown(p, rows));
  writeFileAtomically((dir / "summary.svg").string(), summarySvg(rows));
  printStates(p, "report");
  std::printf("wrote %s/summary.{csv,md,svg}\n", dir.c_str());
  return 0;
}

int exec(int argc, char** argv) {
  po::options_description o("radar_batch exec RUN ID");
  o.add_options()("run", po::value<std::string>()->required(), "the run folder")(
      "id", po::value<std::string>()->required(), "the task's id")("threads", po::value<int>()->default_value(1),
                                                                   "threads the task runs with");
  po::positional_options_description pos;
  pos.add("run", 1).add("id", 1);
  po::variables_map vm;
  po::store(po::command_line_parser(argc, argv).options(o).positional(pos).run(), vm);
  po::notify(vm);
  const Plan p = readPlan(vm["run"].as<std::string>());
  const std::string id = vm["id"].as<std::string>();
  for (const auto& t : p.tasks)
    if (t.id == id) {
      const int code = executeTask(p.request.run_dir, t, vm["threads"].as<int>());
      std::printf("%s %s %s %s: exit %d\n", t.id.c_str(), t.sequence.c_str(), t.method.c_str(),
                  t.settingsText().c_str(), code);
      return code == 0 ? 0 : 1;
    }
  throw std::invalid_argument("no task " + id + " in " + p.request.run_dir + "/tasks.tsv");
}

const char* kUsage =
    "Usage: radar_batch plan --format F --root DIR --out RUN [--method M1,M2] [--set NAME=V1,V2]...\n"
    "       radar_batch run RUN [--engine parallel|slurm|serial] [-j N] [--threads T] [slurm options]\n"
    "       radar_batch report RUN\n"
    "       radar_batch exec RUN ID [--threads T]   (one task: what the engines run)\n\n"
    "Runs radar_odometry over whole datasets: every sequence x method x setting a task with a stable id "
    "and its own folder\n(RUN/tasks/ID: log.txt, trajectory.txt, result.json written last). `run` skips tasks "
    "whose result is complete\nfor the same command and runs the rest; `report` aggregates. Each verb's options: "
    "radar_batch VERB --help.\n";

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    std::cout << kUsage << "\n" << planOptions() << "\n" << runOptions() << std::endl;
    return argc < 2 ? 1 : 0;
  }
  const std::string verb = argv[1];
  return apps::runGuarded("radar_batch", [&] {
    if (verb == "plan") return plan(argc - 1, argv + 1);
    if (verb == "run") return run(argc - 1, argv + 1);
    if (verb == "report") return report(argc, argv);
    if (verb == "exec") return exec(argc - 1, argv + 1);
    throw std::invalid_argument("unknown verb '" + verb + "' (plan, run, report, exec; see --help)");
  });
}
