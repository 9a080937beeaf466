#pragma once
// Shared by the libFuzzer targets. The readers take paths (as users call them), so each input is
// written to a file in a private scratch directory (/dev/shm when it exists) and read back.
//
// The contract every target checks: a reader either returns a well-formed result or throws
// radar_ndt::IoError whose message names the file. Any other exception, a crash, a sanitizer report,
// a hang (-timeout) or a huge allocation (-rss_limit_mb / -malloc_limit_mb) is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "radar_ndt/io/io_error.h"

namespace radar_ndt {
namespace fuzz {

inline const std::string& scratchDir() {
  // Never destroyed: the exit handler that removes the directory runs after static destructors.
  static const std::string* const dir = [] {
    std::string pattern = std::string(::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp") + "/radar_ndt_fuzz_XXXXXX";
    if (::mkdtemp(pattern.data()) == nullptr) {
      std::perror("radar_ndt fuzz: mkdtemp");
      std::abort();
    }
    return new std::string(pattern);
  }();
  static const bool cleanup_registered = [] {
    return std::atexit([] {
             std::error_code ec;
             std::filesystem::remove_all(*dir, ec);
           }) == 0;
  }();
  (void)cleanup_registered;
  return *dir;
}

inline std::string writeBytes(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = scratchDir() + "/" + name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
    std::perror(path.c_str());
    std::abort();
  }
  return path;
}

/// A failed post-condition: a silent wrong answer is a finding like a crash.
[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "radar_ndt fuzz finding: %s\n", what.c_str());
  std::abort();
}

/// Runs `read()`; an IoError naming `path` is a correct answer to bad bytes, anything else escapes.
template <class Read>
void readOrIoError(const std::string& path, Read&& read) {
  try {
    read();
  } catch (const IoError& e) {
    if (std::string(e.what()).find(path) == std::string::npos)
      finding(std::string("IoError does not name the file: ") + e.what());
  }
}

}  // namespace fuzz
}  // namespace radar_ndt
