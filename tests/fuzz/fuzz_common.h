// What every Puff fuzz harness shares: a private directory to write each input into (Puff's readers
// read files, as the tools do), and the OpenImageIO codec installed as the tools install it.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <puff/core/files.h>
#include <puff/io/openimageio.h>

namespace puff::fuzz {

// A directory of this process's own, removed at exit (libFuzzer's -fork and -jobs run several).
inline const std::filesystem::path& workDir() {
  static const std::filesystem::path dir = [] {
    std::error_code ec;
    const std::filesystem::path base =
        std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path(ec);
    std::filesystem::path d = base / ("puff-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d, ec);
    if (ec) {
      std::fprintf(stderr, "puff fuzz: cannot create %s: %s\n", d.c_str(), ec.message().c_str());
      std::abort();
    }
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(workDir(), ignored);
    });
    return d;
  }();
  return dir;
}

// Writes the input to workDir()/name and returns that path (the same file every run).
inline std::filesystem::path writeInput(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path p = workDir() / name;
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  f.close();
  if (!f) {
    std::fprintf(stderr, "puff fuzz: cannot write %s\n", p.c_str());
    std::abort();
  }
  return p;
}

// A Puff error is one line that names the file: anything else is a defect the fuzzer reports.
template <class R>
void expectCleanError(const R& result) {
  if (result.ok()) return;
  const std::string& m = result.error().message;
  if (m.empty() || m.find('\n') != std::string::npos) {
    std::fprintf(stderr, "puff fuzz: an error that is not one line: [%s]\n", m.c_str());
    std::abort();
  }
}

// The extension an image input is written with, from its first byte: the reader is chosen by the
// file's bytes (cooked images by their magic, OpenImageIO by content and extension).
inline const char* imageExtension(std::uint8_t selector) {
  static const char* kExt[] = {".png", ".exr", ".puffimg"};
  return kExt[selector % 3];
}

}  // namespace puff::fuzz
