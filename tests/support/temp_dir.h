// A scratch directory for a test: made unique under the system's temporary directory when
// constructed, removed with everything in it when destroyed.
#pragma once

#include <stdlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace puff::test {

class ScopedTempDir {
 public:
  /// Makes TMP/PREFIX-XXXXXX (mkdtemp: a new directory, only this process's).
  explicit ScopedTempDir(const std::string& prefix = "puff_test") {
    std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
    if (!::mkdtemp(pattern.data())) {
      throw std::runtime_error("ScopedTempDir: cannot create " + pattern + ": " + std::strerror(errno));
    }
    path_ = pattern;
  }
  ~ScopedTempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScopedTempDir(const ScopedTempDir&) = delete;
  ScopedTempDir& operator=(const ScopedTempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& p) const { return path_ / p; }

 private:
  std::filesystem::path path_;
};

}  // namespace puff::test
