#include "frame_writer.hpp"

#include <array>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fcntl.h>
#include <unistd.h>
#include <utility>

#include "cli.hpp"

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
// The camera in OpenEXR's conventions (row vectors, p' = p M): camera space has x right, y up and z
// forward (left-handed, objects in front at z > 0); NDC has (0, 0) at the image's top-left corner and
// (1, 1) at its bottom-right, after the division by w (here the camera-space z).
std::array<double, 16> world_to_camera(const Camera& c) {
  const std::array<float, 3>* axes[3] = {&c.right, &c.up, &c.forward};
  std::array<double, 16> m{};
  for (int j = 0; j < 3; ++j) {
    double dot = 0.0;
    for (int i = 0; i < 3; ++i) {
      m[std::size_t(4 * i + j)] = double((*axes[j])[std::size_t(i)]);
      dot += double((*axes[j])[std::size_t(i)]) * double(c.position[std::size_t(i)]);
    }
    m[std::size_t(12 + j)] = -dot;
  }
  m[15] = 1.0;
  return m;
}

// A pixel's image-plane point at unit distance is forward + a right + b up with a, b in pixel_scale
// units from the centre (camera.hpp), so x_ndc = 0.5 + x / (z pixel_scale width) and y_ndc = 0.5 - y /
// (z pixel_scale height); the third column keeps 1 / z, so the matrix is invertible.
std::array<double, 16> world_to_ndc(const Camera& c) {
  const double sx = 1.0 / (double(c.pixel_scale) * double(c.width)), sy = -1.0 / (double(c.pixel_scale) * double(c.height));
  const std::array<double, 16> projection{sx, 0.0, 0.0, 0.0, 0.0, sy, 0.0, 0.0, 0.5, 0.5, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0};
  const std::array<double, 16> view = world_to_camera(c);
  std::array<double, 16> m{};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      for (int k = 0; k < 4; ++k) m[std::size_t(4 * i + j)] += view[std::size_t(4 * i + k)] * projection[std::size_t(4 * k + j)];
    }
  }
  return m;
}

ImageAttribute matrix_attribute(const char* name, const std::array<double, 16>& m) {
  ImageAttribute a{.name = name, .type = ImageAttribute::matrix44};
  for (std::size_t i = 0; i < 16; ++i) a.floats[i] = float(m[i]);
  return a;
}

class ImageWriter final : public FrameWriter {
 public:
  ImageWriter(const ImageModule& module, std::string pattern, int w, int h, ImageStorage storage, const ImageHeader& header)
      : module_(module), pattern_(std::move(pattern)), w_(w), h_(h), fps_(header.fps) {
    const FrameAovs& a = header.aovs;
    names_ = {"R", "G", "B"};
    if (a.alpha) names_.push_back("A");
    if (a.depth) names_.push_back("Z");
    if (a.normal) names_.insert(names_.end(), {"N.X", "N.Y", "N.Z"});
    if (a.sea) names_.push_back("sea");
    for (const char* n : names_) storage_.push_back(std::string_view(n) == "Z" ? linear_float : storage);
    if (storage == srgb8) bytes_.resize(std::size_t(w) * std::size_t(h) * 3);
    if (names_.size() > 3) floats_.resize(std::size_t(w) * std::size_t(h) * names_.size());
    const auto [num, den] = frame_rate_ratio(header.fps);
    attributes_ = {{.name = "houle:frame", .type = ImageAttribute::integer},
                   {.name = "houle:time", .type = ImageAttribute::real},
                   {.name = "framesPerSecond", .type = ImageAttribute::rational, .ints = {num, den}},
                   {.name = "Software", .type = ImageAttribute::text, .string = software},
                   matrix_attribute("worldToCamera", world_to_camera(header.camera)),
                   matrix_attribute("worldToNDC", world_to_ndc(header.camera))};
  }

  WriteStatus write(const Framebuffer& fb, const ToneMap& tm, long index) override {
    const std::string name = format_frame_name(pattern_, index).value();
    const std::string tmp = temp_path(name);
    const void* data = fb.rgb.data();
    if (!bytes_.empty()) {
      encode_frame(fb, tm, PixelFormat::rgb24, std::as_writable_bytes(std::span(bytes_)));
      data = bytes_.data();
    } else if (!floats_.empty()) {
      interleave(fb);
      data = floats_.data();
    }
    attributes_[0].ints[0] = int(index);
    attributes_[1].number = double(index) / fps_;
    const ImageLayout layout{w_, h_, int(names_.size()), names_.data(), storage_.data()};
    char message[512] = "";
    // The final name picks the format.
    const bool ok = module_.write_image(tmp.c_str(), name.c_str(), &layout, data, attributes_.data(), int(attributes_.size()),
                                        message, sizeof message) == 0;
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
  // The colour and the AOVs, pixel by pixel in the order of names_.
  void interleave(const Framebuffer& fb) {
    const std::size_t c = names_.size(), n = std::size_t(w_) * std::size_t(h_);
    for (std::size_t i = 0; i < n; ++i) {
      float* p = &floats_[i * c];
      *p++ = fb.rgb[3 * i], *p++ = fb.rgb[3 * i + 1], *p++ = fb.rgb[3 * i + 2];
      if (!fb.alpha.empty()) *p++ = fb.alpha[i];
      if (!fb.depth.empty()) *p++ = fb.depth[i];
      if (!fb.normal.empty()) *p++ = fb.normal[3 * i], *p++ = fb.normal[3 * i + 1], *p++ = fb.normal[3 * i + 2];
      if (!fb.sea.empty()) *p++ = fb.sea[i];
    }
  }

  static constexpr const char* software = "houle " HOULE_VERSION;
  const ImageModule& module_;
  std::string pattern_;
  int w_, h_;
  double fps_;
  std::vector<const char*> names_;
  std::vector<int> storage_;
  std::vector<std::uint8_t> bytes_;  // sRGB codes, for 8-bit formats
  std::vector<float> floats_;        // colour and AOVs interleaved, when there are AOVs
  std::vector<ImageAttribute> attributes_;
};
#endif

// Frames into a file descriptor: raw pixels, or a YUV4MPEG2 stream (a header line first, then
// "FRAME\n" and the planes per frame).
class RawWriter final : public FrameWriter {
 public:
  // `tmp`: where the frames go until finish() renames it to `path` (empty: straight to `path`).
  RawWriter(std::string path, std::string tmp, int fd, PixelFormat f, std::size_t frame_bytes)
      : path_(std::move(path)), tmp_(std::move(tmp)), fd_(fd), format_(f), bytes_(frame_bytes) {}
  RawWriter(std::string path, std::string tmp, int fd, int w, int h, double fps, Y4mChroma chroma)
      : path_(std::move(path)), tmp_(std::move(tmp)), fd_(fd), format_(PixelFormat::rgb24), chroma_(chroma),
        header_(y4m_header(w, h, fps, chroma)), w_(w), h_(h), rgb_(std::size_t(w) * std::size_t(h) * 3),
        bytes_(frame_prefix.size() + y4m_frame_bytes(w, h, chroma)) {
    std::memcpy(bytes_.data(), frame_prefix.data(), frame_prefix.size());
  }
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
    if (!chroma_) {
      encode_frame(fb, tm, format_, std::span(bytes_));
    } else {
      encode_frame(fb, tm, PixelFormat::rgb24, std::span(rgb_));
      y4m_from_rgb24(rgb_, w_, h_, *chroma_, std::span(bytes_).subspan(frame_prefix.size()));
      if (!header_.empty()) {
        if (const WriteStatus st = write_all(std::as_bytes(std::span(header_))); st != WriteStatus::ok) return st;
        header_.clear();
      }
    }
    return write_all(bytes_);
  }

 private:
  static constexpr std::string_view frame_prefix = "FRAME\n";

  WriteStatus write_all(std::span<const std::byte> data) {
    std::size_t done = 0;
    while (done < data.size()) {
      const ssize_t n = ::write(fd_, data.data() + done, data.size() - done);
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

  std::string path_, tmp_;
  int fd_;
  PixelFormat format_;
  std::optional<Y4mChroma> chroma_;  // a y4m stream
  std::string header_;                // y4m: the stream header, until the first frame is written
  int w_ = 0, h_ = 0;
  std::vector<std::byte> rgb_;        // y4m: the frame's rgb24 codes
  std::vector<std::byte> bytes_;      // one frame as written
};

// The file descriptor frames go to: standard output for "-", else `path` or, when `whole`, its
// temporary name (`tmp`, set here).
Expected<int> open_frame_stream(const std::string& path, bool whole, std::string& tmp) {
  // A reader that goes away must show up as EPIPE from write(), not as a fatal signal.
  std::signal(SIGPIPE, SIG_IGN);
  tmp = whole && path != "-" ? temp_path(path) : std::string();
  if (path == "-") return 1;
  const int fd = ::open((tmp.empty() ? path : tmp).c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return Error{path, std::string("cannot open for writing: ") + std::strerror(errno)};
  return fd;
}

}  // namespace

#if HOULE_WITH_OIIO
namespace {
// Float formats get the linear framebuffer; only TIFF holds either, and is 8-bit unless asked.
Expected<ImageStorage> image_storage(const std::string& pattern, const std::string& first, bool float32) {
  std::string ext = std::filesystem::path(first).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  const bool float_only = ext == ".exr" || ext == ".hdr";
  if (float32 && !float_only && ext != ".tif" && ext != ".tiff") {
    return Error{pattern, "32-bit float images need .exr, .hdr, .tif or .tiff"};
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
                                                         bool float32, const ImageHeader& header) {
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
  return std::unique_ptr<FrameWriter>(new ImageWriter(*image_module().value(), pattern, width, height, storage, header));
#else
  (void)width, (void)height, (void)float32, (void)header;
  return Error{pattern, "this houle was built without OpenImageIO: use --raw"};
#endif
}

Expected<std::unique_ptr<FrameWriter>> make_raw_writer(const std::string& path, PixelFormat format, int width,
                                                       int height, bool whole) {
  std::string tmp;
  const Expected<int> fd = open_frame_stream(path, whole, tmp);
  if (!fd) return fd.error();
  const std::size_t bytes = bytes_per_pixel(format) * std::size_t(width) * std::size_t(height);
  return std::unique_ptr<FrameWriter>(new RawWriter(path, tmp, fd.value(), format, bytes));
}

Expected<std::unique_ptr<FrameWriter>> make_y4m_writer(const std::string& path, int width, int height, double fps,
                                                       Y4mChroma chroma, bool whole) {
  std::string tmp;
  const Expected<int> fd = open_frame_stream(path, whole, tmp);
  if (!fd) return fd.error();
  return std::unique_ptr<FrameWriter>(new RawWriter(path, tmp, fd.value(), width, height, fps, chroma));
}

}  // namespace houle::cli
