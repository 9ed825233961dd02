// Files written so that a failure loses nothing: every output goes to a temporary file beside its
// target and is renamed over the target only when all outputs of the operation are complete.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <puff/core/error.h>

namespace puff::core {

/// Stages a set of output files. stage() hands out a temporary path next to each target (same
/// directory, same extension); commit() renames every temporary over its target. If commit() is
/// never reached (an error, an exception), the destructor removes the temporaries and, when the
/// transaction created the output directory and it is still empty, that directory too. Existing
/// files are untouched until commit().
class OutputTransaction {
 public:
  OutputTransaction() = default;
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;
  ~OutputTransaction();

  /// Creates `dir` (and parents) if missing; an error names the directory and the reason.
  Result<void> prepareDirectory(const std::filesystem::path& dir);
  /// A temporary path for `target`, e.g. "out/.puff_color.png.tmp-1234.png".
  std::filesystem::path stage(const std::filesystem::path& target);
  /// Names the file written at `staged` (a path stage() returned) by its content: its target becomes
  /// TARGET's stem, a dot, the first 12 hex digits of the bytes' FNV-1a hash, and TARGET's extension
  /// ("puff_color.mip1.png" -> "puff_color.mip1.3fa2c1b4e5d6.png"). A name then never stands for
  /// other content, so a reader that holds an older index file (an atlas sidecar) never opens a
  /// newer file under a name it knows. Returns the new target.
  Result<std::filesystem::path> nameByContent(const std::filesystem::path& staged);
  /// Renames all staged files over their targets, in the order they were staged.
  Result<void> commit();

 private:
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_;  // temp, target
  std::vector<std::filesystem::path> createdDirs_;
  bool committed_ = false;
};

/// The whole file as bytes; an error says "FILE: cannot open: reason".
Result<std::string> readFileBytes(const std::filesystem::path& path);

/// Writes exactly `path` (for example an OutputTransaction's staged path); errors name `name`
/// (the user-facing target) when given, else `path`.
Result<void> writeFileBytes(const std::filesystem::path& path, const std::string& bytes,
                            const std::filesystem::path& name = {});

/// Writes text through a temporary file and a rename.
Result<void> writeFileAtomic(const std::filesystem::path& path, const std::string& bytes);

/// Whether `a` and `b` name one file: the same file on disk (std::filesystem::equivalent), or, for a
/// file not yet written, the same path once made absolute and normal (weakly_canonical).
bool sameFile(const std::filesystem::path& a, const std::filesystem::path& b);

/// 64-bit FNV-1a of the bytes, as 16 lowercase hex digits. Identifies content, not a security hash.
std::string fnv1a64Hex(const std::string& bytes);

}  // namespace puff::core
