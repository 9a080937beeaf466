// io/atomic_file.h: a file is written whole under its final name or not at all, and a failure is
// an IoError naming the file, with no temporary file left behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/io_error.h"
#include "test_support.h"

using namespace radar_ndt;
namespace fs = std::filesystem;

TEST(AtomicFile, WritesAndReplacesWholeFilesAndLeavesNoTemporary) {
  const std::string dir = test::freshTempDir("atomic");
  const std::string path = dir + "/out.txt";
  writeFileAtomically(path, "first\n");
  EXPECT_EQ(test::readBytes(path), "first\n");
  const std::string big(1 << 20, 'x');
  writeFileAtomically(path, big);
  EXPECT_EQ(test::readBytes(path), big) << "replaced, not appended";
  writeFileAtomically(path, "");
  EXPECT_TRUE(fs::exists(path));
  EXPECT_EQ(fs::file_size(path), 0u);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "out.txt") << "a temporary file was left behind";
  }
  EXPECT_EQ(files, 1u);
}

TEST(AtomicFile, AFailureNamesTheFileAndKeepsTheOldContent) {
  const std::string dir = test::freshTempDir("atomic_fail");
  const std::string missing = dir + "/no_such_folder/out.txt";
  try {
    writeFileAtomically(missing, "x");
    FAIL() << "expected an IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  // A directory in the way of the final name: the rename fails, the directory stays, and the
  // temporary file is removed.
  const std::string blocked = dir + "/blocked";
  fs::create_directories(blocked + "/inside");
  EXPECT_THROW(writeFileAtomically(blocked, "x"), IoError);
  EXPECT_TRUE(fs::is_directory(blocked + "/inside"));
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 1u) << "only the directory: no temporary file";
}
