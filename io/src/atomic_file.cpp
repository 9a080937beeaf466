#include "radar_ndt/io/atomic_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "radar_ndt/io/io_error.h"
#include "read_file.h"

namespace radar_ndt {

void detail::readWholeFile(const std::string& path, std::string& bytes) {
  // One read into a buffer of the file's size (a stream through a stringstream copied it twice).
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw IoError(path, "cannot open file for reading");
  struct stat st {};
  const bool regular = ::fstat(::fileno(f), &st) == 0 && S_ISREG(st.st_mode);
  if (!regular && S_ISDIR(st.st_mode)) {
    std::fclose(f);
    throw IoError(path, "cannot open file for reading: it is a directory");
  }
  bytes.resize(regular ? static_cast<std::size_t>(st.st_size) : 0);  // a pipe is read to its end
  std::size_t got = bytes.empty() ? 0 : std::fread(&bytes[0], 1, bytes.size(), f);
  // A file that grew since fstat (or a pipe) is read to its end.
  for (char c[4096]; !std::ferror(f);) {
    const std::size_t more = std::fread(c, 1, sizeof c, f);
    if (more == 0) break;
    bytes.append(c, more);
    got += more;
  }
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw IoError(path, "read error");
  bytes.resize(got);
}

std::string detail::readWholeFile(const std::string& path) {
  std::string bytes;
  readWholeFile(path, bytes);
  return bytes;
}

void writeFileAtomically(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp." + std::to_string(static_cast<long>(::getpid()));
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw IoError(path, std::string("cannot open for writing: ") + std::strerror(errno));
  const bool written = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  const bool flushed = std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
  const bool closed = std::fclose(f) == 0;
  if (!written || !flushed || !closed) {
    const int err = errno;
    std::remove(tmp.c_str());
    throw IoError(path, std::string("write failed: ") + std::strerror(err));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp.c_str());
    throw IoError(path, std::string("cannot rename the temporary file into place: ") + std::strerror(err));
  }
}

}  // namespace radar_ndt
