#include <puffview/watcher.h>

#include <set>

namespace puff::view {

namespace fs = std::filesystem;

FileWatcher::Stamp FileWatcher::stamp(const fs::path& file) {
  Stamp s;
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (ec || !fs::is_regular_file(st)) return s;
  s.mtime = fs::last_write_time(file, ec);
  if (ec) return Stamp{};
  s.size = fs::file_size(file, ec);
  if (ec) return Stamp{};
  s.exists = true;
  return s;
}

std::map<fs::path, FileWatcher::Stamp> FileWatcher::snapshot() const {
  std::map<fs::path, Stamp> now;
  for (const fs::path& f : files_) now[f] = stamp(f);
  for (const fs::path& d : dirs_) {
    std::error_code ec;
    for (fs::recursive_directory_iterator it(d, ec), end; !ec && it != end; it.increment(ec)) {
      if (it->is_regular_file(ec)) now[it->path()] = stamp(it->path());
    }
  }
  return now;
}

void FileWatcher::watch(std::vector<fs::path> files, std::vector<fs::path> dirs) {
  files_ = std::move(files);
  dirs_ = std::move(dirs);
  seen_ = snapshot();
}

std::vector<fs::path> FileWatcher::poll() {
  std::map<fs::path, Stamp> now = snapshot();
  std::vector<fs::path> changed;
  std::set<fs::path> keys;
  for (const auto& [path, s] : now) keys.insert(path);
  for (const auto& [path, s] : seen_) keys.insert(path);
  for (const fs::path& path : keys) {
    const auto a = seen_.find(path), b = now.find(path);
    const Stamp before = a == seen_.end() ? Stamp{} : a->second;
    const Stamp after = b == now.end() ? Stamp{} : b->second;
    if (!(before == after)) changed.push_back(path);
  }
  seen_ = std::move(now);
  return changed;
}

void FileWatcher::markSeen(const fs::path& file) { seen_[file] = stamp(file); }

}  // namespace puff::view
