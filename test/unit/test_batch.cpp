// radar_batch's plan, resume decisions and aggregation (apps/batch/): the expansion's counts and
// stable ids, shell quoting of paths with spaces, which tasks a second run runs, and the report's
// means and medians against hand-computed ones.

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "batch/batch_plan.h"
#include "batch/batch_report.h"
#include "batch/batch_run.h"
#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/io_error.h"
#include "test_support.h"

using namespace radar_ndt::batch;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("radar_ndt_batch_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

/// Three scanning sequence folders (one with a space in its name, one with ground truth).
PlanRequest request(const fs::path& root, const fs::path& run) {
  for (const char* s : {"drive a", "drive_b", "drive_c"}) {
    fs::create_directories(root / s / "radar");
    radar_ndt::writeFileAtomically((root / s / "radar.timestamps").string(), "1 1\n");
  }
  fs::create_directories(root / "drive_b" / "gt");
  radar_ndt::writeFileAtomically((root / "drive_b" / "gt" / "radar_odometry.csv").string(), "x\n");
  fs::create_directories(root / "not a sequence");
  PlanRequest r;
  r.format = "oxford";
  r.root = root.string();
  r.methods = {"pw-ndt", "pcl-ndt"};
  r.settings = {parseSettingAxis("grid=3,3.75"), parseSettingAxis("--power-shift=0,0.333,0.5")};
  r.odometry_app = "/opt/radar ndt/bin/radar_odometry";
  r.run_dir = run.string();
  return r;
}

}  // namespace

TEST(BatchPlan, ExpandsEverySequenceMethodAndSettingWithStableIds) {
  const fs::path dir = scratch("plan");
  const PlanRequest r = request(dir / "data", dir / "run");
  const auto sequences = findSequences("oxford", r.root);
  ASSERT_EQ(sequences.size(), 3u);  // "not a sequence" has no radar.timestamps
  EXPECT_EQ(sequences[0].name, "drive a");
  const auto tasks = expandPlan(r, sequences);
  ASSERT_EQ(tasks.size(), 3u * 2u * 6u);
  // Nesting: sequence, method, then the settings grid with the last axis fastest.
  EXPECT_EQ(tasks[0].settingsText(), "grid=3 power-shift=0");
  EXPECT_EQ(tasks[1].settingsText(), "grid=3 power-shift=0.333");
  EXPECT_EQ(tasks[3].settingsText(), "grid=3.75 power-shift=0");
  EXPECT_EQ(tasks[6].method, "pcl-ndt");
  EXPECT_EQ(tasks[12].sequence, "drive_b");
  // The id depends on sequence, method and settings only: not on the order, the paths or the run.
  PlanRequest other = r;
  other.methods = {"pcl-ndt"};
  other.run_dir = (dir / "elsewhere").string();
  other.odometry_app = "/usr/bin/radar_odometry";
  const auto again = expandPlan(other, {sequences[1]});
  EXPECT_EQ(again[0].id, taskId("drive_b", "pcl-ndt", {{"grid", "3"}, {"power-shift", "0"}}));
  EXPECT_EQ(again[0].id, tasks[18].id);
  std::set<std::string> ids;
  for (const auto& t : tasks) ids.insert(t.id);
  EXPECT_EQ(ids.size(), tasks.size());
  EXPECT_EQ(tasks[0].id.size(), 16u);
  // Only the sequence with ground truth is evaluated.
  const auto& with_gt = tasks[12].command;
  EXPECT_NE(std::find(with_gt.begin(), with_gt.end(), "--eval"), with_gt.end());
  EXPECT_EQ(std::find(tasks[0].command.begin(), tasks[0].command.end(), "--eval"), tasks[0].command.end());
  EXPECT_EQ(tasks[0].command.back(), (fs::path(r.run_dir) / "tasks" / tasks[0].id / "trajectory.txt").string());
  // Selection by name and by pattern.
  EXPECT_EQ(findSequences("oxford", r.root, {"drive_c"}).size(), 1u);
  EXPECT_EQ(findSequences("oxford", r.root, {}, "drive_*").size(), 2u);
  EXPECT_THROW(findSequences("oxford", r.root, {"drive_x"}), std::invalid_argument);
  EXPECT_THROW(parseSettingAxis("grid"), std::invalid_argument);
  EXPECT_THROW(parseSettingAxis("grid=3,"), std::invalid_argument);
  EXPECT_THROW(parseSettingAxis("grid=3, 4"), std::invalid_argument);
  fs::remove_all(dir);
}

TEST(BatchPlan, BagsAreSequencesReadThroughOneSensorDescription) {
  const fs::path dir = scratch("bags");
  fs::create_directories(dir / "bags" / "sub");
  for (const char* f : {"drive 1.bag", "drive_2.bag", "notes.txt", "sub/deeper.bag"})
    radar_ndt::writeFileAtomically((dir / "bags" / f).string(), "#ROSBAG V2.0\n");
  PlanRequest r;
  r.format = "rosbag";
  r.root = (dir / "bags").string();
  r.odometry_app = "radar_odometry";
  r.run_dir = (dir / "run").string();
  const auto bags = findSequences("rosbag", r.root);
  ASSERT_EQ(bags.size(), 2u);  // the folder's *.bag files, not its subfolders'
  EXPECT_EQ(bags[0].name, "drive 1");
  EXPECT_EQ(bags[1].path, (dir / "bags" / "drive_2.bag").string());
  const auto one = findSequences("rosbag", (dir / "bags" / "sub" / "deeper.bag").string());
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].name, "deeper");
  EXPECT_THROW(expandPlan(r, bags), std::invalid_argument);  // no description
  // The nuScenes preset names a ground truth: every bag's task is evaluated.
  r.sensors = "preset:nuscenes_ars408";
  const auto tasks = expandPlan(r, bags);
  ASSERT_EQ(tasks.size(), 2u);
  const std::vector<std::string> head(tasks[0].command.begin(), tasks[0].command.begin() + 11);
  EXPECT_EQ(head, (std::vector<std::string>{"radar_odometry", "--format", "rosbag", "--bag", bags[0].path, "--sensors",
                                            "preset:nuscenes_ars408", "--method", "pw-ndt", "--eval", "--metric"}));
  // The TI preset names none: no --eval.
  r.sensors = "preset:ti_iwr6843_rio";
  const auto no_gt = expandPlan(r, bags)[0].command;
  EXPECT_EQ(std::find(no_gt.begin(), no_gt.end(), "--eval"), no_gt.end());
  // The description is part of the plan.
  Plan p{r, bags, expandPlan(r, bags), "0.2.0", "abc"};
  writePlan(p);
  EXPECT_EQ(readPlan(r.run_dir).request.sensors, "preset:ti_iwr6843_rio");
  EXPECT_THROW(findSequences("rosbag", (dir / "nothing").string()), radar_ndt::IoError);
  fs::remove_all(dir);
}

TEST(BatchPlan, QuotesPathsWithSpacesAsAShellSplitsThem) {
  const std::vector<std::string> words{
      "/opt/radar ndt/radar_odometry", "--sequence", "/data/it's here", "plain", "a\"b", "$HOME", ""};
  const std::string line = joinShellWords(words);
  EXPECT_EQ(splitShellWords(line), words);
  EXPECT_EQ(shellQuote("plain"), "plain");
  EXPECT_EQ(shellQuote("it's"), "'it'\\''s'");
  // What /bin/sh makes of the line: the same words.
  const std::string cmd = "for w in " + line + "; do printf '[%s]' \"$w\"; done";
  FILE* p = popen(("/bin/sh -c " + shellQuote(cmd)).c_str(), "r");
  ASSERT_NE(p, nullptr);
  char buf[512] = {};
  const std::size_t n = std::fread(buf, 1, sizeof buf - 1, p);
  pclose(p);
  std::string expected;
  for (const auto& w : words) expected += "[" + w + "]";
  EXPECT_EQ(std::string(buf, n), expected);
  EXPECT_THROW(splitShellWords("a 'b"), std::invalid_argument);
}

TEST(BatchPlan, AWrittenPlanReadsBackTheSame) {
  const fs::path dir = scratch("roundtrip");
  Plan p;
  p.request = request(dir / "data", dir / "run");
  p.sequences = findSequences("oxford", p.request.root);
  p.tasks = expandPlan(p.request, p.sequences);
  p.version = "0.2.0";
  p.git_revision = "abc";
  writePlan(p);
  const Plan back = readPlan(p.request.run_dir);
  ASSERT_EQ(back.tasks.size(), p.tasks.size());
  for (std::size_t i = 0; i < p.tasks.size(); ++i) {
    EXPECT_EQ(back.tasks[i].id, p.tasks[i].id);
    EXPECT_EQ(back.tasks[i].command, p.tasks[i].command);
    EXPECT_EQ(back.tasks[i].settings, p.tasks[i].settings);
  }
  EXPECT_EQ(back.request.settings.size(), 2u);
  EXPECT_EQ(back.sequences[0].path, p.sequences[0].path);
  EXPECT_THROW(readPlan((dir / "nothing").string()), radar_ndt::IoError);
  fs::remove_all(dir);
}

TEST(BatchRun, ResumesOnlyWhatHasNoCompleteResultForTheSameCommand) {
  const fs::path dir = scratch("resume");
  Task t{"0123456789abcdef", "s", "pw-ndt", {}, {"/bin/true", "--x"}};
  const std::string run = dir.string();
  EXPECT_EQ(taskState(run, t), TaskState::Missing);
  auto write = [&](const nlohmann::json& j) {
    fs::create_directories(taskDir(run, t.id));
    radar_ndt::writeFileAtomically((fs::path(taskDir(run, t.id)) / "result.json").string(), j.dump());
  };
  const nlohmann::json summary = {{"scans", 3}};
  write({{"command", joinShellWords(t.command)}, {"exit_code", 0}, {"summary", summary}});
  EXPECT_EQ(taskState(run, t), TaskState::Complete);
  write({{"command", joinShellWords(t.command)}, {"exit_code", 1}, {"summary", nullptr}});
  EXPECT_EQ(taskState(run, t), TaskState::Failed);
  write({{"command", "/bin/true --y"}, {"exit_code", 0}, {"summary", summary}});
  EXPECT_EQ(taskState(run, t), TaskState::Stale);
  radar_ndt::writeFileAtomically((fs::path(taskDir(run, t.id)) / "result.json").string(), "{\"command\": ");
  EXPECT_EQ(taskState(run, t), TaskState::Missing);
  // A task that runs: its exit code and no summary (true prints nothing) make it failed, with a log.
  EXPECT_EQ(executeTask(run, t, 1), 125);
  EXPECT_EQ(taskState(run, t), TaskState::Failed);
  EXPECT_TRUE(fs::exists(fs::path(taskDir(run, t.id)) / "log.txt"));
  Task missing{"fedcba9876543210", "s", "pw-ndt", {}, {"/no/such/app"}};
  EXPECT_EQ(executeTask(run, missing, 1), 127);
  EXPECT_EQ(taskState(run, missing), TaskState::Failed);
  fs::remove_all(dir);
}

TEST(BatchReport, MeansAndMediansOverSequencesAsComputedByHand) {
  auto row = [](const std::string& seq, const std::string& method, double kitti, double ate, TaskState state) {
    TaskRow r;
    r.task = Task{taskId(seq, method, {}), seq, method, {}, {}};
    r.state = state;
    r.kitti_pct = kitti;
    r.ate_m = ate;
    return r;
  };
  const std::vector<TaskRow> rows{
      row("a", "pw-ndt", 1.0, 0.5, TaskState::Complete), row("a", "pcl-ndt", 2.0, 0.25, TaskState::Complete),
      row("b", "pw-ndt", 4.0, 1.5, TaskState::Complete), row("b", "pcl-ndt", kNone, kNone, TaskState::Failed),
      row("c", "pw-ndt", 0.5, 2.0, TaskState::Complete), row("c", "pcl-ndt", 3.0, 0.75, TaskState::Complete)};
  const auto groups = summarize(rows);
  ASSERT_EQ(groups.size(), 2u);
  const auto& cols = metricColumns();
  const auto col = [&](const std::string& name) {
    for (std::size_t c = 0; c < cols.size(); ++c)
      if (cols[c].name == name) return c;
    return cols.size();
  };
  EXPECT_EQ(groups[0].method, "pw-ndt");
  EXPECT_EQ(groups[0].complete, 3u);
  EXPECT_DOUBLE_EQ(groups[0].mean[col("kitti_pct")], (1.0 + 4.0 + 0.5) / 3);
  EXPECT_DOUBLE_EQ(groups[0].median[col("kitti_pct")], 1.0);
  EXPECT_DOUBLE_EQ(groups[0].mean[col("ate_m")], (0.5 + 1.5 + 2.0) / 3);
  EXPECT_EQ(groups[1].complete, 2u);  // the failed task counts in no mean
  EXPECT_DOUBLE_EQ(groups[1].mean[col("kitti_pct")], 2.5);
  EXPECT_DOUBLE_EQ(groups[1].median[col("ate_m")], 0.5);
  EXPECT_TRUE(std::isnan(groups[1].mean[col("frame_m")]));
  EXPECT_EQ(primaryMetric(rows), static_cast<int>(col("kitti_pct")));
  const std::string csv = summaryCsv(rows);
  EXPECT_NE(csv.find(rows[3].task.id + ",b,pcl-ndt,default,failed,"), std::string::npos);
  EXPECT_EQ(formatNumber(1.0 / 3), "0.333333333");
  EXPECT_EQ(formatNumber(kNone), "");
  EXPECT_EQ(summarySvg(rows), summarySvg(rows));
}

TEST(BatchPlan, ASwitchAxisGivesTheSwitchForOnAndNothingForOff) {
  const fs::path dir = scratch("switch");
  radar_ndt::writeFileAtomically((dir / "walk.bag").string(), "#ROSBAG V2.0\n");
  PlanRequest r;
  r.format = "rosbag";
  r.root = (dir / "walk.bag").string();
  r.sensors = "preset:ti_iwr6843_rio";
  r.methods = {"pw-ndt-3d", "doppler-imu"};
  r.settings = {parseSettingAxis("imu=off,on"), parseSettingAxis("radar-latency=0.125")};
  r.settings[0].is_switch = true;
  r.odometry_app = "radar_odometry";
  r.run_dir = (dir / "run").string();
  const auto bags = findSequences("rosbag", r.root);
  const auto tasks = expandPlan(r, bags);
  ASSERT_EQ(tasks.size(), 4u);
  const auto has = [](const Task& t, const std::string& word) {
    return std::find(t.command.begin(), t.command.end(), word) != t.command.end();
  };
  EXPECT_EQ(tasks[0].settingsText(), "imu=off radar-latency=0.125");
  EXPECT_FALSE(has(tasks[0], "--imu"));
  EXPECT_FALSE(has(tasks[0], "off"));
  EXPECT_TRUE(has(tasks[1], "--imu"));
  EXPECT_FALSE(has(tasks[1], "on"));
  EXPECT_TRUE(has(tasks[1], "--radar-latency") && has(tasks[1], "0.125"));
  EXPECT_NE(tasks[0].id, tasks[1].id);
  // plan.json keeps the axis a switch; a plan without one reads as before.
  writePlan({r, bags, tasks, "0.2.0", "abc"});
  const Plan back = readPlan(r.run_dir);
  EXPECT_TRUE(back.request.settings[0].is_switch);
  EXPECT_FALSE(back.request.settings[1].is_switch);
  EXPECT_EQ(back.tasks[1].command, tasks[1].command);
  r.settings[0] = parseSettingAxis("imu=yes");
  r.settings[0].is_switch = true;
  EXPECT_THROW(expandPlan(r, bags), std::invalid_argument);
  fs::remove_all(dir);
}

TEST(BatchReport, ASixDofRunsFiguresAreReadAndChooseTheBest) {
  const fs::path dir = scratch("six_dof");
  Plan plan;
  plan.request.run_dir = dir.string();
  const auto result = [&](const Task& t, double posyaw, double re10, double re20) {
    const nlohmann::json metrics = {
        {"ate6",
         {{"se3", {{"rmse_m", posyaw + 0.5}, {"rot_rmse_deg", 3.0}}},
          {"posyaw", {{"rmse_m", posyaw}, {"rot_rmse_deg", 2.0}}}}},
        {"re", {{{"distance_m", 10.0}, {"trans_mean_pct", re10}}, {{"distance_m", 20.0}, {"trans_mean_pct", re20}}}},
        {"final", {{"final_m", 3.0}, {"final_pct", 1.5}, {"distance_m", 200.0}}},
        {"kitti", {{"trans_err_pct", 9.0}}}};
    const nlohmann::json summary = {
        {"pipeline", "6-DoF"}, {"scans", 100}, {"fallbacks", 2}, {"ms_per_scan", 0.25}, {"metrics", metrics}};
    fs::create_directories(taskDir(dir.string(), t.id));
    radar_ndt::writeFileAtomically(
        (fs::path(taskDir(dir.string(), t.id)) / "result.json").string(),
        nlohmann::json{{"command", joinShellWords(t.command)}, {"exit_code", 0}, {"summary", summary}}.dump());
  };
  plan.tasks = {Task{taskId("walk", "pw-ndt-3d", {}), "walk", "pw-ndt-3d", {}, {"radar_odometry", "--a"}},
                Task{taskId("walk", "doppler-imu", {}), "walk", "doppler-imu", {}, {"radar_odometry", "--b"}}};
  result(plan.tasks[0], 0.75, 1.0, 3.0);
  result(plan.tasks[1], 1.25, 2.0, 2.0);
  const auto rows = collectRows(plan);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_DOUBLE_EQ(rows[0].ate_posyaw_m, 0.75);
  EXPECT_DOUBLE_EQ(rows[0].ate_posyaw_deg, 2.0);
  EXPECT_DOUBLE_EQ(rows[0].ate_se3_m, 1.25);
  EXPECT_DOUBLE_EQ(rows[0].re_pct, 2.0);  // the mean over the distances
  EXPECT_DOUBLE_EQ(rows[0].final_pct, 1.5);
  EXPECT_DOUBLE_EQ(rows[0].ms_per_scan, 0.25);
  EXPECT_DOUBLE_EQ(rows[0].scans, 100);
  // ATE with position + yaw alignment judges 6-DoF runs, ahead of the planar figures they also have.
  const int primary = primaryMetric(rows);
  ASSERT_GE(primary, 0);
  EXPECT_STREQ(metricColumns()[primary].name, "ate_posyaw_m");
  const std::string csv = summaryCsv(rows);
  EXPECT_NE(csv.find(",ate_posyaw_m,ate_posyaw_deg,ate_se3_m,re_pct,final_pct,"), std::string::npos);
  EXPECT_NE(csv.find(",0.75,2,1.25,2,1.5,"), std::string::npos);
  // A planar run's file has no 6-DoF column.
  TaskRow planar;
  planar.task = plan.tasks[0];
  planar.state = TaskState::Complete;
  planar.kitti_pct = 1.0;
  EXPECT_EQ(summaryCsv({planar}).find("ate_posyaw"), std::string::npos);
  fs::remove_all(dir);
}
