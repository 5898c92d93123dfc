#include "frame_writer.hpp"

#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fcntl.h>
#include <unistd.h>
#include <utility>

#include "frame_files.hpp"

#if HOULE_WITH_OIIO
#include "image_module.hpp"
#endif

namespace houle::cli {

Expected<std::string> format_frame_name(const std::string& pattern, long index) {
  int conversions = 0;
  std::size_t conversion_end = 0;  // position of the conversion's 'd'
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') continue;
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < pattern.size() && (std::isdigit(static_cast<unsigned char>(pattern[j])) || pattern[j] == '0')) ++j;
    if (j >= pattern.size() || pattern[j] != 'd') {
      return Error{pattern, "the output pattern may only hold integer conversions like %04d"};
    }
    // A width past 9999 would make printf pad that far; no file system takes a name over 255 bytes anyway.
    if (j - i - 1 > 4) return Error{pattern, "the frame number's width makes a file name longer than 255 bytes"};
    ++conversions;
    conversion_end = j;
    i = j;
  }
  if (conversions != 1) {
    return Error{pattern, "the output pattern needs exactly one frame-number conversion like %04d, found " +
                              std::to_string(conversions)};
  }
  const std::string pat = pattern.substr(0, conversion_end) + "l" + pattern.substr(conversion_end);  // %04d -> %04ld
  // The width is the user's (at most 9999, checked above): size the name from it.
  std::vector<char> buf(std::size_t(std::snprintf(nullptr, 0, pat.c_str(), index)) + 1);
  std::snprintf(buf.data(), buf.size(), pat.c_str(), index);
  std::string name(buf.data());
  if (const std::string file = std::filesystem::path(name).filename().string(); file.size() > 255) {
    return Error{pattern, "the frame number's width makes a file name of " + std::to_string(file.size()) +
                              " bytes, over the 255 a file system takes"};
  }
  return name;
}

namespace {

// Why frames cannot be created in `dir` (the current folder if empty), or nothing. A missing folder
// is fine where `missing_ok` (created later): then its parent must take it.
std::optional<std::string> folder_problem(std::filesystem::path dir, bool made_if_missing) {
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) {
    if (!made_if_missing) return "the folder " + dir.string() + " does not exist";
    // It will be made with its parents: the nearest folder that exists must take them.
    while (!dir.parent_path().empty() && dir.parent_path() != dir && !std::filesystem::exists(dir, ec)) dir = dir.parent_path();
    if (!std::filesystem::exists(dir, ec)) dir = ".";
  }
  if (!std::filesystem::is_directory(dir, ec)) return dir.string() + " is not a folder";
  if (::access(dir.c_str(), W_OK | X_OK) != 0) return "the folder " + dir.string() + " is not writable (" + std::strerror(errno) + ")";
  return std::nullopt;
}

#if HOULE_WITH_OIIO
class ImageWriter final : public FrameWriter {
 public:
  ImageWriter(const ImageModule& module, std::string pattern, int w, int h, ImageStorage storage)
      : module_(module), pattern_(std::move(pattern)), w_(w), h_(h), storage_(storage), pixels_(std::size_t(w) * h * 3) {}

  WriteStatus write(const Framebuffer& fb, const ToneMap& tm, long index) override {
    const std::string name = format_frame_name(pattern_, index).value();
    const std::string tmp = temp_path(name);
    const bool linear = storage_ != srgb8;
    if (!linear) encode_frame(fb, tm, PixelFormat::rgb24, std::as_writable_bytes(std::span(pixels_)));
    const void* data = linear ? static_cast<const void*>(fb.rgb.data()) : pixels_.data();
    char message[512] = "";
    // The final name picks the format.
    const bool ok = module_.write_rgb(tmp.c_str(), name.c_str(), w_, h_, storage_, data, message, sizeof message) == 0;
    std::error_code ec;
    if (ok) std::filesystem::rename(tmp, name, ec);
    if (!ok || ec) {
      error_ = name + ": cannot write the image: " + (ec ? ec.message() : std::string(message));
      std::filesystem::remove(tmp, ec);
      return WriteStatus::failed;
    }
    return WriteStatus::ok;
  }

 private:
  const ImageModule& module_;
  std::string pattern_;
  int w_, h_;
  ImageStorage storage_;
  std::vector<std::uint8_t> pixels_;
};
#endif

class RawWriter final : public FrameWriter {
 public:
  // `tmp`: where the frames go until finish() renames it to `path` (empty: straight to `path`).
  RawWriter(std::string path, std::string tmp, int fd, PixelFormat f, std::size_t frame_bytes)
      : path_(std::move(path)), tmp_(std::move(tmp)), fd_(fd), format_(f), bytes_(frame_bytes) {}
  ~RawWriter() override {
    if (fd_ > 1) ::close(fd_);
    if (!tmp_.empty()) ::unlink(tmp_.c_str());
  }

  WriteStatus finish() override {
    if (tmp_.empty()) return WriteStatus::ok;
    const int fd = std::exchange(fd_, -1);
    if (::close(fd) != 0 || ::rename(tmp_.c_str(), path_.c_str()) != 0) {
      error_ = path_ + ": cannot write: " + std::strerror(errno);
      return WriteStatus::failed;
    }
    tmp_.clear();
    return WriteStatus::ok;
  }

  WriteStatus write(const Framebuffer& fb, const ToneMap& tm, long) override {
    encode_frame(fb, tm, format_, std::span(bytes_));
    std::size_t done = 0;
    while (done < bytes_.size()) {
      const ssize_t n = ::write(fd_, bytes_.data() + done, bytes_.size() - done);
      if (n > 0) {
        done += std::size_t(n);
      } else if (n < 0 && errno == EINTR) {
        continue;
      } else if (n < 0 && errno == EPIPE) {
        return WriteStatus::closed;
      } else {
        error_ = path_ + ": cannot write: " + std::strerror(errno);
        return WriteStatus::failed;
      }
    }
    return WriteStatus::ok;
  }

 private:
  std::string path_, tmp_;
  int fd_;
  PixelFormat format_;
  std::vector<std::byte> bytes_;
};

}  // namespace

#if HOULE_WITH_OIIO
namespace {
// Float formats get the linear framebuffer; only TIFF holds either, and is 8-bit unless asked.
Expected<ImageStorage> image_storage(const std::string& pattern, const std::string& first, bool float32) {
  std::string ext = std::filesystem::path(first).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  const bool float_only = ext == ".exr" || ext == ".hdr" || ext == ".pfm";
  if (float32 && !float_only && ext != ".tif" && ext != ".tiff") {
    return Error{pattern, "32-bit float images need .exr, .hdr, .pfm, .tif or .tiff"};
  }
  return float32 ? linear_float : ext == ".exr" ? linear_half : float_only ? linear_float : srgb8;
}
}  // namespace
#endif

Expected<void> check_image_output(const std::string& pattern, bool float32) {
#if HOULE_WITH_OIIO
  Expected<std::string> first = format_frame_name(pattern, 0);
  if (!first) return first.error();
  Expected<const ImageModule*> module = image_module();
  if (!module) return module.error();
  char message[512] = "";
  if (module.value()->can_write(first.value().c_str(), message, sizeof message) != 0) {
    return Error{pattern, "no image format for this file name (" + std::string(message) + ")"};
  }
  if (Expected<ImageStorage> storage = image_storage(pattern, first.value(), float32); !storage) return storage.error();
  if (auto problem = folder_problem(std::filesystem::path(first.value()).parent_path(), true)) return Error{pattern, *problem};
  return {};
#else
  (void)float32;
  return Error{pattern, "this houle was built without OpenImageIO: use --raw"};
#endif
}

Expected<void> check_raw_output(const std::string& path) {
  if (path == "-") return {};
  std::optional<std::string> problem = folder_problem(std::filesystem::path(path).parent_path(), false);
  std::error_code ec;
  if (!problem && std::filesystem::exists(path, ec) && ::access(path.c_str(), W_OK) != 0) {
    problem = std::string("not writable (") + std::strerror(errno) + ")";
  }
  if (problem) return Error{path, "cannot open for writing: " + *problem};
  return {};
}

Expected<std::unique_ptr<FrameWriter>> make_image_writer(const std::string& pattern, int width, int height,
                                                         bool float32) {
  if (Expected<void> ok = check_image_output(pattern, float32); !ok) return ok.error();
#if HOULE_WITH_OIIO
  const std::string first = format_frame_name(pattern, 0).value();
  const ImageStorage storage = image_storage(pattern, first, float32).value();
  // The pattern's folder is made like the default frames/ (with its parents).
  const std::filesystem::path dir = std::filesystem::path(first).parent_path();
  std::error_code ec;
  if (!dir.empty() && !std::filesystem::create_directories(dir, ec) && !std::filesystem::is_directory(dir)) {
    return Error{pattern, "cannot make the folder " + dir.string() + (ec ? ": " + ec.message() : std::string())};
  }
  return std::unique_ptr<FrameWriter>(new ImageWriter(*image_module().value(), pattern, width, height, storage));
#else
  (void)width, (void)height, (void)float32;
  return Error{pattern, "this houle was built without OpenImageIO: use --raw"};
#endif
}

Expected<std::unique_ptr<FrameWriter>> make_raw_writer(const std::string& path, PixelFormat format, int width,
                                                       int height, bool whole) {
  // A reader that goes away must show up as EPIPE from write(), not as a fatal signal.
  std::signal(SIGPIPE, SIG_IGN);
  int fd = 1;
  const std::string tmp = whole && path != "-" ? temp_path(path) : std::string();
  if (path != "-") {
    fd = ::open((tmp.empty() ? path : tmp).c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return Error{path, std::string("cannot open for writing: ") + std::strerror(errno)};
  }
  const std::size_t bytes = bytes_per_pixel(format) * std::size_t(width) * std::size_t(height);
  return std::unique_ptr<FrameWriter>(new RawWriter(path, tmp, fd, format, bytes));
}

}  // namespace houle::cli
