#include "radar_ndt/evaluation/report.h"

#include <cmath>
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
      case Metric::Kitti: r.kitti = kittiError(pairs, options.kitti_lengths, options.kitti_step); break;
      case Metric::OneMeter: r.one_meter = oneMeterError(pairs, options.one_meter_length); break;
      case Metric::Frame: r.frame = frameError(pairs, options.frame_step); break;
      case Metric::Ate: r.ate = absoluteTrajectoryError(pairs); break;
    }
  }
  return r;
}

namespace {
/// Mean of the finite values (NaN when there are none).
struct DefinedMean {
  double sum = 0;
  std::size_t n = 0;
  void add(double v) {
    if (std::isfinite(v)) sum += v, ++n;
  }
  double value() const { return n ? sum / static_cast<double>(n) : kUndefinedError; }
};

SegmentError meanSegments(const std::vector<const SegmentError*>& runs) {
  SegmentError out;
  DefinedMean t, r;
  for (const SegmentError* e : runs) {
    t.add(e->trans_err_pct);
    r.add(e->rot_err_deg_per_m);
    out.segments += e->segments;
  }
  out.trans_err_pct = t.value();
  out.rot_err_deg_per_m = r.value();
  out.per_length = runs.front()->per_length;
  for (std::size_t i = 0; i < out.per_length.size(); ++i) {
    DefinedMean pt, pr;
    std::size_t segments = 0;
    for (const SegmentError* e : runs)
      if (i < e->per_length.size()) {
        pt.add(e->per_length[i].trans_err_pct);
        pr.add(e->per_length[i].rot_err_deg_per_m);
        segments += e->per_length[i].segments;
      }
    out.per_length[i].trans_err_pct = pt.value();
    out.per_length[i].rot_err_deg_per_m = pr.value();
    out.per_length[i].segments = segments;
  }
  return out;
}
}  // namespace

EvaluationReport meanReport(const std::vector<EvaluationReport>& reports) {
  EvaluationReport mean;
  if (reports.empty()) return mean;
  auto all = [&](auto has) {
    for (const auto& r : reports)
      if (!has(r)) return false;
    return true;
  };
  for (const auto& r : reports) mean.associated_poses += r.associated_poses;
  for (auto metric : {&EvaluationReport::kitti, &EvaluationReport::one_meter})
    if (all([&](const EvaluationReport& r) { return (r.*metric).has_value(); })) {
      std::vector<const SegmentError*> runs;
      for (const auto& r : reports) runs.push_back(&*(r.*metric));
      mean.*metric = meanSegments(runs);
    }
  if (all([](const EvaluationReport& r) { return r.frame.has_value(); })) {
    FrameError f;
    DefinedMean t, rot;
    for (const auto& r : reports) {
      t.add(r.frame->trans_err_m);
      rot.add(r.frame->rot_err_deg);
      f.pairs += r.frame->pairs;
    }
    f.trans_err_m = t.value();
    f.rot_err_deg = rot.value();
    mean.frame = f;
  }
  if (all([](const EvaluationReport& r) { return r.ate.has_value(); })) {
    AbsoluteError a;
    DefinedMean m;
    for (const auto& r : reports) {
      m.add(r.ate->rmse_m);
      a.poses += r.ate->poses;
    }
    a.rmse_m = m.value();
    mean.ate = a;
  }
  return mean;
}

namespace {
nlohmann::json segmentJson(const SegmentError& e) {
  return {{"trans_err_pct", e.trans_err_pct}, {"rot_err_deg_per_m", e.rot_err_deg_per_m}, {"segments", e.segments}};
}
nlohmann::json metricsObject(const EvaluationReport& r) {
  nlohmann::json m = nlohmann::json::object();
  if (r.kitti) m["kitti"] = segmentJson(*r.kitti);
  if (r.one_meter) m["1m"] = segmentJson(*r.one_meter);
  if (r.frame)
    m["frame"] = {
        {"trans_err_m", r.frame->trans_err_m}, {"rot_err_deg", r.frame->rot_err_deg}, {"pairs", r.frame->pairs}};
  if (r.ate) m["ate"] = {{"rmse_m", r.ate->rmse_m}};
  return m;
}
}  // namespace

std::string metricsJson(const EvaluationReport& report) {
  return metricsObject(report).dump();
}

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
  // An undefined error (nothing to average) is "n/a", never a number.
  auto segment_row = [&](const std::string& name, double trans, double rot, std::size_t segments) {
    if (segments > 0)
      std::snprintf(line, sizeof(line), "%-8s %12.5f %% %10.6f deg/m %8zu seg\n", name.c_str(), trans, rot, segments);
    else
      std::snprintf(line, sizeof(line), "%-8s %14s %16s %8zu seg\n", name.c_str(), "n/a", "n/a", segments);
    out << line;
  };
  if (r.kitti) {
    segment_row("kitti", r.kitti->trans_err_pct, r.kitti->rot_err_deg_per_m, r.kitti->segments);
    for (const auto& pl : r.kitti->per_length) {
      char name[16];
      std::snprintf(name, sizeof(name), "  %4.0f m", pl.length);
      segment_row(name, pl.trans_err_pct, pl.rot_err_deg_per_m, pl.segments);
    }
    if (r.kitti->segments == 0 && !r.kitti->per_length.empty())
      out << "         (no KITTI segment: the ground truth is shorter than " << r.kitti->per_length.front().length
          << " m)\n";
  }
  if (r.one_meter) segment_row("1m", r.one_meter->trans_err_pct, r.one_meter->rot_err_deg_per_m, r.one_meter->segments);
  if (r.frame) {
    if (r.frame->pairs > 0)
      std::snprintf(line, sizeof(line), "%-8s %12.5f m %10.5f deg   %8zu pairs\n", "frame", r.frame->trans_err_m,
                    r.frame->rot_err_deg, r.frame->pairs);
    else
      std::snprintf(line, sizeof(line), "%-8s %14s %14s   %8zu pairs\n", "frame", "n/a", "n/a", r.frame->pairs);
    out << line;
  }
  if (r.ate) {
    std::snprintf(line, sizeof(line), "%-8s %12.5f m %16s %8zu poses\n", "ate", r.ate->rmse_m, "", r.ate->poses);
    out << line;
  }
  return out.str();
}

}  // namespace radar_ndt
