// The ROS node's parameters (apps/node/node_parameters.h) against the command line: for every field
// of both run options' tables, the same value given as a parameter of its own XmlRpc type and as
// the command line's text builds the same options (or is refused by both). The test walks the
// tables, so a field added later is covered without editing it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "command_line_support.h"
#include "field_options.h"
#include "node/node_parameters.h"
#include "pipeline_options.h"
#include "radar_ndt/odometry/matcher_registry.h"

using namespace radar_ndt;
namespace po = boost::program_options;

namespace {

XmlRpc::XmlRpcValue xmlOf(const FieldValue& v) {
  switch (v.kind()) {
    case FieldValue::Kind::Bool: return XmlRpc::XmlRpcValue(v.boolean());
    case FieldValue::Kind::Integer: return XmlRpc::XmlRpcValue(static_cast<int>(v.integer()));
    case FieldValue::Kind::Real: return XmlRpc::XmlRpcValue(v.real());
    case FieldValue::Kind::Text: return XmlRpc::XmlRpcValue(v.text());
    default: {
      XmlRpc::XmlRpcValue list;
      list.setSize(static_cast<int>(v.list().size()));
      for (std::size_t k = 0; k < v.list().size(); ++k) list[static_cast<int>(k)] = xmlOf(v.list()[k]);
      return list;
    }
  }
}

/// Values for a field other than its default: a switch both ways, 1e-7 and a larger number where
/// the bounds allow, an integer one above the default, each other name of a choice, a one-item list.
template <typename R>
std::vector<FieldValue> probes(const FieldEntry<R>& e, const R& defaults) {
  const FieldValue d = e.get(defaults);
  std::vector<FieldValue> out;
  const Bounds& b = e.field.bounds;
  switch (d.kind()) {
    case FieldValue::Kind::Bool: return {FieldValue(true), FieldValue(false)};
    case FieldValue::Kind::Integer: {
      const long long v = b.contains(static_cast<double>(d.integer() + 1)) ? d.integer() + 1 : d.integer() - 1;
      return {FieldValue(v)};
    }
    case FieldValue::Kind::Real:
      for (const double v : {1e-7, 2 * d.real() + 0.5, d.real() + 0.125})
        if (b.contains(v) && v != d.real()) out.emplace_back(v);
      return out;
    case FieldValue::Kind::Text:
      if (e.path == "matcher.method") {
        for (const std::string& m : matcherNames()) out.emplace_back(m);
      } else {
        for (const std::string& n : e.names) out.emplace_back(n);
        if (e.names.empty()) out.emplace_back(std::string("RADAR_FRONT"));
      }
      return out;
    default: {
      const FieldValue item = e.item_kind == FieldValue::Kind::Text   ? FieldValue("RADAR_FRONT")
                              : e.item_kind == FieldValue::Kind::Real ? FieldValue(3.5)
                                                                      : FieldValue(3);
      return {FieldValue(FieldValue::List{item})};
    }
  }
}

/// The command line's text for a value (numbers with every digit a double needs).
std::string cliText(const FieldValue& v) {
  if (v.kind() == FieldValue::Kind::Text) return v.text();
  if (v.kind() != FieldValue::Kind::List) return v.str();
  std::string out;
  for (const FieldValue& item : v.list()) out += (out.empty() ? "" : ",") + cliText(item);
  return out;
}

/// The options a build gives, or the refusal's first words (its text names the caller's spelling).
template <typename R, typename Build>
std::string outcome(const Build& build) {
  try {
    std::string out;
    for (const auto& [path, value] : fieldValues(build())) out += path + "=" + value.str() + "\n";
    return out;
  } catch (const std::invalid_argument&) {
    return "refused";
  }
}

/// For every field of R and every probe value: the node's parameter and the command line (or,
/// for a field the command line cannot give that way, the library's setting by path) agree.
template <typename R, typename FromSettings, typename FromCli>
void compareEveryField(const std::string& format, const FromSettings& from_settings, const FromCli& from_cli) {
  const R defaults;
  std::size_t fields = 0, compared = 0, via_cli = 0;
  for (const FieldEntry<R>& e : fieldEntries<R>()) {
    ++fields;
    std::string name = e.path;
    std::replace(name.begin(), name.end(), '.', '/');
    for (const FieldValue& v : probes(e, defaults)) {
      SCOPED_TRACE(e.path + " = " + v.str());
      const std::string layout = e.scope.empty() ? format : e.scope;
      std::map<std::string, XmlRpc::XmlRpcValue> params{{name, xmlOf(v)}};
      const std::string node = outcome<R>([&] { return from_settings(node::settingsFromParameters(params), layout); });
      std::string cli;
      const Field& f = e.field;
      if (f.cli_name && (!f.off_switch_help || (v.kind() == FieldValue::Kind::Bool && v.boolean() == f.switch_sets))) {
        std::vector<std::string> args{"--format", layout, std::string("--") + f.cli_name};
        if (!f.off_switch_help)  // a flag the command line spells by its own two names takes them
          args.push_back(f.true_name && v.kind() == FieldValue::Kind::Bool ? (v.boolean() ? f.true_name : f.false_name)
                                                                           : cliText(v));
        cli = outcome<R>([&] { return from_cli(test::parseOdometryCommandLine(args)); });
        ++via_cli;
      } else {
        cli = outcome<R>([&] { return from_settings(Settings{{e.path, v, ""}}, layout); });
      }
      EXPECT_TRUE(node == cli) << "node:\n" << node << "\ncommand line:\n" << cli;
      ++compared;
    }
  }
  EXPECT_GT(fields, 20u);
  EXPECT_GE(compared, fields) << "every field probed at least once";
  EXPECT_GT(via_cli, 20u);
}

}  // namespace

TEST(NodeParameters, EveryAutomotiveFieldAsAParameterGivesTheCommandLinesOptions) {
  compareEveryField<AutomotiveRunOptions>(
      "nuscenes", [](const Settings& s, const std::string&) { return automotiveRunOptions(s); },
      [](const po::variables_map& vm) { return apps::automotiveOptions(vm); });
}

TEST(NodeParameters, EveryScanningFieldAsAParameterGivesTheCommandLinesOptions) {
  compareEveryField<ScanningRunOptions>(
      "oxford", [](const Settings& s, const std::string& layout) { return scanningRunOptions(s, layout); },
      [](const po::variables_map& vm) { return apps::scanningOptions(vm); });
}

TEST(NodeParameters, ASwitchSetsItsFieldsValueBothWays) {
  // ~odometry/fuse_doppler is an off switch on the command line (--no-fusion); as a parameter it
  // is the field: true keeps the fusion, false turns it off.
  for (const bool on : {true, false}) {
    const AutomotiveRunOptions o =
        automotiveRunOptions(node::settingsFromParameters({{"odometry/fuse_doppler", XmlRpc::XmlRpcValue(on)}}));
    EXPECT_EQ(o.odometry.fuse_doppler, on);
  }
  EXPECT_FALSE(apps::automotiveOptions(test::parseOdometryCommandLine({"--format", "nuscenes", "--no-fusion"}))
                   .odometry.fuse_doppler);
}

TEST(NodeParameters, ASmallDoubleStaysADouble) {
  const ScanningRunOptions o = scanningRunOptions(
      node::settingsFromParameters({{"odometry/gyro/bias_walk", XmlRpc::XmlRpcValue(1e-7)}}), "rosbag");
  EXPECT_EQ(o.odometry.gyro.bias_walk, 1e-7);
  // An integer parameter of a real field is taken as that number; a fraction for an integer is not.
  EXPECT_EQ(automotiveRunOptions(node::settingsFromParameters({{"matcher/grid", XmlRpc::XmlRpcValue(4)}})).matcher.grid,
            4.0);
  EXPECT_THROW(automotiveRunOptions(node::settingsFromParameters({{"max_cycles", XmlRpc::XmlRpcValue(2.5)}})),
               std::invalid_argument);
}

TEST(NodeParameters, AParameterThePipelineDoesNotUseIsRefusedNamingIt) {
  auto message = [](auto build) {
    try {
      build();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string other = message([] {
    automotiveRunOptions(node::settingsFromParameters({{"front_end/threshold", XmlRpc::XmlRpcValue(0.3)}}));
  });
  EXPECT_NE(other.find("~front_end/threshold"), std::string::npos) << other;
  EXPECT_NE(other.find("scanning"), std::string::npos) << other;
  const std::string typo = message([] {
    automotiveRunOptions(node::settingsFromParameters({{"odometry/fuse_dopler", XmlRpc::XmlRpcValue(true)}}));
  });
  EXPECT_NE(typo.find("~odometry/fuse_dopler"), std::string::npos) << typo;
  const std::string layout = message([] {
    scanningRunOptions(node::settingsFromParameters({{"sequence/boreas/range_resolution", XmlRpc::XmlRpcValue(0.05)}}),
                       "rosbag");
  });
  EXPECT_NE(layout.find("boreas"), std::string::npos) << layout;
  const std::string wrong_type = message([] {
    automotiveRunOptions(node::settingsFromParameters({{"odometry/fuse_doppler", XmlRpc::XmlRpcValue("yes")}}));
  });
  EXPECT_NE(wrong_type.find("true or false"), std::string::npos) << wrong_type;
  // The node's own parameters are not settings.
  EXPECT_TRUE(node::settingsFromParameters({{"sensors", XmlRpc::XmlRpcValue("preset:nuscenes_ars408")},
                                            {"cycle_period", XmlRpc::XmlRpcValue(0.077)}})
                  .empty());
}
