// Field tables (radar_ndt/fields.h): the name tables of enumerations, bounds, and validate()'s
// checks made from a struct's table, nested structs included.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "radar_ndt/fields.h"
#include "radar_ndt/odometry/motion_compensation.h"
#include "radar_ndt/pipeline/scanning_run.h"

using namespace radar_ndt;

namespace {

struct Inner {
  int count = 2;
  template <typename Visit>
  static void fields(Visit&& visit) {
    visit(&Inner::count, Field("count", "at least one").atLeast(1));
  }
};

struct Outer {
  double size = 1.0;
  float share = 0.5f;
  std::vector<double> lengths{1.0, 2.0};
  double limit = 1.0;
  Inner inner;
  template <typename Visit>
  static void fields(Visit&& visit) {
    visit(&Outer::size, Field("size", "a length").unit("m").positive());
    visit(&Outer::share, Field("share", "a share").atLeast(0).below(1));
    visit(&Outer::lengths, Field("lengths", "lengths").positive());
    visit(&Outer::limit, Field("limit", "a bound").atLeast(0).orInfinite());
    visit(&Outer::inner, Field("inner", "nested"));
  }
};

std::string messageOf(const Outer& o) {
  try {
    checkFields(o, "Outer");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Fields, ChecksEveryNumberAgainstItsBoundsAndNamesTheField) {
  Outer o;
  EXPECT_EQ(messageOf(o), "");
  o.size = 0;
  EXPECT_EQ(messageOf(o), "Outer: size must be > 0 (got 0)");
  o = Outer();
  o.share = 1.0f;
  EXPECT_EQ(messageOf(o), "Outer: share must be in [0, 1) (got 1)");
  o = Outer();
  o.size = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(messageOf(o).find("size"), std::string::npos) << "NaN is never within bounds";
  o = Outer();
  o.size = std::numeric_limits<double>::infinity();
  EXPECT_NE(messageOf(o).find("size"), std::string::npos) << "infinity only where the field allows it";
  o = Outer();
  o.limit = std::numeric_limits<double>::infinity();
  EXPECT_EQ(messageOf(o), "") << "infinity: no bound";
  o.lengths = {1.0, -2.0};
  EXPECT_EQ(messageOf(o), "Outer: lengths must be > 0 (got -2)") << "each number of a list";
  o = Outer();
  o.inner.count = 0;
  EXPECT_EQ(messageOf(o), "Outer.inner: count must be >= 1 (got 0)") << "a nested table, named by its path";
}

TEST(Fields, TheTablesOfTheLibrarysOptionsValidateThem) {
  ScanningRunOptions o;
  EXPECT_NO_THROW(o.validate());
  o.odometry.keyframes.distance = -1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = ScanningRunOptions();
  o.sequence.oxford.convention.range_resolution = 0;
  try {
    o.validate();
    FAIL() << "a bin size of 0";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("oxford.convention: range_resolution"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(HasFields<ScanningRunOptions>::value);
  EXPECT_FALSE(HasFields<double>::value);
}

TEST(Fields, AnEnumerationsNameTableParsesPrintsAndListsIt) {
  EXPECT_STREQ(toString(CompensationMode::Joint), "joint");
  EXPECT_EQ(parseEnum<CompensationMode>("rounds"), CompensationMode::Rounds);
  EXPECT_EQ(enumChoices<CompensationMode>(" | "), "rounds | joint");
  try {
    parseEnum<CompensationMode>("both");
    FAIL() << "an unknown name";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "unknown compensation mode 'both' (rounds, joint)");
  }
  EXPECT_EQ(Bounds{}.text(), "finite");
}
