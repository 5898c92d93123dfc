#include "frame_writer.hpp"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fcntl.h>
#include <unistd.h>

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
    ++conversions;
    conversion_end = j;
    i = j;
  }
  if (conversions != 1) {
    return Error{pattern, "the output pattern needs exactly one frame-number conversion like %04d, found " +
                              std::to_string(conversions)};
  }
  const std::string pat = pattern.substr(0, conversion_end) + "l" + pattern.substr(conversion_end);  // %04d -> %04ld
  std::vector<char> buf(pattern.size() + 32);
  std::snprintf(buf.data(), buf.size(), pat.c_str(), index);
  return std::string(buf.data());
}

namespace {

// Why frames cannot be created in `dir` (the current folder if empty), or nothing. A missing folder
// is fine where `missing_ok` (created later): then its parent must take it.
std::optional<std::string> folder_problem(std::filesystem::path dir, bool missing_ok) {
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) {
    if (!missing_ok) return "the folder " + dir.string() + " does not exist";
    dir = dir.parent_path().empty() ? std::filesystem::path(".") : dir.parent_path();
  }
  if (!std::filesystem::is_directory(dir, ec)) return dir.string() + " is not a folder";
  if (::access(dir.c_str(), W_OK | X_OK) != 0) return "the folder " + dir.string() + " is not writable (" + std::strerror(errno) + ")";
  return std::nullopt;
}

#if HOULE_WITH_OIIO
class ImageWriter final : public FrameWriter {
 public:
  ImageWriter(const ImageModule& module, std::string pattern, int w, int h, bool linear)
      : module_(module), pattern_(std::move(pattern)), w_(w), h_(h), linear_(linear), pixels_(std::size_t(w) * h * 3) {}

  WriteStatus write(const Framebuffer& fb, const ToneMap& tm, long index) override {
    const std::string name = format_frame_name(pattern_, index).value();
    const std::string tmp = name + ".tmp" + std::to_string(::getpid());
    if (!linear_) encode_frame(fb, tm, PixelFormat::rgb24, std::as_writable_bytes(std::span(pixels_)));
    const void* data = linear_ ? static_cast<const void*>(fb.rgb.data()) : pixels_.data();
    char message[512] = "";
    // The final name picks the format.
    const bool ok = module_.write_rgb(tmp.c_str(), name.c_str(), w_, h_, linear_, data, message, sizeof message) == 0;
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
  bool linear_;
  std::vector<std::uint8_t> pixels_;
};
#endif

class RawWriter final : public FrameWriter {
 public:
  RawWriter(std::string path, int fd, PixelFormat f, std::size_t frame_bytes)
      : path_(std::move(path)), fd_(fd), format_(f), bytes_(frame_bytes) {}
  ~RawWriter() override {
    if (fd_ > 1) ::close(fd_);
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
  std::string path_;
  int fd_;
  PixelFormat format_;
  std::vector<std::byte> bytes_;
};

}  // namespace

std::optional<Error> check_image_output(const std::string& pattern, bool folder_created) {
#if HOULE_WITH_OIIO
  Expected<std::string> first = format_frame_name(pattern, 0);
  if (!first) return first.error();
  Expected<const ImageModule*> module = image_module();
  if (!module) return module.error();
  char message[512] = "";
  if (module.value()->can_write(first.value().c_str(), message, sizeof message) != 0) {
    return Error{pattern, "no image format for this file name (" + std::string(message) + ")"};
  }
  if (auto problem = folder_problem(std::filesystem::path(first.value()).parent_path(), folder_created)) {
    return Error{pattern, *problem};
  }
  return std::nullopt;
#else
  (void)folder_created;
  return Error{pattern, "this houle was built without OpenImageIO: use --raw"};
#endif
}

std::optional<Error> check_raw_output(const std::string& path) {
  if (path == "-") return std::nullopt;
  std::optional<std::string> problem = folder_problem(std::filesystem::path(path).parent_path(), false);
  std::error_code ec;
  if (!problem && std::filesystem::exists(path, ec) && ::access(path.c_str(), W_OK) != 0) {
    problem = std::string("not writable (") + std::strerror(errno) + ")";
  }
  if (problem) return Error{path, "cannot open for writing: " + *problem};
  return std::nullopt;
}

Expected<std::unique_ptr<FrameWriter>> make_image_writer(const std::string& pattern, int width, int height) {
  if (std::optional<Error> e = check_image_output(pattern, false)) return *e;
#if HOULE_WITH_OIIO
  const std::string ext = std::filesystem::path(format_frame_name(pattern, 0).value()).extension().string();
  const bool linear = ext == ".exr" || ext == ".EXR";
  return std::unique_ptr<FrameWriter>(new ImageWriter(*image_module().value(), pattern, width, height, linear));
#else
  (void)width, (void)height;
  return Error{pattern, "this houle was built without OpenImageIO: use --raw"};
#endif
}

Expected<std::unique_ptr<FrameWriter>> make_raw_writer(const std::string& path, PixelFormat format, int width,
                                                       int height) {
  // A reader that goes away must show up as EPIPE from write(), not as a fatal signal.
  std::signal(SIGPIPE, SIG_IGN);
  int fd = 1;
  if (path != "-") {
    fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return Error{path, std::string("cannot open for writing: ") + std::strerror(errno)};
  }
  const std::size_t bytes = bytes_per_pixel(format) * std::size_t(width) * std::size_t(height);
  return std::unique_ptr<FrameWriter>(new RawWriter(path, fd, format, bytes));
}

}  // namespace houle::cli
