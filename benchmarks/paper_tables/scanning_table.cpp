// radar_paper_tables --format oxford|radiate|boreas (tables.h): pw-ndt against PCL's NDT and ICP and
// the paper's ablations on every sequence.
#include <cstdio>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "pipeline_options.h"
#include "radar_ndt/evaluation/report.h"
#include "tables.h"

namespace radar_ndt {
namespace apps {

using nlohmann::json;

namespace {

/// One configuration's figures, one entry per sequence.
struct Row {
  std::string group, name;
  std::vector<double> trans, rot, frame_t, frame_r, match_ms, fe_ms, fallbacks;
};

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

/// The sequences of the table and how each configuration runs on them.
struct TableRuns {
  std::vector<std::unique_ptr<ScanningSequence>> sequences;
  bool progress_on = false;

  /// `o` on the first `n_sequences` sequences (0: all), the first `max_scans` scans each (0: the
  /// options' max_scans).
  Row run(const std::string& group, const std::string& name, const ScanningRunOptions& o, std::size_t max_scans = 0,
          std::size_t n_sequences = 0) const {
    Row row{group, name, {}, {}, {}, {}, {}, {}, {}};
    const std::size_t ns = n_sequences ? n_sequences : sequences.size();
    for (std::size_t i = 0; i < ns; ++i) {
      ScanningRunOptions oo = o;
      if (max_scans) oo.max_scans = max_scans;  // the sweep's; otherwise --max-cycles' (0: all)
      const ScanningRunResult r = runScanningOdometry(*sequences[i], oo, Progress{progress_on, name.substr(0, 12)});
      const PosePairs pairs = associate(r.ground_truth, r.estimate);
      const EvaluationReport rep = evaluate(pairs, {Metric::Kitti, Metric::Frame});
      row.trans.push_back(rep.kitti->trans_err_pct);
      row.rot.push_back(rep.kitti->rot_err_deg_per_m);
      row.frame_t.push_back(rep.frame->trans_err_m);
      row.frame_r.push_back(rep.frame->rot_err_deg);
      row.match_ms.push_back(r.median_ms.match_ms);
      row.fe_ms.push_back(r.median_ms.front_end_ms);
      row.fallbacks.push_back(static_cast<double>(r.counters.fallbacks));
    }
    return row;
  }
};

/// A PCL matcher at its documented grid, its sweep over grids (scored on the first sequence's
/// first scans by frame-to-frame translation error) and the best of the sweep on every sequence.
void addPclRows(const TableRuns& runs, const ScanningRunOptions& base, const std::string& method,
                std::size_t sweep_scans, std::vector<Row>& rows) {
  char label[96];
  ScanningRunOptions o = base;
  o.matcher.method = method;
  std::snprintf(label, sizeof label, "%s, documented (%s %.2f m)", method.c_str(),
                method == "pcl-ndt" ? "resolution" : "max corr.", o.matcher.grid);
  rows.push_back(runs.run("comparison", label, o));
  const std::size_t documented = rows.size() - 1;
  double best_err = std::numeric_limits<double>::infinity(), best_grid = o.matcher.grid;
  for (const double g : {2.5, 3.75, 5.0}) {
    o.matcher.grid = g;
    std::snprintf(label, sizeof label, "%s sweep %.2f", method.c_str(), g);
    const Row sweep = runs.run("sweep", label, o, sweep_scans, 1);
    if (sweep.frame_t[0] < best_err) {
      best_err = sweep.frame_t[0];
      best_grid = g;
    }
  }
  std::snprintf(label, sizeof label, "%s, best of sweep (%.2f m)", method.c_str(), best_grid);
  if (best_grid == base.matcher.grid) {  // the documented run already is this one
    Row again = rows[documented];
    again.name = label;
    rows.push_back(again);
  } else {
    o.matcher.grid = best_grid;
    rows.push_back(runs.run("comparison", label, o));
  }
}

/// The paper's ablations, one setting changed each.
void addAblationRows(const TableRuns& runs, const ScanningRunOptions& base, std::vector<Row>& rows) {
  auto ablate = [&](const std::string& name, const std::function<void(ScanningRunOptions&)>& change) {
    ScanningRunOptions o = base;
    change(o);
    rows.push_back(runs.run("ablation", name, o));
  };
  char label[96];
  ablate("power shift off (s = 0)", [](ScanningRunOptions& o) { o.matcher.power_shift = 0; });
  ablate("shift in the cells only", [](ScanningRunOptions& o) { o.matcher.shift_source_weights = false; });
  for (const float t : {0.2f, 0.3f, 0.4f, 0.5f}) {
    std::snprintf(label, sizeof label, "threshold = s = %.1f", static_cast<double>(t));
    ablate(label, [t](ScanningRunOptions& o) {
      o.front_end.threshold = t;
      o.matcher.power_shift = t;
    });
  }
  for (const double g : {2.5, 5.0}) {
    std::snprintf(label, sizeof label, "grid g = %.1f m", g);
    ablate(label, [g](ScanningRunOptions& o) { o.matcher.grid = g; });
  }
  ablate("scan to scan (no keyframes, the paper)", [](ScanningRunOptions& o) { o.odometry.keyframes.distance = 0; });
  ablate("motion compensation off", [](ScanningRunOptions& o) { o.odometry.compensation.enabled = false; });
  ablate("polar points (no Cartesian image)", [](ScanningRunOptions& o) { o.front_end.cartesian = false; });
  ablate("2x2-neighbour cell lookup",
         [](ScanningRunOptions& o) { o.matcher.weighted_ndt.cell_lookup = CellLookup::Neighbours; });
}

void printJson(const std::vector<Row>& rows, const std::vector<std::string>& dirs) {
  json j = json::array();
  for (const auto& r : rows)
    j.push_back({{"group", r.group},
                 {"name", r.name},
                 {"trans_err_pct", r.trans},
                 {"rot_err_deg_per_m", r.rot},
                 {"frame_trans_err_m", r.frame_t},
                 {"frame_rot_err_deg", r.frame_r},
                 {"match_ms_median", r.match_ms},
                 {"front_end_ms_median", r.fe_ms},
                 {"fallbacks", r.fallbacks}});
  std::cout << json{{"sequences", dirs}, {"rows", j}}.dump(2) << std::endl;
}

void printMarkdown(const std::vector<Row>& rows, const TableRuns& runs, std::size_t sweep_scans) {
  std::ostringstream md;
  md << "| | configuration |";
  for (const auto& s : runs.sequences) md << " " << s->name() << " trans % |";
  md << " mean trans % | mean deg/m | frame m | frame deg | match ms | front-end ms | fallbacks |\n|---|---|";
  for (std::size_t i = 0; i < runs.sequences.size(); ++i) md << "---|";
  md << "---|---|---|---|---|---|---|\n";
  char b[64];
  for (const auto& r : rows) {
    if (r.group == "sweep") continue;
    md << "| " << r.group << " | " << r.name << " |";
    for (double t : r.trans) {
      std::snprintf(b, sizeof b, " %.2f |", t);
      md << b;
    }
    std::snprintf(b, sizeof b, " %.2f |", mean(r.trans));
    md << b;
    std::snprintf(b, sizeof b, " %.4f | %.4f | %.4f | %.2f | %.2f | %.0f |\n", mean(r.rot), mean(r.frame_t),
                  mean(r.frame_r), mean(r.match_ms), mean(r.fe_ms),
                  mean(r.fallbacks) * static_cast<double>(r.fallbacks.size()));
    md << b;
  }
  md << "\nours vs each PCL row (mean translational error): ";
  for (const auto& r : rows)
    if (r.group == "comparison" && &r != &rows[0]) {
      std::snprintf(b, sizeof b, "%.0f %% lower than ", 100.0 * (1.0 - mean(rows[0].trans) / mean(r.trans)));
      md << b << r.name << "; ";
    }
  md << "\nPCL sweep (frame-to-frame translation error, m, first " << sweep_scans << " scans of "
     << runs.sequences[0]->name() << "):";
  for (const auto& r : rows)
    if (r.group == "sweep") {
      std::snprintf(b, sizeof b, " %.4f;", r.frame_t[0]);
      md << " " << r.name << b;
    }
  std::cout << md.str() << std::endl;
}

}  // namespace

int runScanningTable(const ScanningRunOptions& base, ScanFormat format, const std::vector<std::string>& dirs,
                     std::size_t sweep_scans, bool json_out, bool progress_on) {
  TableRuns runs;
  runs.progress_on = progress_on;
  for (const auto& d : dirs) {
    runs.sequences.push_back(std::make_unique<ScanningSequence>(d, format, base.sequence));
    if (!runs.sequences.back()->hasGroundTruth())
      throw std::invalid_argument(
          "--table: " + d + " has no ground truth (oxford: gt/radar_odometry.csv; boreas: applanix/radar_poses.csv)");
  }
  // The comparison: the same thresholded scans, guesses and failure handling for every matcher.
  std::vector<Row> rows;
  rows.push_back(runs.run("comparison", "ours (pw-ndt)", base));
  for (const std::string method : {"pcl-ndt", "pcl-icp"}) addPclRows(runs, base, method, sweep_scans, rows);
  addAblationRows(runs, base, rows);
  if (json_out)
    printJson(rows, dirs);
  else
    printMarkdown(rows, runs, sweep_scans);
  return 0;
}

}  // namespace apps
}  // namespace radar_ndt
