#pragma once
// radar_odometry's command line as the apps build it from the field tables (apps/pipeline_options.h),
// for the tests of the options and of the node's parameters against them.
#include <string>
#include <vector>

#include <boost/program_options.hpp>

#include "pipeline_options.h"

namespace radar_ndt {
namespace test {

/// The options radar_odometry's command line `args` gives (program name excluded).
inline boost::program_options::variables_map parseOdometryCommandLine(const std::vector<std::string>& args) {
  namespace po = boost::program_options;
  po::options_description opts;
  apps::addPipelineOptions(opts);
  std::vector<const char*> argv{"radar_odometry"};
  for (const auto& a : args) argv.push_back(a.c_str());
  po::variables_map vm;
  po::store(po::parse_command_line(static_cast<int>(argv.size()), argv.data(), opts), vm);
  po::notify(vm);
  return vm;
}

}  // namespace test
}  // namespace radar_ndt
