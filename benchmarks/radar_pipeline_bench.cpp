// radar_pipeline_bench: the whole pipeline timed as a user runs it. Each run is its own process (a
// fork of this one, before any thread exists), so its wall clock, CPU time and peak memory are those
// of a whole radar_odometry run on the same data: ours, PCL's NDT and PCL's ICP through the same
// scanning pipeline, for each thread count, with ms per stage and scans a second; --dataroot: the
// nuScenes pipeline the same way; --growth: ours on one thread against the points per scan (by the
// power threshold) and the range bins used (by the range limit), with an SVG plot; --decode: the
// PNG decoders (libpng and the fast path) on every scan of a folder.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app_common.h"
#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/png_image.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/scanning_run.h"

using namespace radar_ndt;
using json = nlohmann::json;
namespace po = boost::program_options;

namespace {

using apps::median;

double seconds(const timeval& t) {
  return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
}

/// Runs `body` in a child process and returns what it printed (one JSON object) with the child's
/// wall clock, CPU time and peak resident memory added. A child that fails is an error.
json inChild(const std::function<json()>& body) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error("pipe failed");
  std::fflush(nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    ::close(fds[0]);
    int code = 0;
    std::string out;
    try {
      out = body().dump();
    } catch (const std::exception& e) {
      out = json{{"error", e.what()}}.dump();
      code = 1;
    }
    const bool written = ::write(fds[1], out.data(), out.size()) == static_cast<ssize_t>(out.size());
    ::close(fds[1]);
    ::_exit(written ? code : 2);
  }
  ::close(fds[1]);
  std::string text;
  char buffer[4096];
  for (ssize_t got; (got = ::read(fds[0], buffer, sizeof buffer)) > 0;)
    text.append(buffer, static_cast<std::size_t>(got));
  ::close(fds[0]);
  int status = 0;
  rusage usage{};
  ::wait4(pid, &status, 0, &usage);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  json r = text.empty() ? json{{"error", "the run printed nothing"}} : json::parse(text);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("a run failed: " + r.value("error", std::string("exit status ") + std::to_string(status)));
  r["process_wall_s"] = wall;
  r["process_cpu_s"] = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  r["peak_mib"] = static_cast<double>(usage.ru_maxrss) / 1024.0;  // kilobytes on Linux
  return r;
}

struct ScanningConfig {
  std::string method = "pw-ndt";
  int threads = 1;
  float threshold = ScanningRunOptions().front_end.threshold;
  double max_range = ScanningRunOptions().front_end.max_range;
};

json runScanning(const std::string& dir, ScanFormat format, const ScanningConfig& c, std::size_t max_scans) {
  return inChild([&] {
    ScanningRunOptions o;
    o.matcher.method = c.method;
    o.threads = c.threads;
    o.front_end.threshold = c.threshold;
    o.front_end.max_range = c.max_range;
    o.max_scans = max_scans;
    const ScanningSequence sequence(dir, format, o.sequence);
    const ScanningRunResult r = runScanningOdometry(sequence, o);
    return json{{"scans", r.estimate.size()},
                {"scans_per_second", r.scans_per_second},
                {"decode_ms", r.median_ms.read_ms},
                {"front_end_ms", r.median_ms.front_end_ms},
                {"match_ms", r.median_ms.match_ms},
                {"points", r.median_points},
                {"threads", r.threads}};
  });
}

/// The medians of `repeats` runs of `run`, key by key.
json medianOf(int repeats, const std::function<json()>& run) {
  std::vector<json> runs;
  for (int i = 0; i < repeats; ++i) runs.push_back(run());
  json out = runs.front();
  for (auto& [key, value] : out.items())
    if (value.is_number()) {
      std::vector<double> v;
      for (const json& r : runs) v.push_back(r[key].get<double>());
      value = median(v);
    }
  out["repeats"] = repeats;
  return out;
}

/// The registered matchers a scanning radar can run (the registry's, in its order).
std::vector<std::string> scanningMethods() {
  std::vector<std::string> out;
  for (const std::string& name : matcherNames())
    if (!findMatcher(name).uses.automotiveOnly()) out.push_back(name);
  return out;
}

std::vector<int> parseInts(const std::string& list) {
  std::vector<int> out;
  std::stringstream ss(list);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(std::stoi(item));
  return out;
}

std::vector<double> parseDoubles(const std::string& list) {
  std::vector<double> out;
  std::stringstream ss(list);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(std::stod(item));
  return out;
}

json scanningTable(const po::variables_map& vm, const std::string& dir, ScanFormat format) {
  const int repeats = vm["repeats"].as<int>();
  const std::size_t max_scans = vm["max-scans"].as<std::size_t>();
  json rows = json::array();
  std::printf("%-8s %7s %9s %9s %9s %8s %9s %9s %8s\n", "method", "threads", "decode", "front-end", "match", "points",
              "scans/s", "cpu s", "peak MiB");
  for (const std::string& name : scanningMethods())
    for (int threads : parseInts(vm["threads"].as<std::string>())) {
      ScanningConfig c;
      c.method = name;
      c.threads = threads;
      json r = medianOf(repeats, [&] { return runScanning(dir, format, c, max_scans); });
      r["method"] = name;
      std::printf("%-8s %7d %9.2f %9.2f %9.2f %8.0f %9.1f %9.2f %8.1f\n", name.c_str(), r["threads"].get<int>(),
                  r["decode_ms"].get<double>(), r["front_end_ms"].get<double>(), r["match_ms"].get<double>(),
                  r["points"].get<double>(), r["scans_per_second"].get<double>(), r["process_cpu_s"].get<double>(),
                  r["peak_mib"].get<double>());
      std::fflush(stdout);
      rows.push_back(r);
    }
  // Ours against PCL's NDT, each thread count, from this run's medians.
  for (const json& ours : rows)
    for (const json& ndt : rows)
      if (ours["method"] == "pw-ndt" && ndt["method"] == "pcl-ndt" && ours["threads"] == ndt["threads"])
        std::printf("threads %d: ours %.2fx PCL's NDT end to end\n", ours["threads"].get<int>(),
                    ours["scans_per_second"].get<double>() / ndt["scans_per_second"].get<double>());
  return rows;
}

json nuscenesTable(const po::variables_map& vm) {
  const std::string root = vm["dataroot"].as<std::string>();
  json rows = json::array();
  std::printf("%-8s %7s %9s %9s %8s %8s\n", "method", "threads", "cycles", "wall s", "cpu s", "peak MiB");
  for (int threads : parseInts(vm["threads"].as<std::string>())) {
    json r = medianOf(vm["repeats"].as<int>(), [&] {
      return inChild([&] {
        const NuScenesDataset ds(root);
        std::size_t cycles = 0;
        for (const NuScenesScene& scene : ds.scenes()) {
          AutomotiveRunOptions o;
          o.threads = threads;
          cycles += runAutomotiveOdometry(ds, scene, o).estimate.size();
        }
        return json{{"cycles", cycles}, {"threads", threads}};
      });
    });
    r["method"] = "pw-ndt";
    std::printf("%-8s %7d %9.0f %9.3f %8.3f %8.1f\n", "pw-ndt", threads, r["cycles"].get<double>(),
                r["process_wall_s"].get<double>(), r["process_cpu_s"].get<double>(), r["peak_mib"].get<double>());
    rows.push_back(r);
  }
  return rows;
}

/// One panel of the growth plot: ms per scan (front-end + match, and decode) against `x`.
std::string panel(const json& rows, const char* x_key, const char* x_label, double left) {
  double x_max = 0, y_max = 0;
  for (const json& r : rows) {
    x_max = std::max(x_max, r[x_key].get<double>());
    y_max =
        std::max({y_max, r["front_end_ms"].get<double>() + r["match_ms"].get<double>(), r["decode_ms"].get<double>()});
  }
  const double w = 360, h = 260, top = 40;
  auto px = [&](double x) { return left + w * x / (1.05 * x_max); };
  auto py = [&](double y) { return top + h - h * y / (1.1 * y_max); };
  std::ostringstream s;
  s << "<rect x='" << left << "' y='" << top << "' width='" << w << "' height='" << h
    << "' fill='none' stroke='#888'/>\n<text x='" << left + w / 2 << "' y='" << top + h + 35
    << "' text-anchor='middle'>" << x_label << "</text>\n";
  for (int i = 0; i <= 4; ++i) {
    const double y = 1.1 * y_max * i / 4;
    s << "<text x='" << left - 6 << "' y='" << py(y) + 4 << "' text-anchor='end' font-size='11'>" << std::fixed
      << std::setprecision(1) << y << "</text>\n";
    const double x = 1.05 * x_max * i / 4;
    s << "<text x='" << px(x) << "' y='" << top + h + 16 << "' text-anchor='middle' font-size='11'>"
      << std::setprecision(0) << x << "</text>\n";
  }
  const std::pair<const char*, const char*> series[] = {{"match", "#c0392b"}, {"decode_ms", "#2471a3"}};
  for (const auto& [which, colour] : series) {
    s << "<polyline fill='none' stroke='" << colour << "' stroke-width='2' points='";
    for (const json& r : rows) {
      const double y = std::string(which) == "match" ? r["front_end_ms"].get<double>() + r["match_ms"].get<double>()
                                                     : r["decode_ms"].get<double>();
      s << std::setprecision(1) << px(r[x_key].get<double>()) << "," << py(y) << " ";
    }
    s << "'/>\n";
  }
  return s.str();
}

json growth(const po::variables_map& vm, const std::string& dir, ScanFormat format) {
  const std::size_t max_scans = vm["max-scans"].as<std::size_t>();
  const int repeats = vm["repeats"].as<int>();
  json by_threshold = json::array(), by_range = json::array();
  std::printf("%-12s %8s %9s %9s %9s %9s\n", "setting", "points", "bins", "decode", "front-end", "match");
  auto add = [&](json& rows, ScanningConfig c, const std::string& label) {
    json r = medianOf(repeats, [&] { return runScanning(dir, format, c, max_scans); });
    r["threshold"] = c.threshold;
    r["max_range_m"] = c.max_range;
    r["bins_used"] = c.max_range / ScanningSequenceOptions().oxford.convention.range_resolution;
    std::printf("%-12s %8.0f %9.0f %9.2f %9.2f %9.2f\n", label.c_str(), r["points"].get<double>(),
                r["bins_used"].get<double>(), r["decode_ms"].get<double>(), r["front_end_ms"].get<double>(),
                r["match_ms"].get<double>());
    std::fflush(stdout);
    rows.push_back(r);
  };
  for (double t : parseDoubles(vm["growth-thresholds"].as<std::string>())) {
    ScanningConfig c;
    c.threshold = static_cast<float>(t);
    add(by_threshold, c, "threshold " + std::to_string(t).substr(0, 5));
  }
  for (double m : parseDoubles(vm["growth-ranges"].as<std::string>())) {
    ScanningConfig c;
    c.max_range = m;
    add(by_range, c, "range " + std::to_string(static_cast<int>(m)) + " m");
  }
  std::sort(by_threshold.begin(), by_threshold.end(),
            [](const json& a, const json& b) { return a["points"].get<double>() < b["points"].get<double>(); });
  if (vm.count("svg")) {
    std::ostringstream svg;
    svg << "<svg xmlns='http://www.w3.org/2000/svg' width='880' height='360' font-family='sans-serif' "
           "font-size='13'>\n<rect width='100%' height='100%' fill='white'/>\n"
        << "<text x='440' y='22' text-anchor='middle'>ms per scan, one thread (red: front-end + match, blue: "
           "decode)</text>\n"
        << panel(by_threshold, "points", "points per scan (power threshold)", 60)
        << panel(by_range, "bins_used", "range bins used (range limit)", 500) << "</svg>\n";
    writeFileAtomically(vm["svg"].as<std::string>(), svg.str());
  }
  return json{{"by_threshold", by_threshold}, {"by_range", by_range}};
}

/// The PNG decoders on every scan of `dir`, one thread: median ms of each, and whether they agree.
json decodeTable(const std::string& dir, int repeats) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".png") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw std::invalid_argument("--decode: no .png file in " + dir);
  json rows = json::array();
  std::vector<double> ms[2];
  bool same = true;
  GrayImage image[2];
  for (int r = 0; r < std::max(repeats, 3); ++r)
    for (const std::string& f : files)
      for (int d = 0; d < 2; ++d) {
        const auto t0 = std::chrono::steady_clock::now();
        readGrayPng(f, image[d], d == 0 ? PngDecoder::Libpng : PngDecoder::Fast);
        ms[d].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        if (d == 1) same = same && image[0].pixels == image[1].pixels;
      }
  const double megapixels = 1e-6 * image[0].width * image[0].height;
  std::printf("%zu scans of %dx%d in %s: libpng %.2f ms, fast path %.2f ms (%.1fx), pixels %s\n", files.size(),
              image[0].width, image[0].height, dir.c_str(), median(ms[0]), median(ms[1]), median(ms[0]) / median(ms[1]),
              same ? "identical" : "DIFFERENT");
  return json{{"dir", dir},
              {"scans", files.size()},
              {"megapixels", megapixels},
              {"libpng_ms", median(ms[0])},
              {"fast_ms", median(ms[1])},
              {"identical", same}};
}

}  // namespace

int main(int argc, char** argv) {
  const std::string usage =
      "Usage: radar_pipeline_bench --sequence DIR [--format oxford|radiate|boreas] [--threads 1,2] [--repeats 3] "
      "[--json F]\n"
      "       radar_pipeline_bench --sequence DIR --growth [--svg F] [--json F]\n"
      "       radar_pipeline_bench --dataroot DIR [--threads 1,2] [--repeats 3] [--json F]\n"
      "       radar_pipeline_bench --decode DIR [--decode DIR...]   (the PNG decoders, one thread)\n"
      "Each run is a process of its own (wall clock, CPU time and peak memory are a whole run's); the\n"
      "figures are medians over the repeats.";
  po::options_description opts("Options");
  // clang-format off
  opts.add_options()
    ("help,h", "this help")
    ("sequence", po::value<std::string>(), "a scanning sequence (Oxford or RADIATE layout)")
    ("format", po::value<std::string>()->default_value("oxford"),
     "oxford, radiate or boreas (the paper's front-end settings for each)")
    ("dataroot", po::value<std::string>(), "a nuScenes dataroot: every scene, ours, per thread count")
    ("decode", po::value<std::vector<std::string>>(), "instead: libpng and the fast path on every PNG of this folder")
    ("threads", po::value<std::string>()->default_value("1,2"), "thread counts to run, comma separated")
    ("repeats", po::value<int>()->default_value(3), "runs per configuration (the median is reported)")
    ("max-scans", po::value<std::size_t>()->default_value(0), "scans per run, 0: all")
    ("growth", po::bool_switch(), "ours on one thread against points per scan and range bins used")
    ("growth-thresholds", po::value<std::string>()->default_value("0.45,0.4,0.35,0.333,0.3,0.27,0.25,0.23"),
     "--growth: power thresholds")
    ("growth-ranges", po::value<std::string>()->default_value("25,50,62.5,100,150"),
     "--growth: range limits (m)")
    ("svg", po::value<std::string>(), "--growth: write the plot here")
    ("json", po::value<std::string>(), "write the figures as JSON here");
  // clang-format on
  po::variables_map vm;
  if (const int rc = apps::parseCommandLine(argc, argv, opts, usage, vm); rc >= 0) return rc;
  return apps::runGuarded("radar_pipeline_bench", [&] {
    if (vm["repeats"].as<int>() < 1) throw std::invalid_argument("--repeats must be at least 1");
    json out;
    if (vm.count("decode")) {
      for (const std::string& dir : vm["decode"].as<std::vector<std::string>>())
        out["decode"].push_back(decodeTable(dir, vm["repeats"].as<int>()));
    } else if (vm.count("dataroot")) {
      out["nuscenes"] = nuscenesTable(vm);
    } else if (vm.count("sequence")) {
      const std::string dir = vm["sequence"].as<std::string>();
      const std::string f = vm["format"].as<std::string>();
      const ScanFormat format = parseEnum<ScanFormat>(f);
      out["sequence"] = dir;
      if (vm["growth"].as<bool>())
        out["growth"] = growth(vm, dir, format);
      else
        out["scanning"] = scanningTable(vm, dir, format);
    } else {
      throw std::invalid_argument("give --sequence DIR or --dataroot DIR (see --help)");
    }
    out["machine_cores"] = ::sysconf(_SC_NPROCESSORS_ONLN);
    if (vm.count("json")) writeFileAtomically(vm["json"].as<std::string>(), out.dump(2) + "\n");
    return 0;
  });
}
