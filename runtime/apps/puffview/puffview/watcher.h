// Polls files for changes by modification time and size (no inotify: it works the same on every
// file system, and a few dozen stat calls every 250 ms cost nothing). Editors save in odd ways
// (write a temp file and rename, truncate then write, delete then create), so a file that vanishes
// or changes twice in a row is simply reported again; the caller retries on each report.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace puff::view {

class FileWatcher {
 public:
  /// Replaces the watched set. Files in `files` are watched individually (they may not exist yet);
  /// each directory in `dirs` is watched recursively (files added, removed or changed under it).
  /// The current state becomes the baseline: nothing is reported until it changes again.
  void watch(std::vector<std::filesystem::path> files, std::vector<std::filesystem::path> dirs = {});
  /// The watched files (or directory entries) that changed since the last poll (or watch).
  std::vector<std::filesystem::path> poll();
  /// Takes the current state of `file` as seen (e.g. after the viewer saved it itself).
  void markSeen(const std::filesystem::path& file);
  const std::vector<std::filesystem::path>& files() const { return files_; }
  const std::vector<std::filesystem::path>& dirs() const { return dirs_; }

 private:
  struct Stamp {
    bool exists = false;
    std::filesystem::file_time_type mtime{};
    std::uintmax_t size = 0;
    bool operator==(const Stamp&) const = default;
  };
  static Stamp stamp(const std::filesystem::path& file);
  std::map<std::filesystem::path, Stamp> snapshot() const;

  std::vector<std::filesystem::path> files_, dirs_;
  std::map<std::filesystem::path, Stamp> seen_;
};

}  // namespace puff::view
