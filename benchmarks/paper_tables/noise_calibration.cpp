// radar_paper_tables --noise-calibration (tables.h): the fusion's covariances calibrated on every
// scene, checked leaving each scene out in turn (calibrated on the others, mean NEES on it; 3 is
// calibrated), and what the match adds to the Doppler motion per axis.
#include <cstdio>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "motion_noise.h"
#include "pipeline_options.h"
#include "radar_ndt/evaluation/report.h"
#include "tables.h"

namespace radar_ndt {
namespace apps {

using nlohmann::json;

namespace {

json calibrationJson(const MotionNoiseCalibration& c) {
  return json{{"doppler_sigma_x", c.doppler_sigma_x},     {"doppler_sigma_y", c.doppler_sigma_y},
              {"doppler_sigma_yaw", c.doppler_sigma_yaw}, {"match_covariance_scale", c.match_covariance_scale},
              {"match_sigma_x", c.match_sigma_x},         {"match_sigma_y", c.match_sigma_y},
              {"match_sigma_yaw", c.match_sigma_yaw},     {"doppler_samples", c.doppler_samples},
              {"match_samples", c.match_samples}};
}

json errorsJson(const EvaluationReport& r) {
  return {{"trans_err_pct", r.one_meter->trans_err_pct},
          {"rot_err_deg_per_m", r.one_meter->rot_err_deg_per_m},
          {"ate_m", r.ate->rmse_m}};
}

/// Every scene's run with the defaults and its samples.
struct SceneRuns {
  std::vector<AutomotiveRunResult> runs;
  std::vector<std::vector<MotionNoiseSample>> samples;
  /// The samples of every scene but `skip` (all for skip = scenes).
  std::vector<MotionNoiseSample> allBut(std::size_t skip) const {
    std::vector<MotionNoiseSample> v;
    for (std::size_t i = 0; i < samples.size(); ++i)
      if (i != skip) v.insert(v.end(), samples[i].begin(), samples[i].end());
    return v;
  }
};

/// Scene i left out: calibrated on the others, its NEES, and the scene run again with that
/// calibration against its run with the defaults (a markdown row and a JSON entry).
void leaveOneOut(const AutomotiveRunOptions& options, const NuScenesDataset& dataset, const NuScenesScene& scene,
                 const SceneRuns& s, std::size_t i, std::ostringstream& md, json& out) {
  const MotionNoiseCalibration c = calibrateMotionNoise(s.allBut(i));
  const MatchCalibration which = matchCalibrationOf(options.matcher.method);
  const MotionNees nees = motionNees(s.samples[i], c.applyTo(options.odometry.fusion, which), which);
  const EvaluationReport before =
      evaluate(associate(s.runs[i].ground_truth, s.runs[i].estimate), {Metric::OneMeter, Metric::Ate});
  AutomotiveRunOptions o = options;
  o.odometry.fusion = c.applyTo(options.odometry.fusion, which);
  const AutomotiveRunResult rerun = runAutomotiveOdometry(dataset, scene, o);
  const EvaluationReport after =
      evaluate(associate(rerun.ground_truth, rerun.estimate), {Metric::OneMeter, Metric::Ate});
  char b[256];
  std::snprintf(b, sizeof b, "| %s | %.2f | %.2f | %zu | %zu | %.3f → %.3f | %.4f → %.4f | %.3f → %.3f |\n",
                scene.name.c_str(), nees.doppler, nees.match, nees.doppler_samples, nees.match_samples,
                before.one_meter->trans_err_pct, after.one_meter->trans_err_pct, before.one_meter->rot_err_deg_per_m,
                after.one_meter->rot_err_deg_per_m, before.ate->rmse_m, after.ate->rmse_m);
  md << b;
  out["leave_one_out"].push_back({{"scene", scene.name},
                                  {"calibration", calibrationJson(c)},
                                  {"doppler_nees", nees.doppler},
                                  {"match_nees", nees.match},
                                  {"doppler_samples", nees.doppler_samples},
                                  {"match_samples", nees.match_samples},
                                  {"defaults", errorsJson(before)},
                                  {"left_out_calibration", errorsJson(after)}});
}

/// What the match adds to the Doppler motion per axis, with the best fixed weight the ground truth
/// itself would choose per scene (an upper bound for any linear fusion of the two).
void matchInformationRows(const std::vector<const NuScenesScene*>& scenes, const SceneRuns& s, std::ostringstream& md,
                          json& out) {
  md << "\nwhat the match adds (oracle: the best fixed weight on match − Doppler, chosen with the ground truth per "
        "scene)\n\n"
     << "| scene | axis | Doppler RMS | match RMS | correlation | oracle weight | oracle RMS | gain "
        "|\n|---|---|---|---|---|---|---|---|\n";
  out["match_information"] = json::array();
  char b[256];
  for (std::size_t i = 0; i < s.samples.size(); ++i) {
    const MatchInformation info = matchInformation(s.samples[i]);
    const char* names[3] = {"x (mm)", "y (mm)", "yaw (mrad)"};
    json axes = json::array();
    for (int a = 0; a < 3; ++a) {
      const MatchInformationAxis& x = info.axis[a];
      std::snprintf(b, sizeof b, "| %s | %s | %.2f | %.2f | %.2f | %.3f | %.2f | %.1f %% |\n", scenes[i]->name.c_str(),
                    names[a], 1e3 * x.doppler_rms, 1e3 * x.match_rms, x.correlation, x.oracle_weight,
                    1e3 * x.oracle_rms, 100.0 * (x.oracle_rms / x.doppler_rms - 1.0));
      md << b;
      axes.push_back({{"doppler_rms", x.doppler_rms},
                      {"match_rms", x.match_rms},
                      {"correlation", x.correlation},
                      {"oracle_weight", x.oracle_weight},
                      {"oracle_rms", x.oracle_rms}});
    }
    out["match_information"].push_back({{"scene", scenes[i]->name}, {"samples", info.samples}, {"x_y_yaw", axes}});
  }
}

}  // namespace

int runNoiseCalibration(const AutomotiveRunOptions& options, const NuScenesDataset& dataset,
                        const std::vector<const NuScenesScene*>& scenes, bool json_out, bool progress_on) {
  SceneRuns s;
  for (const auto* scene : scenes) {
    s.runs.push_back(runAutomotiveOdometry(dataset, *scene, options, Progress{progress_on, scene->name}));
    s.samples.push_back(motionNoiseSamples(s.runs.back()));
  }
  const MotionNoiseCalibration all = calibrateMotionNoise(s.allBut(s.samples.size()));
  json out = {{"method", options.matcher.method},
              {"calibrated_on_all", calibrationJson(all)},
              {"leave_one_out", json::array()}};
  std::ostringstream md;
  char b[256];
  std::snprintf(b, sizeof b,
                "calibrated on all %zu scenes (%s): Doppler σ %.4f m/s, %.4f m/s, %.5f rad/s; match covariance x %.3f; "
                "match σ %.4f m, %.4f m, %.5f rad\n\n",
                scenes.size(), options.matcher.method.c_str(), all.doppler_sigma_x, all.doppler_sigma_y,
                all.doppler_sigma_yaw, all.match_covariance_scale, all.match_sigma_x, all.match_sigma_y,
                all.match_sigma_yaw);
  md << b
     << "| left out | Doppler NEES | match NEES | cycles | matches | 1m % (defaults → left-out calibration) | deg/m | "
        "ATE m |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < s.samples.size(); ++i) leaveOneOut(options, dataset, *scenes[i], s, i, md, out);
  matchInformationRows(scenes, s, md, out);
  if (json_out)
    std::cout << out.dump(2) << std::endl;
  else
    std::cout << md.str();
  return 0;
}

}  // namespace apps
}  // namespace radar_ndt
