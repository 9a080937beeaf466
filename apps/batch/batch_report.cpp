#include "batch_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app_common.h"

namespace radar_ndt {
namespace batch {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

double number(const json& j, std::initializer_list<const char*> path) {
  const json* p = &j;
  for (const char* key : path) {
    if (!p->is_object() || !p->contains(key)) return kNone;
    p = &(*p)[key];
  }
  return p->is_number() ? p->get<double>() : kNone;
}

double mean(const std::vector<double>& v) {
  if (v.empty()) return kNone;
  double s = 0;
  for (double x : v) s += x;  // in plan order: the same bytes for the same results
  return s / static_cast<double>(v.size());
}

double median(const std::vector<double>& v) {
  return radar_ndt::median(v, kNone);
}

/// A 6-DoF run's figures (metrics.ate6, re, final); NaN where the summary has none.
void readSixDof(const json& s, TaskRow& r) {
  r.ate_posyaw_m = number(s, {"metrics", "ate6", "posyaw", "rmse_m"});
  r.ate_posyaw_deg = number(s, {"metrics", "ate6", "posyaw", "rot_rmse_deg"});
  r.ate_se3_m = number(s, {"metrics", "ate6", "se3", "rmse_m"});
  r.final_pct = number(s, {"metrics", "final", "final_pct"});
  if (!s.contains("metrics") || !s["metrics"].contains("re") || !s["metrics"]["re"].is_array()) return;
  std::vector<double> pct;
  for (const json& e : s["metrics"]["re"]) pct.push_back(number(e, {"trans_mean_pct"}));
  if (!pct.empty() && std::none_of(pct.begin(), pct.end(), [](double v) { return std::isnan(v); }))
    r.re_pct = mean(pct);
}

std::string escapeXml(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
  return out;
}

}  // namespace

std::string formatNumber(double v) {
  if (std::isnan(v)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

const std::vector<MetricColumn>& metricColumns() {
  static const std::vector<MetricColumn> columns{{"kitti_pct", &TaskRow::kitti_pct},
                                                 {"kitti_deg_per_m", &TaskRow::kitti_deg_per_m},
                                                 {"1m_pct", &TaskRow::one_meter_pct},
                                                 {"1m_deg_per_m", &TaskRow::one_meter_deg_per_m},
                                                 {"frame_m", &TaskRow::frame_m},
                                                 {"frame_deg", &TaskRow::frame_deg},
                                                 {"ate_m", &TaskRow::ate_m},
                                                 {"ms_per_scan", &TaskRow::ms_per_scan},
                                                 {"ate_posyaw_m", &TaskRow::ate_posyaw_m, true},
                                                 {"ate_posyaw_deg", &TaskRow::ate_posyaw_deg, true},
                                                 {"ate_se3_m", &TaskRow::ate_se3_m, true},
                                                 {"re_pct", &TaskRow::re_pct, true},
                                                 {"final_pct", &TaskRow::final_pct, true}};
  return columns;
}

std::vector<TaskRow> collectRows(const Plan& plan) {
  std::vector<TaskRow> rows;
  for (const Task& t : plan.tasks) {
    TaskRow r;
    r.task = t;
    r.state = taskState(plan.request.run_dir, t);
    r.log = (fs::path("tasks") / t.id / "log.txt").string();
    if (r.state == TaskState::Complete || r.state == TaskState::Failed) {
      std::ifstream in(fs::path(taskDir(plan.request.run_dir, t.id)) / "result.json");
      const json result = json::parse(in, nullptr, false);
      r.exit_code = result.value("exit_code", -1);
      const json& s = result.contains("summary") ? result["summary"] : json();
      if (r.state == TaskState::Complete) {
        r.kitti_pct = number(s, {"metrics", "kitti", "trans_err_pct"});
        r.kitti_deg_per_m = number(s, {"metrics", "kitti", "rot_err_deg_per_m"});
        r.one_meter_pct = number(s, {"metrics", "1m", "trans_err_pct"});
        r.one_meter_deg_per_m = number(s, {"metrics", "1m", "rot_err_deg_per_m"});
        r.frame_m = number(s, {"metrics", "frame", "trans_err_m"});
        r.frame_deg = number(s, {"metrics", "frame", "rot_err_deg"});
        r.ate_m = number(s, {"metrics", "ate", "rmse_m"});
        r.scans = s.contains("scans") ? number(s, {"scans"}) : number(s, {"cycles"});
        r.fallbacks = number(s, {"fallbacks"});
        r.problems = number(s, {"problems"});
        r.ms_per_scan = s.contains("ms_per_scan_median") ? number(s, {"ms_per_scan_median", "total"})
                        : s.contains("ms_per_scan")      ? number(s, {"ms_per_scan"})  // a 6-DoF run's
                                                         : number(s, {"ms_per_cycle_median", "total"});
        readSixDof(s, r);
      }
    }
    rows.push_back(std::move(r));
  }
  return rows;
}

std::vector<GroupSummary> summarize(const std::vector<TaskRow>& rows) {
  std::vector<GroupSummary> groups;
  std::map<std::pair<std::string, std::string>, std::size_t> index;  // in order of first appearance
  std::vector<std::vector<std::vector<double>>> values;              // group, column, values
  const auto& columns = metricColumns();
  for (const TaskRow& r : rows) {
    const auto key = std::make_pair(r.task.method, r.task.settingsText());
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, groups.size()).first;
      groups.push_back({key.first, key.second, 0, 0, {}, {}});
      values.emplace_back(columns.size());
    }
    GroupSummary& g = groups[it->second];
    ++g.tasks;
    if (r.state != TaskState::Complete) continue;
    ++g.complete;
    for (std::size_t c = 0; c < columns.size(); ++c)
      if (!std::isnan(r.*columns[c].field)) values[it->second][c].push_back(r.*columns[c].field);
  }
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (std::size_t c = 0; c < columns.size(); ++c) {
      groups[g].mean.push_back(mean(values[g][c]));
      groups[g].median.push_back(median(values[g][c]));
    }
  return groups;
}

int primaryMetric(const std::vector<TaskRow>& rows) {
  const auto& columns = metricColumns();
  for (const char* name : {"ate_posyaw_m", "kitti_pct", "1m_pct", "ate_m", "frame_m"})
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (name != std::string(columns[c].name)) continue;
      std::size_t complete = 0, defined = 0;
      for (const TaskRow& r : rows)
        if (r.state == TaskState::Complete) ++complete, defined += !std::isnan(r.*columns[c].field);
      if (complete > 0 && defined == complete) return static_cast<int>(c);
    }
  return -1;
}

std::string summaryCsv(const std::vector<TaskRow>& rows) {
  std::vector<MetricColumn> columns;  // the planar ones always, the 6-DoF ones when a task has one
  for (const auto& c : metricColumns())
    if (!c.six_dof || std::any_of(rows.begin(), rows.end(), [&](const TaskRow& r) { return !std::isnan(r.*c.field); }))
      columns.push_back(c);
  std::string csv = "id,sequence,method,settings,status,exit_code";
  for (const auto& c : columns) csv += std::string(",") + c.name;
  csv += ",scans,fallbacks,problems,log\n";
  for (const TaskRow& r : rows) {
    csv += r.task.id + "," + r.task.sequence + "," + r.task.method + "," + r.task.settingsText() + "," +
           toString(r.state) + "," + (r.exit_code >= 0 ? std::to_string(r.exit_code) : "");
    for (const auto& c : columns) csv += "," + formatNumber(r.*c.field);
    csv += "," + formatNumber(r.scans) + "," + formatNumber(r.fallbacks) + "," + formatNumber(r.problems) + "," +
           r.log + "\n";
  }
  return csv;
}

namespace {

/// The report's head: what was run and how many tasks ended how.
void markdownHead(std::ostringstream& md, const Plan& plan, const std::vector<TaskRow>& rows) {
  const auto& req = plan.request;
  std::size_t complete = 0, failed = 0;
  for (const auto& r : rows) complete += r.state == TaskState::Complete, failed += r.state == TaskState::Failed;
  md << "# radar_batch report\n\n"
     << "- format `" << req.format << "`, root `" << req.root << "`, " << plan.sequences.size() << " sequences\n"
     << "- methods:";
  for (const auto& m : req.methods) md << " `" << m << "`";
  md << "\n- settings:";
  if (req.settings.empty()) md << " default";
  for (const auto& a : req.settings) {
    md << " `" << a.name << "` =";
    for (const auto& v : a.values) md << " " << v;
    md << ";";
  }
  md << "\n- RadarNDT " << plan.version << ", revision " << plan.git_revision << "\n"
     << "- tasks: " << rows.size() << ", complete " << complete << ", failed " << failed << ", not run "
     << rows.size() - complete - failed << "\n\n";
}

/// The means and medians per method and setting, then the best setting of each method.
void markdownGroups(std::ostringstream& md, const Plan& plan, const std::vector<TaskRow>& rows) {
  const auto groups = summarize(rows);
  const auto& columns = metricColumns();
  std::vector<std::size_t> shown;  // columns with a value in some group
  for (std::size_t c = 0; c < columns.size(); ++c)
    for (const auto& g : groups)
      if (!std::isnan(g.mean[c])) {
        shown.push_back(c);
        break;
      }
  md << "## Per method and setting (mean / median over the sequences)\n\n| method | settings | done |";
  for (std::size_t c : shown) md << " " << columns[c].name << " |";
  md << "\n|---|---|---|";
  for (std::size_t i = 0; i < shown.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& g : groups) {
    md << "| " << g.method << " | " << g.settings << " | " << g.complete << "/" << g.tasks << " |";
    for (std::size_t c : shown) md << " " << formatNumber(g.mean[c]) << " / " << formatNumber(g.median[c]) << " |";
    md << "\n";
  }
  const int primary = primaryMetric(rows);
  if (primary < 0) return;
  md << "\n## Best setting per method (lowest mean " << columns[primary].name << ")\n\n";
  for (const auto& m : plan.request.methods) {
    const GroupSummary* best = nullptr;
    for (const auto& g : groups)
      if (g.method == m && !std::isnan(g.mean[primary]) && (!best || g.mean[primary] < best->mean[primary])) best = &g;
    if (best)
      md << "- `" << m << "`: " << best->settings << " (" << formatNumber(best->mean[primary]) << ", " << best->complete
         << " of " << best->tasks << " sequences)\n";
  }
}

/// The tasks in `states`, under `title` (nothing when there are none).
void markdownTasks(std::ostringstream& md, const std::vector<TaskRow>& rows, const char* title,
                   const std::vector<TaskState>& states) {
  bool any = false;
  for (const auto& r : rows) {
    if (std::find(states.begin(), states.end(), r.state) == states.end()) continue;
    if (!any)
      md << "\n## " << title << "\n\n| id | sequence | method | settings | state | exit code | log |\n"
         << "|---|---|---|---|---|---|---|\n";
    any = true;
    md << "| " << r.task.id << " | " << r.task.sequence << " | " << r.task.method << " | " << r.task.settingsText()
       << " | " << toString(r.state) << " | " << (r.exit_code >= 0 ? std::to_string(r.exit_code) : "") << " | `"
       << r.log << "` |\n";
  }
}

}  // namespace

std::string summaryMarkdown(const Plan& plan, const std::vector<TaskRow>& rows) {
  std::ostringstream md;
  markdownHead(md, plan, rows);
  markdownGroups(md, plan, rows);
  markdownTasks(md, rows, "Failed tasks", {TaskState::Failed});
  markdownTasks(md, rows, "Tasks without a result (not run, killed, or planned anew): `radar_batch run` runs them",
                {TaskState::Missing, TaskState::Stale});
  return md.str();
}

namespace {
/// The largest value of the metric `column` among the complete tasks (1 without one): the plot's top.
double largestValue(const std::vector<TaskRow>& rows, int column) {
  double top = 0;
  if (column >= 0)
    for (const auto& r : rows)
      if (r.state == TaskState::Complete && !std::isnan(r.*metricColumns()[column].field))
        top = std::max(top, r.*metricColumns()[column].field);
  return top <= 0 ? 1 : top;
}
}  // namespace

std::string summarySvg(const std::vector<TaskRow>& rows) {
  const int primary = primaryMetric(rows);
  std::vector<std::string> sequences, groups;
  for (const auto& r : rows) {
    if (std::find(sequences.begin(), sequences.end(), r.task.sequence) == sequences.end())
      sequences.push_back(r.task.sequence);
    const std::string g = r.task.method + " " + r.task.settingsText();
    if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
  }
  const double top = largestValue(rows, primary);
  const int bar = 14, gap = 20, left = 70, plot_h = 260, legend_h = 18 * static_cast<int>(groups.size());
  const int width = left + static_cast<int>(sequences.size()) * (bar * static_cast<int>(groups.size()) + gap) + 20;
  const int height = 40 + plot_h + 110 + legend_h;
  static const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                  "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
    << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << left << "\" y=\"20\" font-size=\"13\">"
    << (primary >= 0 ? metricColumns()[primary].name : "no metric") << " per sequence</text>\n";
  const int y0 = 40 + plot_h;
  for (int k = 0; k <= 4; ++k) {
    const double v = top * k / 4;
    const int y = y0 - static_cast<int>(plot_h * k / 4);
    s << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << width - 10 << "\" y2=\"" << y
      << "\" stroke=\"#ddd\"/>\n<text x=\"" << left - 4 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">"
      << formatNumber(v) << "</text>\n";
  }
  for (std::size_t i = 0; i < sequences.size(); ++i) {
    const int x0 = left + static_cast<int>(i) * (bar * static_cast<int>(groups.size()) + gap) + gap / 2;
    for (const auto& r : rows) {
      if (r.task.sequence != sequences[i] || primary < 0) continue;
      const double v = r.*metricColumns()[primary].field;
      const auto g = static_cast<int>(
          std::find(groups.begin(), groups.end(), r.task.method + " " + r.task.settingsText()) - groups.begin());
      const int x = x0 + g * bar;
      if (r.state != TaskState::Complete || std::isnan(v)) {
        s << "<text x=\"" << x + bar / 2 << "\" y=\"" << y0 - 4 << "\" text-anchor=\"middle\" fill=\"#d00\">x</text>\n";
        continue;
      }
      const int h = static_cast<int>(plot_h * v / top);
      s << "<rect x=\"" << x << "\" y=\"" << y0 - h << "\" width=\"" << bar - 2 << "\" height=\"" << h << "\" fill=\""
        << colours[g % 8] << "\"><title>" << escapeXml(r.task.sequence + ", " + groups[g]) << ": " << formatNumber(v)
        << "</title></rect>\n";
    }
    s << "<text transform=\"translate(" << x0 << "," << y0 + 12 << ") rotate(30)\">" << escapeXml(sequences[i])
      << "</text>\n";
  }
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const int y = y0 + 110 + 18 * static_cast<int>(g);
    s << "<rect x=\"" << left << "\" y=\"" << y - 10 << "\" width=\"12\" height=\"12\" fill=\"" << colours[g % 8]
      << "\"/><text x=\"" << left + 18 << "\" y=\"" << y << "\">" << escapeXml(groups[g]) << "</text>\n";
  }
  s << "</svg>\n";
  return s.str();
}

}  // namespace batch
}  // namespace radar_ndt
