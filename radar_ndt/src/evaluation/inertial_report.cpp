// The 6-DoF run's reports (run_report.h): the same outputs as the planar pipelines'.
#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "detail/printf_string.h"
#include "radar_ndt/evaluation/run_report.h"

namespace radar_ndt {

namespace {

using nlohmann::json;

using detail::format;

/// The median of the matched steps' match times (ms); 0 without.
double medianMatchMs(const InertialRunResult& r) {
  std::vector<double> ms;
  for (const OdometryStep3D& s : r.steps)
    if (s.matched || s.fallback) ms.push_back(s.match_ms);
  if (ms.empty()) return 0;
  std::nth_element(ms.begin(), ms.begin() + static_cast<std::ptrdiff_t>(ms.size() / 2), ms.end());
  return ms[ms.size() / 2];
}

/// The run's wall time a scan (ms), reading included.
double msPerScan(const InertialRunResult& r) {
  return r.scans ? 1000.0 * r.seconds / static_cast<double>(r.scans) : 0.0;
}

double recordedSeconds(const InertialRunResult& r) {
  return r.estimate.size() > 1 ? r.estimate.stamps.back() - r.estimate.stamps.front() : 0.0;
}

}  // namespace

std::string stepsCsv(const InertialRunResult& r) {
  std::string out =
      "stamp,x,y,z,qx,qy,qz,qw,vx,vy,vz,velocity_valid,matched,fallback,still,skipped,points,static_points,"
      "iterations,match_ms,why\n";
  for (const OdometryStep3D& s : r.steps) {
    const Eigen::Quaterniond q(s.pose.linear());
    const Eigen::Vector3d& p = s.pose.translation();
    std::string why = s.why;
    std::replace(why.begin(), why.end(), ',', ';');
    out += format("%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.6g,%.6g,%.6g,%d,%d,%d,%d,%d,%zu,%zu,%d,%.3f,%s\n", s.stamp,
                  p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w(), s.velocity.x(), s.velocity.y(), s.velocity.z(),
                  s.velocity_valid, s.matched, s.fallback, s.still, s.skipped, s.points, s.static_points, s.iterations,
                  s.match_ms, why.c_str());
  }
  return out;
}

double realTimeFactor(const InertialRunResult& r) {
  return r.seconds > 0 ? recordedSeconds(r) / r.seconds : 0.0;
}

std::string summaryJson(const InertialRunResult& r, const EvaluationReport* metrics) {
  json j;
  j["sequence"] = r.sequence;
  j["pipeline"] = "6-DoF";
  j["method"] = r.method;
  j["imu"] = r.imu;
  j["radar"] = r.radar;
  if (r.radars > 1) j["radars"] = r.radars;  // a rig of several (one radar: not written)
  j["prior"] = r.prior;
  j["scans"] = r.scans;
  j["scan_period_s"] = r.period_s;
  j["poses"] = r.estimate.size();
  j["matched"] = r.matched;
  j["fallbacks"] = r.fallbacks;
  j["still"] = r.still;
  j["skipped"] = r.skipped;
  j["unreadable"] = r.unreadable;
  j["problems"] = r.problems.size();
  j["ms_per_scan"] = msPerScan(r);
  j["match_ms_median"] = medianMatchMs(r);
  j["real_time_factor"] = realTimeFactor(r);
  if (metrics) j["metrics"] = json::parse(metricsJson(*metrics));
  return j.dump(2);
}

RunEvaluation evaluateRun(const InertialRunResult& run, const std::vector<Metric>& metrics) {
  RunEvaluation e;
  e.report = evaluate(associate(run.ground_truth, run.estimate), metrics.empty() ? defaultMetrics(run) : metrics);
  e.prior_label = run.prior;
  return e;
}

std::string summaryJson(const InertialRunResult& run, const RunEvaluation& evaluation) {
  return summaryJson(run, &evaluation.report);
}

std::string failureText(const InertialRunResult& r) {
  const std::size_t bad = r.fallbacks + r.unreadable;
  if (r.scans < 2 || 2 * bad <= r.scans - 1) return "";
  return format(
      "%s: mostly not matched: %zu fallbacks and %zu unreadable scans of %zu; check the radar's fields and range "
      "(its description), the accuracy settings, or try --imu\n",
      r.sequence.c_str(), r.fallbacks, r.unreadable, r.scans);
}

namespace {

/// The radar that ran, or the reference and how many with it.
std::string radarsText(const InertialRunResult& r) {
  if (r.radars <= 1) return r.radar;
  return r.radar + " and " + std::to_string(r.radars - 1) + " more radar" + (r.radars > 2 ? "s" : "");
}

}  // namespace

std::string summaryText(const InertialRunResult& r) {
  std::string s = format(
      "%s: %zu scans of %s (%.2f Hz), %s%s: %zu poses, %zu matched, %zu fallbacks, %zu still, %zu skipped, %zu "
      "unreadable; %zu problems\n",
      r.sequence.c_str(), r.scans, radarsText(r).c_str(), r.period_s > 0 ? 1.0 / r.period_s : 0.0, r.method.c_str(),
      r.imu && r.method != "doppler-imu" ? " + IMU" : "", r.estimate.size(), r.matched, r.fallbacks, r.still, r.skipped,
      r.unreadable, r.problems.size());
  s += format("  prior: %s; ms per scan %.2f (match, median %.2f), %.0fx real time (one thread)\n", r.prior.c_str(),
              msPerScan(r), medianMatchMs(r), realTimeFactor(r));
  return s;
}

}  // namespace radar_ndt
