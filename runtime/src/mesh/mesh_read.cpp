// Puff's readers of OBJ, OFF, PLY, STL and glTF (mesh_read.h): the dispatch by format and the helpers the
// per-format readers (mesh_read_*.cpp) share.
#include "mesh_read.h"

#include <puff/core/files.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "mesh_read_formats.h"

namespace puff::mesh::detail {

namespace fs = std::filesystem;

const char* formatName(Format f) {
  switch (f) {
    case Format::Obj:
      return "OBJ";
    case Format::Off:
      return "OFF";
    case Format::Ply:
      return "PLY";
    case Format::Stl:
      return "STL";
    case Format::Gltf:
      return "glTF";
  }
  return "?";
}

Error notValid(const fs::path& path, Format f, const std::string& detail) {
  return Error::at(path,
                   std::string("not a valid ") + formatName(f) + " file" + (detail.empty() ? "" : " (" + detail + ")"));
}

std::string lineText(std::size_t n) { return "line " + std::to_string(n); }

bool hasControlBytes(std::string_view line) {
  for (char c : line) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 && !isBlank(c)) || u == 0x7f) return true;
  }
  return false;
}

std::vector<std::string_view> tokens(std::string_view s) {
  std::vector<std::string_view> out;
  for (std::string_view t = firstToken(s); !t.empty(); t = firstToken(s)) {
    s = trimLeft(s);
    s.remove_prefix(t.size());
    out.push_back(t);
  }
  return out;
}

std::optional<double> number(std::string_view token) {
  if (token.empty() || token.size() > 64) return std::nullopt;
  char buf[65];
  std::memcpy(buf, token.data(), token.size());
  buf[token.size()] = '\0';
  char* end = nullptr;
  const double v = std::strtod(buf, &end);
  if (end != buf + token.size()) return std::nullopt;
  return v;
}

std::optional<std::int64_t> integer(std::string_view token) {
  if (token.empty() || token.size() > 32) return std::nullopt;
  char buf[33];
  std::memcpy(buf, token.data(), token.size());
  buf[token.size()] = '\0';
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(buf, &end, 10);
  if (end != buf + token.size() || errno == ERANGE) return std::nullopt;
  return v;
}

Result<RawMesh> readRawMesh(const fs::path& path, Format format) {
  PUFF_TRY_ASSIGN(auto bytes, core::readFileBytes(path));
  const std::string& text = bytes;
  switch (format) {
    case Format::Obj:
      return readObj(path, text);
    case Format::Off:
      return readOff(path, text);
    case Format::Ply:
      return readPly(path, text);
    case Format::Stl:
      return readStl(path, text);
    case Format::Gltf:
      return readGltf(path, text);
  }
  return notValid(path, format);
}

}  // namespace puff::mesh::detail
