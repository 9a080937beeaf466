// radar_paper_tables --format nuscenes (tables.h): the paper's table, rows N, columns ICP / pw-ndt
// / Kellner / Rapp in the paper's mode (submap to submap, not fused), 1m metric, mean over scenes;
// then the same four methods through the default pipeline as an extra row; then frame errors, ms per
// cycle by stage and fallbacks per method and row.
#include <cstdio>
#include <iostream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "pipeline_options.h"
#include "radar_ndt/evaluation/report.h"
#include "tables.h"

namespace radar_ndt {
namespace apps {

using nlohmann::json;

namespace {

/// The sums over scenes of one method and N.
struct Cell {
  double trans = 0, rot = 0, ate = 0, frame_t = 0, frame_r = 0, ms = 0, fallback = 0;
  StageTimes stages;
  int n = 0;
  void add(const AutomotiveRunResult& r) {
    const PosePairs pairs = associate(r.ground_truth, r.estimate);
    const EvaluationReport rep = evaluate(pairs, {Metric::OneMeter, Metric::Frame, Metric::Ate});
    trans += rep.one_meter->trans_err_pct;
    rot += rep.one_meter->rot_err_deg_per_m;
    ate += rep.ate->rmse_m;
    frame_t += rep.frame->trans_err_m;
    frame_r += rep.frame->rot_err_deg;
    ms += r.median_total_ms;
    stages.read_ms += r.median_ms.read_ms;
    stages.front_end_ms += r.median_ms.front_end_ms;
    stages.submap_ms += r.median_ms.submap_ms;
    stages.match_ms += r.median_ms.match_ms;
    fallback +=
        r.counters.cycles ? static_cast<double>(r.counters.fallbacks) / static_cast<double>(r.counters.cycles) : 0.0;
    ++n;
  }
  json toJson(const std::string& method) const {
    const double k = 1.0 / n;
    return {{"method", method},
            {"trans_err_pct", trans * k},
            {"rot_err_deg_per_m", rot * k},
            {"ate_m", ate * k},
            {"frame_trans_err_m", frame_t * k},
            {"frame_rot_err_deg", frame_r * k},
            {"ms_per_cycle", ms * k},
            {"ms_per_cycle_by_stage",
             {{"read", stages.read_ms * k},
              {"front_end", stages.front_end_ms * k},
              {"submap", stages.submap_ms * k},
              {"match", stages.match_ms * k}}},
            {"fallback_rate", fallback * k},
            {"scenes", n}};
  }
};

constexpr std::size_t kDefault = 0;  // the row of the default pipeline
const std::vector<std::string> kMethods = {"pcl-icp", "pw-ndt", "doppler", "rapp-ndt"};
using Cells = std::map<std::pair<std::string, std::size_t>, Cell>;

/// Every method at its rows' N (kDefault: the default pipeline) on every scene.
Cells runCells(const AutomotiveRunOptions& options, const NuScenesDataset& dataset,
               const std::vector<const NuScenesScene*>& scenes, bool progress_on) {
  const std::vector<std::pair<std::string, std::vector<std::size_t>>> plan = {{"pcl-icp", {1, 3, 5, 10, kDefault}},
                                                                              {"pw-ndt", {1, 3, 5, 10, kDefault}},
                                                                              {"doppler", {1, kDefault}},
                                                                              {"rapp-ndt", {1, kDefault}}};
  Cells cells;
  for (const auto& [method, ns] : plan)
    for (const std::size_t N : ns)
      for (const auto* scene : scenes) {
        AutomotiveRunOptions o = withMethod(options, method);
        if (N != kDefault) o.odometry = o.odometry.paper(N);
        const std::string label = method + (N == kDefault ? " default" : " N=" + std::to_string(N));
        cells[{method, N}].add(runAutomotiveOdometry(dataset, *scene, o, Progress{progress_on, label}));
      }
  return cells;
}

std::string fixed(double v, int prec) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

/// The frame errors, ms per cycle by stage and fallbacks of each table entry.
std::string detailTable(const json& entries) {
  std::ostringstream detail;
  detail << "| method | row | ATE (m) | frame trans (m) | frame rot (deg) | ms/cycle (median) | read | front-end | "
            "submap | match | fallbacks |\n"
         << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& e : entries) {
    const json& st = e["ms_per_cycle_by_stage"];
    detail << "| " << e["method"].get<std::string>() << " | "
           << (e.contains("submap") ? "N=" + std::to_string(e["submap"].get<std::size_t>()) : "default") << " | "
           << fixed(e["ate_m"].get<double>(), 3) << " | " << fixed(e["frame_trans_err_m"].get<double>(), 4) << " | "
           << fixed(e["frame_rot_err_deg"].get<double>(), 4) << " | " << fixed(e["ms_per_cycle"].get<double>(), 2)
           << " | " << fixed(st["read"].get<double>(), 2) << " | " << fixed(st["front_end"].get<double>(), 2) << " | "
           << fixed(st["submap"].get<double>(), 3) << " | " << fixed(st["match"].get<double>(), 2) << " | "
           << fixed(100.0 * e["fallback_rate"].get<double>(), 1) << " % |\n";
  }
  return detail.str();
}

}  // namespace

int runNuScenesTable(const AutomotiveRunOptions& options, const NuScenesDataset& dataset,
                     const std::vector<const NuScenesScene*>& scenes, bool json_out, bool progress_on) {
  const Cells cells = runCells(options, dataset, scenes, progress_on);
  const AutomotiveOdometryOptions& d = options.odometry;
  const std::string default_name = std::string(toString(d.mode)) +
                                   (d.mode == AutomotiveMatchMode::CycleToMap ? " M=" + std::to_string(d.map_cycles)
                                                                              : " N=" + std::to_string(d.submap_size)) +
                                   (d.fuse_doppler ? ", fused" : "");
  json j = json::array();
  std::ostringstream md;
  md << "| N | ICP trans % | ICP deg/m | ours trans % | ours deg/m | Kellner trans % | Kellner deg/m | Rapp trans % | "
        "Rapp deg/m |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  for (const std::size_t N : {std::size_t{1}, std::size_t{3}, std::size_t{5}, std::size_t{10}, kDefault}) {
    md << "| " << (N == kDefault ? "default (" + default_name + ")" : std::to_string(N));
    for (const std::string& m : kMethods) {
      const auto it = cells.find({m, N});
      if (it == cells.end()) {
        md << " | | ";
        continue;
      }
      const Cell& c = it->second;
      const double k = 1.0 / c.n;
      md << " | " << fixed(c.trans * k, 2) << " | " << fixed(c.rot * k, 3);
      json e = c.toJson(m);
      if (N == kDefault)
        e["pipeline"] = default_name;
      else
        e["submap"] = N;
      j.push_back(e);
    }
    md << " |\n";
  }
  if (json_out)
    std::cout << json{{"table", j}}.dump(2) << std::endl;
  else
    std::cout << md.str() << "\n" << detailTable(j);
  return 0;
}

}  // namespace apps
}  // namespace radar_ndt
