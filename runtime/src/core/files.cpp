#include <puff/core/files.h>

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

namespace puff::core {

namespace fs = std::filesystem;

OutputTransaction::~OutputTransaction() {
  if (committed_) return;
  std::error_code ec;
  for (const auto& [temp, target] : staged_) fs::remove(temp, ec);
  for (auto it = createdDirs_.rbegin(); it != createdDirs_.rend(); ++it) {
    if (fs::is_empty(*it, ec)) fs::remove(*it, ec);
  }
}

Result<void> OutputTransaction::prepareDirectory(const fs::path& dir) {
  if (dir.empty()) return {};
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) return Error::at(dir, "not a directory");
  } else {
    // Remember each directory we create so a failed run can take them back.
    std::vector<fs::path> missing;
    for (fs::path p = dir; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
      missing.push_back(p);
      if (p == p.parent_path()) break;
    }
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
      if (!fs::create_directory(*it, ec) && ec) {
        return Error::at(*it, "cannot create directory: " + ec.message());
      }
      createdDirs_.push_back(*it);
    }
  }
  if (::access(dir.c_str(), W_OK) != 0) return Error::at(dir, std::string("cannot write: ") + std::strerror(errno));
  // access() answers for the permission bits, which root passes even where no file can be made
  // (/proc): a file is made and removed here, so that a run fails before its work, not after.
  const fs::path probe = dir / (".puff-probe-" + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0 && errno != EEXIST) return Error::at(dir, std::string("cannot write: ") + std::strerror(errno));
  if (fd >= 0) {
    ::close(fd);
    ::unlink(probe.c_str());
  }
  return {};
}

namespace {

// Removes the files runs that are gone (killed before they could clean up: a process PID that no
// longer exists) left for `target`: DIR/.NAME.tmp-PID.EXT that `stage` named, and DIR/NAME.bak-PID
// that `commit` linked.
void removeStaleTemps(const fs::path& target) {
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  const std::string temp = "." + target.filename().string() + ".tmp-", backup = target.filename().string() + ".bak-";
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::size_t at = 0;
    if (name.compare(0, temp.size(), temp) == 0) {
      at = temp.size();
    } else if (name.compare(0, backup.size(), backup) == 0) {
      at = backup.size();
    } else {
      continue;
    }
    char* after = nullptr;
    const long pid = std::strtol(name.c_str() + at, &after, 10);
    if (at == backup.size() && *after != '\0') continue;  // NAME.bak-PID and nothing after
    if (pid <= 0 || pid == ::getpid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to ask
    std::error_code removed;
    fs::remove(it->path(), removed);
  }
}

}  // namespace

fs::path OutputTransaction::stage(const fs::path& target) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on a chain of operator+.
  std::string name = ".";
  name += target.filename().string();
  name += ".tmp-";
  name += std::to_string(::getpid());
  name += target.extension().string();
  const fs::path temp = target.parent_path() / name;
  removeStaleTemps(target);
  staged_.emplace_back(temp, target);
  return temp;
}

Result<fs::path> OutputTransaction::nameByContent(const fs::path& staged) {
  const auto it = std::find_if(staged_.begin(), staged_.end(), [&](const auto& s) { return s.first == staged; });
  PUFF_CHECK(it != staged_.end());
  auto bytes = readFileBytes(staged);
  if (!bytes) return Error::at(it->second, "cannot read back what was written: " + bytes.error().message);
  const fs::path& target = it->second;
  std::string name = target.stem().string();
  name += ".";
  name += fnv1a64Hex(*bytes).substr(0, 12);
  name += target.extension().string();
  it->second = target.parent_path() / name;
  return it->second;
}

Result<void> OutputTransaction::commit() {
  // Refuse before touching anything if a target can never be replaced by a file.
  for (const auto& [temp, target] : staged_) {
    std::error_code ec;
    if (fs::is_directory(target, ec)) return Error::at(target, "cannot replace: is a directory");
  }
  // What killed runs left for the final names (a content name is known only now).
  for (const auto& [temp, target] : staged_) removeStaleTemps(target);
  // Keep a hard link to each existing target so a rename that still fails part-way can be undone
  // and the previous outputs come back whole.
  std::vector<std::pair<fs::path, fs::path>> backups;  // backup, target
  auto rollback = [&](std::size_t renamed) {
    std::error_code ec;
    for (std::size_t i = 0; i < renamed; ++i) fs::remove(staged_[i].second, ec);
    for (const auto& [backup, target] : backups) fs::rename(backup, target, ec);
  };
  for (const auto& [temp, target] : staged_) {
    std::error_code ec;
    if (!fs::exists(target, ec)) continue;
    fs::path backup = target;
    backup += ".bak-" + std::to_string(::getpid());
    fs::create_hard_link(target, backup, ec);
    if (ec) {
      rollback(0);
      return Error::at(target, "cannot replace: " + ec.message());
    }
    backups.emplace_back(backup, target);
  }
  for (std::size_t i = 0; i < staged_.size(); ++i) {
    std::error_code ec;
    fs::rename(staged_[i].first, staged_[i].second, ec);
    if (ec) {
      rollback(i);
      return Error::at(staged_[i].second, "cannot replace: " + ec.message());
    }
  }
  std::error_code ec;
  for (const auto& [backup, target] : backups) fs::remove(backup, ec);
  committed_ = true;
  return {};
}

Result<std::string> readFileBytes(const fs::path& path) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (fs::is_directory(status)) return Error::at(path, "cannot open: is a directory");
  // A FIFO would block the read and a device (/dev/zero) never ends.
  if (fs::exists(status) && !fs::is_regular_file(status)) return Error::at(path, "cannot open: not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error::at(path, std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) return Error::at(path, "read error");
  return ss.str();
}

Result<void> writeFileBytes(const fs::path& path, const std::string& bytes, const fs::path& name) {
  const fs::path& shown = name.empty() ? path : name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return Error::at(shown, std::string("cannot write: ") + std::strerror(errno));
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.flush();
  if (!out) return Error::at(shown, "write failed (disk full?)");
  return {};
}

Result<void> writeFileAtomic(const fs::path& path, const std::string& bytes) {
  OutputTransaction tx;
  PUFF_TRY(tx.prepareDirectory(path.parent_path()));
  PUFF_TRY(writeFileBytes(tx.stage(path), bytes, path));
  return tx.commit();
}

bool sameFile(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code ec;
  if (std::filesystem::equivalent(a, b, ec)) return true;
  std::error_code ea, eb;
  const std::filesystem::path ca = std::filesystem::weakly_canonical(a, ea),
                              cb = std::filesystem::weakly_canonical(b, eb);
  return !ea && !eb ? ca == cb : a.lexically_normal() == b.lexically_normal();
}

std::string fnv1a64Hex(const std::string& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace puff::core
