#include "radar_ndt/evaluation_report.h"

#include <cstdio>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace radar_ndt {

std::vector<Metric> parseMetrics(const std::string& text) {
  std::vector<Metric> out;
  auto add = [&out](Metric m) {
    for (Metric x : out)
      if (x == m) return;
    out.push_back(m);
  };
  std::stringstream ss(text);
  std::string word;
  while (std::getline(ss, word, ',')) {
    if (word == "kitti")
      add(Metric::Kitti);
    else if (word == "1m")
      add(Metric::OneMeter);
    else if (word == "frame")
      add(Metric::Frame);
    else if (word == "ate")
      add(Metric::Ate);
    else if (word == "all") {
      for (Metric m : {Metric::Kitti, Metric::OneMeter, Metric::Frame, Metric::Ate}) add(m);
    } else
      throw std::invalid_argument("unknown metric '" + word + "' (expected kitti, 1m, frame, ate or all)");
  }
  if (out.empty()) throw std::invalid_argument("no metric given (expected kitti, 1m, frame, ate or all)");
  return out;
}

EvaluationReport evaluate(const PosePairs& pairs, const std::vector<Metric>& metrics,
                          const EvaluationOptions& options) {
  EvaluationReport r;
  r.associated_poses = pairs.size();
  for (Metric m : metrics) {
    switch (m) {
      case Metric::Kitti:
        r.kitti = kittiError(pairs, options.kitti_lengths, options.kitti_step);
        break;
      case Metric::OneMeter:
        r.one_meter = oneMeterError(pairs, options.one_meter_length);
        break;
      case Metric::Frame:
        r.frame = frameError(pairs, options.frame_step);
        break;
      case Metric::Ate:
        r.ate = absoluteTrajectoryError(pairs);
        break;
    }
  }
  return r;
}

namespace {
nlohmann::json segmentJson(const SegmentError& e) {
  return {{"trans_err_pct", e.trans_err_pct}, {"rot_err_deg_per_m", e.rot_err_deg_per_m}, {"segments", e.segments}};
}
nlohmann::json metricsObject(const EvaluationReport& r) {
  nlohmann::json m = nlohmann::json::object();
  if (r.kitti) m["kitti"] = segmentJson(*r.kitti);
  if (r.one_meter) m["1m"] = segmentJson(*r.one_meter);
  if (r.frame) m["frame"] = {{"trans_err_m", r.frame->trans_err_m}, {"rot_err_deg", r.frame->rot_err_deg}, {"pairs", r.frame->pairs}};
  if (r.ate) m["ate"] = {{"rmse_m", r.ate->rmse_m}};
  return m;
}
}  // namespace

std::string metricsJson(const EvaluationReport& report) { return metricsObject(report).dump(); }

std::string toJson(const EvaluationReport& report) {
  nlohmann::json j;
  j["metrics"] = metricsObject(report);
  return j.dump(2);
}

std::string formatTable(const EvaluationReport& r) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof(line), "%-8s %14s %16s %12s\n", "metric", "translation", "rotation", "count");
  out << line;
  auto segment_row = [&](const char* name, const SegmentError& e) {
    std::snprintf(line, sizeof(line), "%-8s %12.5f %% %10.6f deg/m %8zu seg\n", name, e.trans_err_pct,
                  e.rot_err_deg_per_m, e.segments);
    out << line;
  };
  if (r.kitti) {
    segment_row("kitti", *r.kitti);
    for (const auto& pl : r.kitti->per_length) {
      std::snprintf(line, sizeof(line), "  %4.0f m %12.5f %% %10.6f deg/m %8zu seg\n", pl.length, pl.trans_err_pct,
                    pl.rot_err_deg_per_m, pl.segments);
      out << line;
    }
  }
  if (r.one_meter) segment_row("1m", *r.one_meter);
  if (r.frame) {
    std::snprintf(line, sizeof(line), "%-8s %12.5f m %10.5f deg   %8zu pairs\n", "frame", r.frame->trans_err_m,
                  r.frame->rot_err_deg, r.frame->pairs);
    out << line;
  }
  if (r.ate) {
    std::snprintf(line, sizeof(line), "%-8s %12.5f m %16s %8zu poses\n", "ate", r.ate->rmse_m, "", r.ate->poses);
    out << line;
  }
  return out.str();
}

}  // namespace radar_ndt
