#include "radar_ndt/pipeline/automotive_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <utility>

#include "detail/run_timing.h"
#include "pipeline/ordered_pipeline.h"
#include "radar_ndt/io/nuscenes_can_bus.h"

namespace radar_ndt {

using detail::Clock;
using detail::median;
namespace {
double ms(Clock::time_point a, Clock::time_point b) {
  return detail::msBetween(a, b);
}
}  // namespace

void AutomotiveRunOptions::validate() const {
  checkFields(*this, "AutomotiveRunOptions");
  // A method is more than its matcher (withMethod): a half-set combination is refused, not run.
  const bool doppler_weights = findMatcher(matcher.method).uses.doppler_weights;
  if (doppler_weights != odometry.doppler_weights)
    throw std::invalid_argument(std::string("AutomotiveRunOptions: odometry.doppler_weights must be ") +
                                (doppler_weights ? "true" : "false") + " for method " + matcher.method +
                                " (withMethod sets it)");
  const MatcherUses& uses = findMatcher(matcher.method).uses;
  if ((uses.gyro && !odometry.car.gyro) || (uses.wheels && !odometry.car.wheels))
    throw std::invalid_argument("AutomotiveRunOptions: method " + matcher.method + " needs odometry.car." +
                                (uses.gyro && !odometry.car.gyro ? "gyro" : "wheels") + " on (withMethod sets it)");
  if (!uses.doppler_fusion && odometry.fuse_doppler)
    throw std::invalid_argument("AutomotiveRunOptions: odometry.fuse_doppler must be false for method " +
                                matcher.method + ": it is dead reckoning without the radar (withMethod sets it)");
  if (doppler_weights && front_end.remove_moving)
    throw std::invalid_argument("AutomotiveRunOptions: front_end.remove_moving must be false for method " +
                                matcher.method +
                                ": its Doppler weights handle the moving detections (withMethod sets it)");
}

AutomotiveRunOptions withMethod(AutomotiveRunOptions options, const std::string& method) {
  const MatcherUses& uses = findMatcher(method).uses;
  options.matcher.method = method;
  options.odometry.doppler_weights = uses.doppler_weights;
  if (uses.doppler_weights) options.front_end.remove_moving = false;
  options.odometry.car.gyro = options.odometry.car.gyro || uses.gyro;
  options.odometry.car.wheels = options.odometry.car.wheels || uses.wheels;
  if (!uses.doppler_fusion) options.odometry.fuse_doppler = false;
  return options;
}

MatchCalibration matchCalibrationOf(const std::string& method) {
  return findMatcher(method).calibration;
}

AutomotiveRunResult runAutomotiveOdometry(const NuScenesDataset& dataset, const NuScenesScene& scene,
                                          const AutomotiveRunOptions& options,
                                          const std::function<void(std::size_t, std::size_t)>& progress,
                                          const CycleCallback& on_cycle) {
  options.validate();
  return runAutomotiveOdometry(dataset, scene, options, makeMatcher(options.matcher), progress, on_cycle);
}

namespace {

/// Per cycle samples of the stage times and the ego-velocity fit, for the medians and means.
struct CycleSamples {
  std::vector<double> read, front_end, submap, match, total, residual;
  void add(double read_ms, double front_end_ms, const OdometryStep& step) {
    read.push_back(read_ms);
    front_end.push_back(front_end_ms);
    submap.push_back(step.submap_ms);
    match.push_back(step.match_ms);
    total.push_back(read_ms + front_end_ms + step.submap_ms + step.match_ms);
  }
};

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

/// What the front-end found in a cycle: detections, moving ones removed, the ego-velocity fit.
void countFrontEnd(const ProcessedCycle& processed, AutomotiveRunResult& result, CycleSamples& samples) {
  result.detections += processed.raw_points;
  result.removed_moving += processed.removed_moving;
  if (processed.ego.valid) {
    samples.residual.push_back(processed.ego.residual_rms);
    if (processed.ego.nonholonomic) ++result.nonholonomic_velocity_cycles;
    if (processed.ego.forward_only) ++result.forward_speed_cycles;
  } else {
    ++result.invalid_velocity_cycles;
  }
  result.ego_speed.push_back(processed.ego.valid ? processed.ego.velocity.head<2>().norm()
                                                 : std::numeric_limits<double>::quiet_NaN());
}

/// A cycle read and through the front-end without a fallback ego-velocity (what a worker thread
/// can do ahead of the odometry), with the problems met reading it.
struct PreparedCycle {
  std::size_t index = 0;
  RadarCycle cycle;
  ProcessedCycle processed;
  std::vector<std::string> problems;
  double read_ms = 0, front_end_ms = 0;
};

PreparedCycle prepareCycle(const RadarCycleSource& sequence, const AutomotiveFrontEnd& front_end, std::size_t k) {
  PreparedCycle p;
  p.index = k;
  const auto t0 = Clock::now();
  p.cycle = sequence.load(k, &p.problems);
  const auto t1 = Clock::now();
  p.processed = front_end.process(p.cycle);
  p.read_ms = ms(t0, t1);
  p.front_end_ms = ms(t1, Clock::now());
  return p;
}

/// The scene's CAN bus when the options fuse it: none, said in `problems`, when the dataroot has no
/// can_bus folder (a method that is the car's own dead reckoning cannot run without it).
std::shared_ptr<const VehicleSignals> vehicleSignals(const NuScenesDataset& dataset, const NuScenesScene& scene,
                                                     const AutomotiveRunOptions& options,
                                                     std::vector<std::string>& problems) {
  std::optional<VehicleSignals> signals = readNuScenesCanBus(dataset.dataroot(), scene.name);
  if (signals) {
    if (signals->dropped)
      problems.push_back(signals->source + ": " + std::to_string(signals->dropped) +
                         " CAN messages without a value (NaN) left out");
    return std::make_shared<const VehicleSignals>(std::move(*signals));
  }
  const MatcherUses& uses = findMatcher(options.matcher.method).uses;
  const std::string missing = dataset.dataroot() + "/can_bus: missing";
  if (uses.gyro || uses.wheels)
    throw std::invalid_argument(missing + ": method " + options.matcher.method + " needs the car's CAN bus");
  problems.push_back(missing + ": the run goes on without the car's gyro and wheel speeds");
  return nullptr;
}

/// What the guesses come from when the car's sensors make them.
std::string carPriorName(const CarSensorOptions& car) {
  return car.gyro && car.wheels ? "the car's gyro and wheels"
         : car.gyro             ? "the car's gyro, Doppler translation"
                                : "the car's wheels, Doppler yaw";
}

/// A cycle a matcher could not match for too few points, as a problem naming it; "" otherwise.
std::string problemOf(const OdometryStep& step, const AutomotiveOdometryOptions& options) {
  if (step.status != StepStatus::DeadReckoned || !step.too_few_points) return "";
  return "too few points to match (" + std::to_string(step.source_points) + " in the cycle, " +
         std::to_string(step.target_points) + " in its target; at least " + std::to_string(options.min_points) +
         " each): the Doppler motion";
}

/// The result's description of the run, before its cycles: scene, method, reference radar, the
/// inputs' problems first and then the radars' silences.
AutomotiveRunResult startResult(const AutomotiveInputs& inputs, const AutomotiveRunOptions& options, bool uses_car) {
  AutomotiveRunResult result;
  result.scene = inputs.cycles.sceneName();
  result.method = options.matcher.method;
  result.submap_size = options.odometry.submap_size;
  result.reference_channel = inputs.cycles.referenceChannel();
  result.period_s = inputs.cycles.periodSeconds();
  if (uses_car) result.prior = carPriorName(options.odometry.car);
  result.problems = inputs.problems;
  const auto& silences = inputs.cycles.silences();
  result.problems.insert(result.problems.end(), silences.begin(), silences.end());
  return result;
}

/// A method that is the car's own dead reckoning cannot run on a recording without the car's sensors.
void checkCarInputs(const AutomotiveInputs& inputs, const AutomotiveRunOptions& options) {
  const MatcherUses& uses = findMatcher(options.matcher.method).uses;
  if ((uses.gyro || uses.wheels) && !inputs.car)
    throw std::invalid_argument(inputs.cycles.sceneName() + ": method " + options.matcher.method +
                                " needs the car's own sensors, and the recording has none");
}

}  // namespace

AutomotiveRunResult runAutomotiveOdometry(const NuScenesDataset& dataset, const NuScenesScene& scene,
                                          const AutomotiveRunOptions& options, MatcherAdapter matcher,
                                          const std::function<void(std::size_t, std::size_t)>& progress,
                                          const CycleCallback& on_cycle) {
  options.validate();
  const NuScenesRadarSequence sequence(dataset, scene, options.sequence);
  AutomotiveInputs inputs{sequence, nullptr, {}};
  if (options.odometry.car.any()) inputs.car = vehicleSignals(dataset, scene, options, inputs.problems);
  return runAutomotiveOdometry(inputs, options, std::move(matcher), progress, on_cycle);
}

namespace {

/// One cycle, read and through the front-end, into the odometry: the same for a run and a stream.
/// A cycle whose own ego-velocity fit failed is processed again with the last valid one as the
/// fallback, which only the order knows.
class CycleStepper {
 public:
  CycleStepper(const AutomotiveFrontEnd& front_end, AutomotiveOdometry& odometry, const AutomotiveRunOptions& options,
               AutomotiveRunResult& result)
      : front_end_(front_end), odometry_(odometry), options_(options), result_(result) {}

  /// The step `p` made; its problems (and a match refused for too few points) go into the result,
  /// named by the cycle's index.
  const OdometryStep& add(PreparedCycle& p) {
    if (!p.processed.ego.valid && have_valid_) {
      const auto t = Clock::now();
      p.processed = front_end_.process(p.cycle, &last_valid_);
      p.front_end_ms += ms(t, Clock::now());
    }
    countFrontEnd(p.processed, result_, samples_);
    if (p.processed.ego.valid) {
      last_valid_ = p.processed.ego;
      have_valid_ = true;
    }
    const OdometryStep& step = odometry_.add(p.processed);
    const std::string problem = problemOf(step, options_.odometry);
    if (!problem.empty()) p.problems.push_back(problem);
    for (const auto& q : p.problems) result_.problems.push_back("cycle " + std::to_string(p.index) + ": " + q);
    samples_.add(p.read_ms, p.front_end_ms, step);
    return step;
  }

  /// The result's figures and trajectory from the steps so far.
  void finish() const {
    result_.median_ms = {median(samples_.read), median(samples_.front_end), median(samples_.submap),
                         median(samples_.match)};
    result_.mean_ms = {mean(samples_.read), mean(samples_.front_end), mean(samples_.submap), mean(samples_.match)};
    result_.median_total_ms = median(samples_.total);
    result_.median_doppler_residual = median(samples_.residual);
    result_.steps = odometry_.steps();
    result_.counters = odometry_.counters();
    result_.estimate = odometry_.trajectory();
  }

 private:
  const AutomotiveFrontEnd& front_end_;
  AutomotiveOdometry& odometry_;
  const AutomotiveRunOptions& options_;
  AutomotiveRunResult& result_;
  CycleSamples samples_;
  EgoVelocity last_valid_;
  bool have_valid_ = false;
};

}  // namespace

AutomotiveRunResult runAutomotiveOdometry(const AutomotiveInputs& inputs, const AutomotiveRunOptions& options,
                                          MatcherAdapter matcher,
                                          const std::function<void(std::size_t, std::size_t)>& progress,
                                          const CycleCallback& on_cycle) {
  options.validate();
  const RadarCycleSource& sequence = inputs.cycles;
  const AutomotiveFrontEnd front_end(options.front_end);
  AutomotiveOdometry odometry(options.odometry, std::move(matcher));
  checkCarInputs(inputs, options);
  if (options.odometry.car.any() && inputs.car) odometry.setVehicleSignals(inputs.car);
  AutomotiveRunResult result = startResult(inputs, options, odometry.usesCar());
  const std::size_t n = options.max_cycles > 0 ? std::min(options.max_cycles, sequence.size()) : sequence.size();
  CycleStepper stepper(front_end, odometry, options, result);
  // Cycles are read and through the front-end on the worker threads, the odometry takes them here in
  // order: the same result as one thread gives.
  detail::runOrdered<PreparedCycle>(
      0, n, options.threads, [&](std::size_t k) { return prepareCycle(sequence, front_end, k); },
      [&](PreparedCycle& p) {
        const OdometryStep& step = stepper.add(p);
        if (on_cycle) on_cycle(p.index, step, *p.processed.cloud);
        if (progress) progress(p.index + 1, n);
      });
  stepper.finish();
  const Trajectory gt = sequence.groundTruthTrajectory();
  const auto m = static_cast<std::ptrdiff_t>(std::min(n, std::min(gt.stamps.size(), gt.poses.size())));
  result.ground_truth.stamps.assign(gt.stamps.begin(), gt.stamps.begin() + m);
  result.ground_truth.poses.assign(gt.poses.begin(), gt.poses.begin() + m);
  return result;
}

struct AutomotiveStream::Impl {
  Impl(const AutomotiveRunOptions& o, std::shared_ptr<const VehicleSignals> car_signals, const std::string& name)
      : options((o.validate(), o)),
        front_end(options.front_end),
        odometry(options.odometry, makeMatcher(options.matcher)),
        stepper(front_end, odometry, options, result) {
    const MatcherUses& uses = findMatcher(options.matcher.method).uses;
    if ((uses.gyro || uses.wheels || options.odometry.car.any()) && !car_signals)
      throw std::invalid_argument(name + ": the options fuse the car's own sensors, and the stream has none");
    if (options.odometry.car.any()) odometry.setVehicleSignals(std::move(car_signals));
    result.scene = name;
    result.method = options.matcher.method;
    result.submap_size = options.odometry.submap_size;
    if (odometry.usesCar()) result.prior = carPriorName(options.odometry.car);
  }
  AutomotiveRunOptions options;
  AutomotiveRunResult result;
  AutomotiveFrontEnd front_end;
  AutomotiveOdometry odometry;
  CycleStepper stepper;
  std::size_t cycles = 0;
};

AutomotiveStream::AutomotiveStream(const AutomotiveRunOptions& options, std::shared_ptr<const VehicleSignals> car,
                                   const std::string& name)
    : impl_(std::make_unique<Impl>(options, std::move(car), name)) {}
AutomotiveStream::~AutomotiveStream() = default;

AutomotiveStream::Added AutomotiveStream::add(RadarCycle cycle) {
  PreparedCycle p;
  p.index = impl_->cycles++;
  p.cycle = std::move(cycle);
  const auto t0 = Clock::now();
  p.processed = impl_->front_end.process(p.cycle);
  p.front_end_ms = ms(t0, Clock::now());
  const std::size_t said = impl_->result.problems.size();
  Added a{impl_->stepper.add(p), p.processed.cloud, {}};
  a.problems.assign(impl_->result.problems.begin() + static_cast<std::ptrdiff_t>(said), impl_->result.problems.end());
  return a;
}

const AutomotiveOdometry& AutomotiveStream::odometry() const {
  return impl_->odometry;
}

AutomotiveRunResult AutomotiveStream::result() const {
  impl_->stepper.finish();
  return impl_->result;
}

void runAutomotiveScenes(const NuScenesDataset& dataset, const std::vector<const NuScenesScene*>& scenes,
                         const AutomotiveRunOptions& options,
                         const std::function<void(std::size_t, const AutomotiveRunResult&)>& done,
                         const std::function<void(std::size_t, std::size_t)>& progress) {
  options.validate();
  const int threads = detail::resolveThreads(options.threads);
  AutomotiveRunOptions one_scene = options;
  if (scenes.size() > 1 && threads > 1) one_scene.threads = 1;  // the scenes, not the cycles, side by side
  const int scene_threads = scenes.size() > 1 ? threads : 1;
  using Indexed = std::pair<std::size_t, AutomotiveRunResult>;
  detail::runOrdered<Indexed>(
      0, scenes.size(), scene_threads,
      [&](std::size_t i) { return Indexed(i, runAutomotiveOdometry(dataset, *scenes[i], one_scene)); },
      [&](Indexed& r) {
        done(r.first, r.second);
        if (progress) progress(r.first + 1, scenes.size());
      });
}

}  // namespace radar_ndt
