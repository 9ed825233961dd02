// puffrender --contact-sheet and --preview: a sequence seen as a whole. The contact sheet is a grid of
// the frames, each with its number (one frame in N when more do not fit); the preview an animated GIF (OpenImageIO's
// writer) or MP4 (the ffmpeg program, fed raw frames through a pipe). Both are written beside their targets and renamed
// over them only when whole.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include <cli/app.h>
#include <puff/core/colour.h>
#include <puff/core/files.h>
#include <puff/io/openimageio.h>
#include <puff/scene/evaluate.h>
#include <puff/support/label.h>
#include <puff/support/text.h>

#include "commands.h"

namespace puff::app {

namespace fs = std::filesystem;

namespace {

constexpr int kGap = 4;
constexpr int kThumbMaxWidth = 256, kSheetMaxWidth = 2048, kSheetMaxHeight = 8192;
constexpr int kGifMaxWidth = 640;
const glm::vec3 kSheetBackground(0.18f, 0.18f, 0.2f), kLabelColor(0.9f, 0.9f, 0.86f);

// `image` shrunk by a whole `factor` on each side, each pixel the mean of its factor x factor block.
core::Image shrink(const core::Image& image, int factor) {
  if (factor <= 1) return image;
  const int w = image.width / factor, h = image.height / factor;
  core::Image out(w, h, image.channels);
  const float n = static_cast<float>(factor * factor);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < image.channels; ++c) {
        float sum = 0.0f;
        for (int by = 0; by < factor; ++by) {
          for (int bx = 0; bx < factor; ++bx) sum += image.at(x * factor + bx, y * factor + by, c);
        }
        out.at(x, y, c) = sum / n;
      }
    }
  }
  return out;
}

int shrinkFactor(int width, int maxWidth) { return std::max(1, (width + maxWidth - 1) / maxWidth); }

// A rendered frame (scene-linear; a transparent one premultiplied) as an opaque display image: a
// transparent frame over a grey checker, so that what is see-through reads as such.
core::Image opaqueDisplay(const core::Image& linear, core::ViewTransform view, bool transparent) {
  if (!transparent) return core::viewTransform(linear, view);
  core::Image over = linear;
  for (int y = 0; y < over.height; ++y) {
    for (int x = 0; x < over.width; ++x) {
      const float bg = ((x / 8 + y / 8) % 2) ? 0.45f : 0.2f;  // scene-linear
      const float a = over.at(x, y, 3);
      for (int c = 0; c < 3; ++c) over.at(x, y, c) += (1.0f - a) * bg;
      over.at(x, y, 3) = 1.0f;
    }
  }
  return core::viewTransform(over, view);
}

// The ffmpeg program on PATH, or empty.
fs::path findOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate = fs::path(end > start ? dirs.substr(start, end - start) : ".") / program;
    if (::access(candidate.c_str(), X_OK) == 0 && fs::is_regular_file(candidate)) return candidate;
    start = end + 1;
  }
  return {};
}

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// An MP4 through ffmpeg: raw RGB frames into its standard input.
class Mp4Pipe {
 public:
  static Result<std::unique_ptr<Mp4Pipe>> open(const fs::path& ffmpeg, const fs::path& staged, const fs::path& target,
                                               int width, int height, double fps) {
    std::unique_ptr<Mp4Pipe> m(new Mp4Pipe());
    m->target_ = target;
    m->width_ = width;
    m->height_ = height;
    m->log_ = staged;
    m->log_ += ".log";
    char rate[32];
    std::snprintf(rate, sizeof rate, "%.6g", fps);
    // H.264 in yuv420p (what players play) needs even sides: padded by a pixel where odd.
    const std::string cmd =
        shellQuote(ffmpeg.string()) + " -hide_banner -loglevel error -y -f rawvideo -pix_fmt rgb24" + " -s " +
        std::to_string(width) + "x" + std::to_string(height) + " -framerate " + rate + " -i - -vf " +
        shellQuote("pad=ceil(iw/2)*2:ceil(ih/2)*2") + " -c:v libx264 -pix_fmt yuv420p -movflags +faststart " +
        shellQuote(staged.string()) + " 2>" + shellQuote(m->log_.string());
    std::signal(SIGPIPE, SIG_IGN);  // ffmpeg failing shows as a write error, not a killed puffrender
    m->pipe_ = ::popen(cmd.c_str(), "w");
    if (!m->pipe_) return Error::at(target, std::string("cannot start ffmpeg: ") + std::strerror(errno));
    m->row_.resize(static_cast<std::size_t>(width) * 3);
    return m;
  }
  ~Mp4Pipe() {
    if (pipe_) ::pclose(pipe_);
    std::error_code ec;
    fs::remove(log_, ec);
  }
  Result<void> add(const core::Image& display) {
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        for (int c = 0; c < 3; ++c) {
          const float v = std::clamp(display.at(x, y, c), 0.0f, 1.0f);
          row_[static_cast<std::size_t>(x) * 3 + static_cast<std::size_t>(c)] =
              static_cast<unsigned char>(v * 255.0f + 0.5f);
        }
      }
      if (std::fwrite(row_.data(), 1, row_.size(), pipe_) != row_.size())
        return failed("ffmpeg stopped reading frames");
    }
    return {};
  }
  Result<void> close() {
    const int status = ::pclose(pipe_);
    pipe_ = nullptr;
    if (status != 0) return failed("ffmpeg failed (exit status " + std::to_string(WEXITSTATUS(status)) + ")");
    return {};
  }

 private:
  Mp4Pipe() = default;
  // The first line ffmpeg wrote on its stderr says why.
  Error failed(const std::string& what) {
    if (pipe_) ::pclose(pipe_), pipe_ = nullptr;
    std::string why;
    if (auto text = core::readFileBytes(log_); text && !text->empty()) why = ": " + core::oneLine(*text);
    return Error::at(target_, what + why);
  }
  std::FILE* pipe_ = nullptr;
  fs::path target_, log_;
  int width_ = 0, height_ = 0;
  std::vector<unsigned char> row_;
};

}  // namespace

std::string previewSupport() {
  const bool gif = io::canWriteGif();
  const fs::path ffmpeg = findOnPath("ffmpeg");
  return std::string("on this machine: GIF ") +
         (gif ? "yes (OpenImageIO)" : "no (this OpenImageIO has no GIF writer)") + ", MP4 " +
         (ffmpeg.empty() ? "no (no ffmpeg on PATH)" : "yes (" + ffmpeg.string() + ")");
}

Result<void> checkPreviewTarget(const std::string& preview) {
  const std::string ext = core::lower(fs::path(preview).extension().string());
  if (ext == ".gif") {
    if (!io::canWriteGif()) {
      return Error{"--preview " + preview +
                   ": this OpenImageIO has no GIF writer; write an .mp4 preview (needs ffmpeg) "
                   "instead"};
    }
    return {};
  }
  if (ext == ".mp4") {
    if (findOnPath("ffmpeg").empty()) {
      return Error{"--preview " + preview +
                   ": an MP4 preview needs the ffmpeg program, and there is none on PATH "
                   "(apt install ffmpeg), or write a .gif preview" +
                   (io::canWriteGif() ? ""
                                      : " (not here either: this "
                                        "OpenImageIO has no GIF writer)")};
    }
    return {};
  }
  return Error{"--preview " + preview + ": expected a .gif or .mp4 name (" + previewSupport() + ")"};
}

struct SequenceExtras::Impl {
  Impl(const Options& options, const scene::Scene& s, const Plan& p)
      : o(options), scene(s), plan(p), view(scene::viewTransformFor(s)) {}
  const Options& o;
  const scene::Scene& scene;
  const Plan& plan;
  core::ViewTransform view;
  int count = 0;
  // The contact sheet.
  core::OutputTransaction sheetTx;
  core::Image sheet;
  int stride = 1, columns = 1, thumbFactor = 1, thumbW = 0, thumbH = 0, shown = 0;
  int pitchX = 0, pitchY = 0, header = 0, labelScale = 1;
  // The preview.
  core::OutputTransaction previewTx;
  fs::path previewStaged;
  int previewFactor = 1;
  io::GifTiming gifTiming;
  std::unique_ptr<io::AnimatedGif> gif;
  std::unique_ptr<Mp4Pipe> mp4;
};

SequenceExtras::SequenceExtras(const Options& o, const scene::Scene& scene, const Plan& plan)
    : impl_(new Impl(o, scene, plan)) {}
SequenceExtras::~SequenceExtras() = default;

bool SequenceExtras::wanted() const { return !impl_->o.contactSheet.empty() || !impl_->o.preview.empty(); }

Result<void> SequenceExtras::open() {
  Impl& m = *impl_;
  m.count = m.plan.last - m.plan.first + 1;
  const int w = m.scene.width, h = m.scene.height;
  if (!m.o.contactSheet.empty()) {
    // Its directory is made and checked now, not after every frame has been drawn.
    const fs::path target = m.o.contactSheet;
    const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    PUFF_TRY(m.sheetTx.prepareDirectory(dir));
    if (::access(dir.c_str(), W_OK) != 0)
      return Error::at(target, std::string("cannot write: ") + std::strerror(errno));
    m.thumbFactor = shrinkFactor(w, kThumbMaxWidth);
    m.thumbW = std::max(1, w / m.thumbFactor);
    m.thumbH = std::max(1, h / m.thumbFactor);
    // Each thumbnail has its frame number under it (twice the font's size under thumbnails 160
    // pixels wide and more); columns at least as wide as a 5-digit number.
    m.labelScale = m.thumbW >= 160 ? 2 : 1;
    m.header = kGap + core::textHeight(m.labelScale) + kGap;
    m.pitchX = std::max(m.thumbW, core::textWidth("00000", m.labelScale)) + kGap;
    m.pitchY = m.thumbH + core::textHeight(m.labelScale) + 2 * kGap;
    m.columns = std::clamp((kSheetMaxWidth - kGap) / m.pitchX, 1, m.count);
    const int maxRows = std::max(1, (kSheetMaxHeight - m.header) / m.pitchY);
    // More frames than fit: every stride-th frame, from the first.
    m.stride = std::max(1, (m.count + m.columns * maxRows - 1) / (m.columns * maxRows));
    m.shown = (m.count + m.stride - 1) / m.stride;
    m.columns = std::min(m.columns, m.shown);
    const int rows = (m.shown + m.columns - 1) / m.columns;
    std::string title =
        m.scene.file.stem().string() + ": FRAMES " + std::to_string(m.plan.first) + "-" + std::to_string(m.plan.last);
    if (m.stride > 1) title += ", ONE IN " + std::to_string(m.stride);
    const int width = std::max(kGap + m.columns * m.pitchX, 2 * kGap + core::textWidth(title, m.labelScale));
    m.sheet = core::Image(width, m.header + rows * m.pitchY, 3);
    for (std::size_t i = 0; i < m.sheet.pixels.size(); i += 3) {
      for (int c = 0; c < 3; ++c) m.sheet.pixels[i + static_cast<std::size_t>(c)] = kSheetBackground[c];
    }
    core::drawText(m.sheet, kGap, kGap, title, kLabelColor, m.labelScale);
  }
  if (!m.o.preview.empty()) {
    const fs::path target = m.o.preview;
    if (!target.parent_path().empty()) {
      if (auto r = m.previewTx.prepareDirectory(target.parent_path()); !r) return r.error();
    }
    m.previewStaged = m.previewTx.stage(target);
    const bool isGif = core::lower(target.extension().string()) == ".gif";
    const double fps = m.scene.animation.fps;
    if (isGif) {
      // A GIF holds 256 colours a frame and no compression across frames: at most 640 pixels wide.
      m.previewFactor = shrinkFactor(w, kGifMaxWidth);
      m.gifTiming = io::gifTiming(m.count, fps);
      PUFF_TRY_ASSIGN(auto gif, io::AnimatedGif::open(m.previewStaged, static_cast<int>(m.gifTiming.source.size()),
                                                      std::max(1, w / m.previewFactor),
                                                      std::max(1, h / m.previewFactor), m.gifTiming.delay, target));
      m.gif = std::move(gif);
    } else {
      PUFF_TRY_ASSIGN(m.mp4, Mp4Pipe::open(findOnPath("ffmpeg"), m.previewStaged, target, w, h, fps));
    }
  }
  return {};
}

Result<void> SequenceExtras::add(int frame, const core::Image& linear) {
  Impl& m = *impl_;
  const core::Image display = opaqueDisplay(linear, m.view, m.scene.transparent);
  const int index = frame - m.plan.first;
  if (!m.sheet.empty() && index % m.stride == 0) {
    const int slot = index / m.stride;
    const int ox = kGap + (slot % m.columns) * m.pitchX, oy = m.header + (slot / m.columns) * m.pitchY;
    const core::Image thumb = shrink(display, m.thumbFactor);
    for (int y = 0; y < std::min(m.thumbH, thumb.height); ++y) {
      for (int x = 0; x < std::min(m.thumbW, thumb.width); ++x) {
        for (int c = 0; c < 3; ++c) m.sheet.at(ox + x, oy + y, c) = thumb.at(x, y, c);
      }
    }
    core::drawText(m.sheet, ox, oy + m.thumbH + kGap / 2, std::to_string(frame), kLabelColor, m.labelScale);
  }
  if (m.gif) {
    // As many GIF frames as are due while this frame shows (none, one, or a repeat).
    const auto shows = std::count(m.gifTiming.source.begin(), m.gifTiming.source.end(), index);
    if (shows > 0) {
      const core::Image small = shrink(display, m.previewFactor);
      for (long k = 0; k < shows; ++k) PUFF_TRY(m.gif->add(small));
    }
  }
  if (m.mp4) PUFF_TRY(m.mp4->add(display));
  return {};
}

Result<std::string> SequenceExtras::finish() {
  Impl& m = *impl_;
  std::string said;
  if (!m.sheet.empty()) {
    const fs::path target = m.o.contactSheet;
    const fs::path staged = m.sheetTx.stage(target);
    PUFF_TRY(core::writeImage(staged, m.sheet, core::PixelType::kUInt8,
                              {{"puff:view", std::string(core::toString(m.view))}}, target));
    PUFF_TRY(m.sheetTx.commit());
    said += std::string(cli::name()) + ": contact sheet: " + target.string() + " (" + std::to_string(m.sheet.width) +
            "x" + std::to_string(m.sheet.height) + ", " + std::to_string(m.shown) +
            (m.shown == 1 ? " frame" : " frames") + (m.stride > 1 ? ", one in " + std::to_string(m.stride) : "") +
            ")\n";
  }
  if (m.gif || m.mp4) {
    if (m.gif) PUFF_TRY(m.gif->close());
    if (m.mp4) PUFF_TRY(m.mp4->close());
    PUFF_TRY(m.previewTx.commit());
    char rate[200];
    if (m.gif) {
      std::snprintf(rate, sizeof rate, "%d frame%s at %g fps as %zu GIF frames %d/100 s apart, GIF by OpenImageIO",
                    m.count, m.count == 1 ? "" : "s", static_cast<double>(m.scene.animation.fps),
                    m.gifTiming.source.size(), m.gifTiming.delay);
    } else {
      std::snprintf(rate, sizeof rate, "%d frame%s at %g fps, MP4 (H.264) by ffmpeg", m.count, m.count == 1 ? "" : "s",
                    static_cast<double>(m.scene.animation.fps));
    }
    said += std::string(cli::name()) + ": preview: " + m.o.preview + " (" + rate + ")\n";
  }
  return said;
}

}  // namespace puff::app
