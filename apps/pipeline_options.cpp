#include "pipeline_options.h"

#include <cstdio>
#include <map>
#include <set>
#include <stdexcept>

#include "field_options.h"
#include "radar_ndt/io/dataset_format.h"

namespace radar_ndt {
namespace apps {

namespace po = boost::program_options;

namespace {

using AutomotiveField = FieldOption<AutomotiveRunOptions>;
using ScanningField = FieldOption<ScanningRunOptions>;
using InertialField = FieldOption<InertialRunOptions>;

const std::vector<AutomotiveField>& automotiveFields() {
  static const std::vector<AutomotiveField> fields = fieldOptions(AutomotiveRunOptions{});
  return fields;
}
const std::vector<ScanningField>& scanningFields() {
  static const std::vector<ScanningField> fields = fieldOptions(ScanningRunOptions{});
  return fields;
}
const std::vector<InertialField>& inertialFields() {
  static const std::vector<InertialField> fields = fieldOptions(InertialRunOptions{});
  return fields;
}

/// One pipeline's (or layout's) side of an option, for its help.
struct Side {
  std::string label;  ///< nuscenes, scanning, oxford, ...
  const Field* field;
  bool off_switch;
  std::string choices, default_text, path;
};

template <typename R>
void addSides(const std::vector<FieldOption<R>>& fields, const char* label, std::vector<std::string>& order,
              std::map<std::string, std::vector<Side>>& sides) {
  for (const auto& f : fields) {
    if (!sides.count(f.option)) order.push_back(f.option);
    sides[f.option].push_back(
        {f.scope.empty() ? label : f.scope, &f.field, f.off_switch, f.choices, f.default_text, f.path});
  }
}

/// "nuscenes, scanning: NDT grid size g (m), default 3 (nuscenes) or 3.75 (scanning)": the sides
/// that say the same share one sentence.
std::string helpOf(const std::vector<Side>& sides) {
  std::string out;
  std::vector<bool> done(sides.size(), false);
  for (std::size_t i = 0; i < sides.size(); ++i) {
    if (done[i]) continue;
    const Field& f = *sides[i].field;
    const char* text = sides[i].off_switch ? f.off_switch_help : f.help;
    std::vector<std::size_t> same;
    for (std::size_t j = i; j < sides.size(); ++j) {
      const Field& g = *sides[j].field;
      if (!done[j] && std::string(sides[j].off_switch ? g.off_switch_help : g.help) == text &&
          std::string(g.unit_text) == f.unit_text && sides[j].choices == sides[i].choices) {
        same.push_back(j);
        done[j] = true;
      }
    }
    std::string labels, defaults;
    bool one_default = true;
    for (const std::size_t j : same) {
      labels += (labels.empty() ? "" : ", ") + sides[j].label;
      one_default = one_default && sides[j].default_text == sides[same[0]].default_text;
    }
    for (const std::size_t j : same)
      defaults += (defaults.empty() ? "" : " or ") + sides[j].default_text + " (" + sides[j].label + ")";
    std::string sentence = labels + ": " + text;
    if (*f.unit_text) sentence += " (" + std::string(f.unit_text) + ")";
    if (!sides[i].choices.empty()) sentence += ": " + sides[i].choices;
    if (!sides[i].off_switch && !sides[i].default_text.empty())
      sentence += ", default " + (one_default ? sides[i].default_text : defaults);
    out += (out.empty() ? "" : "; ") + sentence;
  }
  return out;
}

/// The settings the command line gives: those of `scope`'s layout, and those of no layout, each a
/// field's path with the value its text gives (typed by the field).
template <typename R>
Settings givenSettings(const po::variables_map& vm, const std::vector<FieldOption<R>>& fields,
                       const std::string& scope) {
  Settings given;
  for (const auto& f : fields) {
    if (!f.scope.empty() && f.scope != scope) continue;
    if (f.off_switch) {
      if (vm[f.option].template as<bool>()) given.push_back({f.path, f.value(""), "--" + f.option});
    } else if (vm.count(f.option)) {
      given.push_back({f.path, f.value(vm[f.option].template as<std::string>()), "--" + f.option});
    }
  }
  if (vm.count("no-prefetch") && vm["no-prefetch"].as<bool>())
    given.push_back({"threads", FieldValue(1), "--no-prefetch"});
  return given;
}

/// The pipeline options, in the order --help lists them, with each one's sides.
std::vector<std::pair<std::string, std::vector<Side>>> pipelineSides() {
  std::vector<std::string> order;
  std::map<std::string, std::vector<Side>> sides;
  addSides(automotiveFields(), "nuscenes", order, sides);
  addSides(scanningFields(), "scanning", order, sides);
  addSides(inertialFields(), "6-DoF", order, sides);
  std::vector<std::pair<std::string, std::vector<Side>>> out;
  for (const std::string& name : order) out.emplace_back(name, sides[name]);
  return out;
}

/// An option the command line gives that sets nothing for `format` is refused, not ignored: a
/// user who asks for a scanning setting on nuScenes would otherwise believe it was used.
template <typename R>
void refuseUnused(const po::variables_map& vm, const std::vector<FieldOption<R>>& fields, const std::string& scope,
                  const std::string& format) {
  std::set<std::string> used;
  for (const auto& f : fields)
    if (f.scope.empty() || f.scope == scope) used.insert(f.option);
  for (const auto& [name, sides] : pipelineSides()) {
    if (used.count(name) || !vm.count(name) || vm[name].defaulted()) continue;
    std::string labels;
    for (const Side& s : sides) labels += (labels.empty() ? "" : ", ") + s.label;
    throw std::invalid_argument("--" + name + " does not apply to --format " + format + " (" + labels + " only)");
  }
}

}  // namespace

Pipeline pipelineOf(const std::string& format) {
  try {
    return isScanLayout(parseEnum<DatasetFormat>(format)) ? Pipeline::Scanning : Pipeline::Automotive;
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("--format " + format + ": " + e.what());
  }
}

std::string pipelineOptionsMarkdown() {
  std::string out = "| option | field | pipeline | meaning | default |\n|---|---|---|---|---|\n";
  for (const auto& [name, sides] : pipelineSides()) {
    // One row for the sides that set the same field in the same words.
    std::vector<bool> done(sides.size(), false);
    for (std::size_t i = 0; i < sides.size(); ++i) {
      if (done[i]) continue;
      const Side& s = sides[i];
      const Field& f = *s.field;
      std::string meaning = s.off_switch ? f.off_switch_help : f.help;
      if (*f.unit_text) meaning += " (" + std::string(f.unit_text) + ")";
      if (!s.choices.empty()) meaning += ": " + s.choices;
      std::string labels, defaults;
      bool one_default = true;
      for (std::size_t j = i; j < sides.size(); ++j)
        if (!done[j] && sides[j].path == s.path && sides[j].field->help == f.help) {
          done[j] = true;
          labels += (labels.empty() ? "" : ", ") + sides[j].label;
          one_default = one_default && sides[j].default_text == s.default_text;
          if (!s.off_switch && !sides[j].default_text.empty())
            defaults += (defaults.empty() ? "" : ", ") + sides[j].default_text + " (" + sides[j].label + ")";
        }
      if (one_default && !defaults.empty()) defaults = s.default_text;
      std::string escaped;
      for (const char c : meaning) escaped += c == '|' ? std::string("\\|") : std::string(1, c);
      out += "| `--" + name + "` | `" + s.path + "`" + (s.off_switch ? (f.switch_sets ? " = true" : " = false") : "") +
             " | " + labels + " | " + escaped + " | " + defaults + " |\n";
    }
  }
  return out;
}

void addPipelineOptions(po::options_description& opts) {
  // clang-format off
  opts.add_options()
    ("format", po::value<std::string>()->required(),
     "dataset layout: nuscenes | rosbag (automotive) | oxford | radiate | boreas (scanning); boreas scans with chirp "
     "types take --threshold and --power-shift 0.43 by default")
    ("bag", po::value<std::string>(), "rosbag: the ROS 1 bag (docs/ros.md)")
    ("sensors", po::value<std::string>(),
     "rosbag: the sensor description (YAML: topics, fields, mountings; docs/ros.md), or preset:NAME "
     "(nuscenes_ars408, ti_iwr6843_rio, navtech_oxford, navtech_boreas); a scanning radar's description runs the "
     "scanning pipeline")
    ("dataroot", po::value<std::string>(), "nuscenes: the dataroot (holds v1.0-*/, samples/, sweeps/)")
    ("sequence", po::value<std::vector<std::string>>()->multitoken(),
     "oxford: a directory with radar.timestamps, radar/<stamp>.png and optionally "
     "gt/radar_odometry.csv; radiate: one with Navtech_Polar.txt and Navtech_Polar/<frame>.png; boreas: "
     "one with radar/<stamp>.png and optionally applanix/radar_poses.csv")
    ("version", po::value<std::string>()->default_value(""),
     "nuscenes: table folder under dataroot (default: the one holding sensor.json)")
    ("scene", po::value<std::string>()->default_value("all"),
     "nuscenes: scene name, or 'all' (each scene, then the mean)");
  // clang-format on
  // Every setting of the run options the field tables put on the command line, its help and
  // defaults from the tables and the library's defaults.
  for (const auto& [name, s] : pipelineSides()) {
    const std::string help = helpOf(s);
    if (s.front().off_switch)
      opts.add_options()(name.c_str(), po::bool_switch(), help.c_str());
    else
      opts.add_options()(name.c_str(), po::value<std::string>(), help.c_str());
  }
  opts.add_options()("no-prefetch", po::bool_switch(), "the same as --threads 1")("quiet,q", po::bool_switch(),
                                                                                  "no progress bar");
}

Settings automotiveSettings(const po::variables_map& vm) {
  refuseUnused(vm, automotiveFields(), "", vm["format"].as<std::string>());
  return givenSettings(vm, automotiveFields(), "");
}

Settings scanningSettings(const po::variables_map& vm) {
  const std::string format = vm["format"].as<std::string>();
  refuseUnused(vm, scanningFields(), format, format);
  return givenSettings(vm, scanningFields(), format);
}

bool asksInertial(const po::variables_map& vm) {
  return vm["format"].as<std::string>() == "rosbag" && vm.count("method") &&
         isInertialMethod(vm["method"].as<std::string>());
}

Settings inertialSettings(const po::variables_map& vm) {
  refuseUnused(vm, inertialFields(), "", "rosbag with a 6-DoF --method");
  return givenSettings(vm, inertialFields(), "");
}

AutomotiveRunOptions automotiveOptions(const po::variables_map& vm) {
  return automotiveRunOptions(automotiveSettings(vm));
}

ScanningRunOptions scanningOptions(const po::variables_map& vm, const ScanningRunOptions& base) {
  return scanningRunOptions(scanningSettings(vm), vm["format"].as<std::string>(), base);
}

NuScenesDataset openDataset(const po::variables_map& vm) {
  if (!vm.count("dataroot")) throw std::invalid_argument("--format nuscenes needs --dataroot DIR");
  return NuScenesDataset(vm["dataroot"].as<std::string>(), vm["version"].as<std::string>());
}

std::vector<const NuScenesScene*> selectScenes(const NuScenesDataset& dataset, const po::variables_map& vm) {
  std::vector<const NuScenesScene*> scenes;
  if (vm["scene"].as<std::string>() == "all")
    for (const auto& s : dataset.scenes()) scenes.push_back(&s);
  else
    scenes.push_back(&dataset.scene(vm["scene"].as<std::string>()));
  return scenes;
}

std::vector<std::string> sequenceDirs(const po::variables_map& vm) {
  if (!vm.count("sequence") || vm["sequence"].as<std::vector<std::string>>().empty())
    throw std::invalid_argument("--format " + vm["format"].as<std::string>() + " needs --sequence DIR");
  return vm["sequence"].as<std::vector<std::string>>();
}

void Progress::operator()(std::size_t done, std::size_t total) const {
  if (!enabled || (done % 10 != 0 && done != total)) return;
  const int width = 30;
  const int filled = total ? static_cast<int>(width * done / total) : width;
  std::fprintf(stderr, "\r%-12s [%s%s] %zu/%zu", label.c_str(),
               std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(width - filled), ' ').c_str(), done, total);
  if (done == total) std::fprintf(stderr, "\n");
}

}  // namespace apps
}  // namespace radar_ndt
