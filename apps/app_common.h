#pragma once
// What every RadarNDT app shares: option parsing with Boost.Program_options that turns bad input
// into one clear line and exit code 1. No algorithm lives here.

#include <algorithm>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <boost/program_options.hpp>
#include <pcl/console/print.h>

#include "radar_ndt/statistics.h"

namespace radar_ndt {
namespace apps {

namespace po = boost::program_options;

/// The median of `v` (the mean of the middle two for an even count; 0 for none), as the apps print.
using radar_ndt::median;  // radar_ndt/statistics.h

/// Parses argv against `options`. Prints help (exit 0) for -h/--help, or one error line (exit 1)
/// for unknown options and malformed values. Returns -1 when the app should go on.
inline int parseCommandLine(int argc, char** argv, const po::options_description& options, const std::string& usage,
                            po::variables_map& vm) {
  try {
    po::store(po::command_line_parser(argc, argv).options(options).run(), vm);
    if (vm.count("help")) {
      std::cout << usage << "\n\n" << options << std::endl;
      return 0;
    }
    po::notify(vm);
  } catch (const po::error& e) {
    pcl::console::print_error("%s: %s (see --help)\n", argv[0], e.what());
    return 1;
  }
  return -1;
}

/// Runs the app body, turning any exception into one error line and exit code 1.
inline int runGuarded(const char* app, const std::function<int()>& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    pcl::console::print_error("%s: %s\n", app, e.what());
    return 1;
  }
}

}  // namespace apps
}  // namespace radar_ndt
