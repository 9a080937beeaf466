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
    else if (word == "ate6")
      add(Metric::Ate6Dof);
    else if (word == "re")
      add(Metric::Relative);
    else if (word == "final")
      add(Metric::Final);
    else if (word == "all") {
      for (Metric m : {Metric::Kitti, Metric::OneMeter, Metric::Frame, Metric::Ate, Metric::SixDof}) add(m);
    } else
      throw std::invalid_argument("unknown metric '" + word +
                                  "' (expected kitti, 1m, frame, ate, ate6, re, final or all)");
  }
  if (out.empty())
    throw std::invalid_argument("no metric given (expected kitti, 1m, frame, ate, ate6, re, final or all)");
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
      case Metric::Ate6Dof:
        r.ate_se3 = absoluteTrajectoryError6Dof(pairs, TrajectoryAlignment::SE3);
        r.ate_posyaw = absoluteTrajectoryError6Dof(pairs, TrajectoryAlignment::PositionYaw);
        break;
      case Metric::Relative:
        r.relative.clear();
        for (double d : options.re_distances)
          r.relative.push_back(relativeError(pairs, d, options.re_max_difference * d));
        break;
      case Metric::Final: r.final_error = finalPositionError(pairs); break;
      case Metric::SixDof:
        if (!isPlanar(pairs)) {
          std::vector<Metric> six{Metric::Ate6Dof, Metric::Relative, Metric::Final};
          const EvaluationReport more = evaluate(pairs, six, options);
          r.ate_se3 = more.ate_se3;
          r.ate_posyaw = more.ate_posyaw;
          r.relative = more.relative;
          r.final_error = more.final_error;
        }
        break;
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
/// meanReport's 6-DoF part: each metric averaged where every report has it.
void meanSixDof(const std::vector<EvaluationReport>& reports, EvaluationReport& mean) {
  auto all = [&](auto has) {
    for (const auto& r : reports)
      if (!has(r)) return false;
    return true;
  };
  for (auto metric : {&EvaluationReport::ate_se3, &EvaluationReport::ate_posyaw})
    if (all([&](const EvaluationReport& r) { return (r.*metric).has_value(); })) {
      AbsoluteError6Dof a;
      DefinedMean t, rot;
      for (const auto& r : reports) {
        t.add((r.*metric)->rmse_m);
        rot.add((r.*metric)->rot_rmse_deg);
        a.poses += (r.*metric)->poses;
      }
      a.rmse_m = t.value();
      a.rot_rmse_deg = rot.value();
      mean.*metric = a;
    }
  const std::size_t n_re = reports.front().relative.size();
  if (n_re > 0 && all([&](const EvaluationReport& r) { return r.relative.size() == n_re; }))
    for (std::size_t i = 0; i < n_re; ++i) {
      RelativeError e;
      e.distance = reports.front().relative[i].distance;
      DefinedMean tm, tmed, trms, tpct, yaw, grav, rot;
      for (const auto& r : reports) {
        const RelativeError& x = r.relative[i];
        tm.add(x.trans_mean_m);
        tmed.add(x.trans_median_m);
        trms.add(x.trans_rmse_m);
        tpct.add(x.trans_mean_pct);
        yaw.add(x.yaw_mean_deg);
        grav.add(x.gravity_mean_deg);
        rot.add(x.rot_mean_deg);
        e.samples += x.samples;
      }
      e.trans_mean_m = tm.value();
      e.trans_median_m = tmed.value();
      e.trans_rmse_m = trms.value();
      e.trans_mean_pct = tpct.value();
      e.yaw_mean_deg = yaw.value();
      e.gravity_mean_deg = grav.value();
      e.rot_mean_deg = rot.value();
      mean.relative.push_back(e);
    }
  if (all([](const EvaluationReport& r) { return r.final_error.has_value(); })) {
    FinalError f;
    DefinedMean m, pct, d;
    for (const auto& r : reports) {
      m.add(r.final_error->final_m);
      pct.add(r.final_error->final_pct);
      d.add(r.final_error->distance_m);
    }
    f.final_m = m.value();
    f.final_pct = pct.value();
    f.distance_m = d.value();
    mean.final_error = f;
  }
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
  meanSixDof(reports, mean);
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
  if (r.ate_se3 && r.ate_posyaw)
    m["ate6"] = {{"se3", {{"rmse_m", r.ate_se3->rmse_m}, {"rot_rmse_deg", r.ate_se3->rot_rmse_deg}}},
                 {"posyaw", {{"rmse_m", r.ate_posyaw->rmse_m}, {"rot_rmse_deg", r.ate_posyaw->rot_rmse_deg}}},
                 {"poses", r.ate_se3->poses}};
  if (!r.relative.empty()) {
    nlohmann::json re = nlohmann::json::array();
    for (const RelativeError& e : r.relative)
      re.push_back({{"distance_m", e.distance},
                    {"samples", e.samples},
                    {"trans_mean_m", e.trans_mean_m},
                    {"trans_median_m", e.trans_median_m},
                    {"trans_rmse_m", e.trans_rmse_m},
                    {"trans_mean_pct", e.trans_mean_pct},
                    {"yaw_mean_deg", e.yaw_mean_deg},
                    {"gravity_mean_deg", e.gravity_mean_deg},
                    {"rot_mean_deg", e.rot_mean_deg}});
    m["re"] = re;
  }
  if (r.final_error)
    m["final"] = {{"final_m", r.final_error->final_m},
                  {"final_pct", r.final_error->final_pct},
                  {"distance_m", r.final_error->distance_m}};
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

namespace {
/// formatTable's 6-DoF rows.
void sixDofRows(const EvaluationReport& r, std::ostringstream& out) {
  char line[256];
  auto ate6_row = [&](const char* name, const AbsoluteError6Dof& a) {
    std::snprintf(line, sizeof(line), "%-8s %12.5f m %10.5f deg   %8zu poses\n", name, a.rmse_m, a.rot_rmse_deg,
                  a.poses);
    out << line;
  };
  if (r.ate_se3) ate6_row("ate-se3", *r.ate_se3);
  if (r.ate_posyaw) ate6_row("ate-pyaw", *r.ate_posyaw);
  for (const RelativeError& e : r.relative) {
    char name[16];
    std::snprintf(name, sizeof(name), "re %.0f m", e.distance);
    if (e.samples >= 2)
      std::snprintf(line, sizeof(line),
                    "%-8s %12.5f m %10.5f deg   %8zu samples  (%.3f %%, yaw %.3f deg, gravity %.3f deg)\n", name,
                    e.trans_mean_m, e.rot_mean_deg, e.samples, e.trans_mean_pct, e.yaw_mean_deg, e.gravity_mean_deg);
    else
      std::snprintf(line, sizeof(line), "%-8s %14s %14s   %8zu samples\n", name, "n/a", "n/a", e.samples);
    out << line;
  }
  if (r.final_error) {
    std::snprintf(line, sizeof(line), "%-8s %12.5f m %12.4f %%   of %.1f m\n", "final", r.final_error->final_m,
                  r.final_error->final_pct, r.final_error->distance_m);
    out << line;
  }
}
}  // namespace

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
  sixDofRows(r, out);
  return out.str();
}

}  // namespace radar_ndt
